#pragma once
// Synthetic terrains: the environments of 001_... V.A (hills and valleys, narrow corridors,
// obstacles, dead ends) and the simple ones the experiments need (flat, ramp, a single hill
// for 004_... fig. 6, and forest: many small lethal clusters for TAEASL, 002_...).
//
// Deterministic: the same options give the same map, bit for bit, on any platform (the random
// numbers come from std::mt19937_64 and are mapped to reals by terratraj's own code, not by the
// implementation-defined std:: distributions).
//
// Every obstacle kind keeps two disks of radius 3 m clear of lethal cells, around the standard
// start (10 % of the width from the west edge, mid-height) and goal (10 % from the east edge):
// see standardStartGoal().

#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::terrain {

/// The generator kinds, named in YAML and on the command line as listed by terrainKindNames().
enum class TerrainKind { kFlat, kRamp, kHill, kHills, kCorridor, kObstacles, kDeadEnd, kForest };

/// Parses a kind name ("flat", "ramp", "hill", "hills", "corridor", "obstacles", "dead_end",
/// "forest").
std::optional<TerrainKind> parseTerrainKind(std::string_view name);
/// The name of a kind, as parseTerrainKind() accepts it.
const char* terrainKindName(TerrainKind kind);
/// Every kind's name, in declaration order.
std::vector<std::string> terrainKindNames();
/// One line describing what a kind generates (for --help).
const char* terrainKindDescription(TerrainKind kind);

/// What to generate.
struct GeneratorOptions {
  TerrainKind kind = TerrainKind::kHills;
  int rows = 256;      ///< cells along y, >= 2
  int cols = 256;      ///< cells along x, >= 2
  double cell = 0.25;  ///< cell size [m], > 0
  std::uint64_t seed = 1;
};

/// Largest grid generateTerrain() accepts, in cells (2^28).
inline constexpr std::int64_t kMaxGeneratedCells = std::int64_t{1} << 28;

/// Generates a terrain: heights in "elevation", and for corridor, obstacles, dead_end and forest
/// a "lethal" layer (1 = lethal). Throws InputError for rows or cols < 2, more than
/// kMaxGeneratedCells cells, or a cell size that is not a positive finite number.
ElevationMap generateTerrain(const GeneratorOptions& options);

/// The standard start and goal of generated maps (local frame, metres): 10 % of the width from
/// the west and east edges, at mid-height. Generators keep 3 m around both free of obstacles.
std::pair<Eigen::Vector2d, Eigen::Vector2d> standardStartGoal(const GridGeometry& geometry);

}  // namespace terratraj::terrain
