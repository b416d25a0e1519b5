#pragma once
// The motion-primitive file (JSON): a PrimitiveSet with its lattice, generation settings and
// every primitive's sampled poses, times and curvatures. docs/planning.md gives the format.
//
// {"format": "terratraj-primitives", "version": 1,
//  "lattice": {"resolution_m": 0.5, "heading_count": 16}, "sample_spacing_m": 0.05,
//  "generation": {"speed": 1.0, "kappa_max": 1.0, "sigma_max": 0.5, "omega_max": 1.0,
//                 "turns": [-2, -1, 1, 2], "solves": 30, "failures": 0, "time_ms": 210.0},
//  "primitives": [{"start_heading": 0, "end_heading": 1, "offset": [4, 1], "length_m": 2.1,
//                  "duration_s": 2.1, "t": [...], "s": [...], "x": [...], "y": [...],
//                  "heading": [...], "curvature": [...]}, ...]}

#include <filesystem>
#include <string>

#include "terratraj/search/motion_primitive.hpp"
#include "terratraj/search/primitive_generator.hpp"

namespace terratraj::search {

/// Writes `set` to `path`. Throws InputError naming the file when it cannot be written.
void writePrimitiveFile(const PrimitiveSet& set, const std::filesystem::path& path);

/// Reads a primitive file. Throws InputError naming the file and the key at fault (missing
/// file, malformed JSON, wrong format or version, missing or non-numeric fields, sample arrays
/// of different lengths). Consistency with a lattice is checked separately
/// (PrimitiveSet::checkAgainst).
PrimitiveSet readPrimitiveFile(const std::filesystem::path& path);

/// The cache file name for a lattice, vehicle limits and generation options: a hash of every
/// value generation depends on ("primitives-<hex>.json").
std::string primitiveCacheName(const LatticeSpec& lattice, const models::VehicleLimits& limits,
                               const PrimitiveGenerationOptions& options);

/// Where a set came from.
enum class PrimitiveSource {
  kFile,       ///< read from the file asked for
  kCache,      ///< read from the cache
  kGenerated,  ///< generated (and written to the cache when one is available)
};

/// "file", "cache", "generated".
const char* primitiveSourceName(PrimitiveSource source);

/// A set ready for a lattice, and where it came from.
struct LoadedPrimitives {
  PrimitiveSet set;
  PrimitiveSource source = PrimitiveSource::kGenerated;
  std::filesystem::path path;  ///< the file read or written ("" when generated and not cached)
  std::string cache_note;      ///< why the cache was not used or written ("" if it was)
};

/// The primitives for `lattice` and `limits`: from `file` when given (it must exist and match
/// the lattice and limits: InputError otherwise, naming the file and what differs), else from
/// the cache in `cache_dir` when a matching entry exists (primitiveCacheName), else generated
/// and written there. An empty `cache_dir` means no cache (the caller chooses the directory:
/// the CLI's is apps::primitiveCacheDirectory). Throws InputError when generation leaves a
/// heading without primitives.
LoadedPrimitives loadOrGeneratePrimitives(const LatticeSpec& lattice,
                                          const models::VehicleLimits& limits,
                                          const PrimitiveGenerationOptions& options,
                                          const std::filesystem::path& file = {},
                                          const std::filesystem::path& cache_dir = {});

}  // namespace terratraj::search
