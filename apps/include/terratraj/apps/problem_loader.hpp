#pragma once
// Reading and validating problem files (docs/problem-file.md).
//
// The loader is strict: every key is checked, and an unknown key, a value of the wrong type, a
// missing required key or an out-of-range value throws terratraj::InputError with a message of
// the form
//   <file>:<line>:<column>: <key.path>: <what is wrong>
// e.g. "problem.yaml:7:13: vehicle.limits.v_max: must be > 0 (got -1)". No other exception
// escapes (std::bad_alloc aside). The terrain itself is not loaded here: see
// terrain::loadTerrain() and resolvePosesOnTerrain().

#include <filesystem>
#include <string>

#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::apps {

/// Reads and validates a problem file. Relative paths inside it are resolved against the
/// file's folder. Throws InputError naming the file when it is missing, unreadable, not valid
/// YAML, or breaks any rule of docs/problem-file.md.
ProblemSpec loadProblem(const std::filesystem::path& yaml_file);

/// Parses problem YAML held in a string. Relative paths are resolved against `base_dir`;
/// `display_name` starts every error message and becomes ProblemSpec::source_file. Throws
/// InputError as loadProblem() does.
ProblemSpec parseProblem(const std::string& yaml_text, const std::filesystem::path& base_dir,
                         const std::string& display_name);

/// Start and goal in the local map frame [m, rad, m/s, rad/s].
struct ResolvedPoses {
  BoundaryState start;
  BoundaryState goal;
};

/// Puts start and goal on the loaded terrain: converts them from world to local coordinates
/// when problem.pose_frame is world, then checks that each lies inside the map's extent and on
/// a cell that is neither no-data nor lethal. Throws InputError naming the file and the pose at
/// fault. `problem` is not changed (ProblemScene holds the resolved poses).
ResolvedPoses resolvePoses(const ProblemSpec& problem, const terrain::ElevationMap& map);

}  // namespace terratraj::apps
