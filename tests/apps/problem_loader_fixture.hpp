#pragma once
// Shared by the problem-loader tests (problem_loader_test.cpp, problem_loader_errors_test.cpp):
// the contract's example, the smallest problem, and parse helpers.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>

#include "terratraj/apps/problem_loader.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps::loader_test {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::StartsWith;

inline constexpr double kTol = 1e-12;
inline constexpr double kDeg = 3.14159265358979323846 / 180.0;

// The example of the contract (shared/spec/interface.md), verbatim.
inline const char* const kContractExample = R"(terrain:
  file: data/dem.tif          # any raster GDAL reads
                              # relative paths are relative to this YAML file
  # generate: {kind: hills, rows: 256, cols: 256, cell: 0.25, seed: 1}
  cell: 0.25                  # optional
  z_scale: 1.0                # optional: multiplies heights
  frame: local                # local | world
  obstacles:                  # optional lethal layer
    file: data/lethal.tif     # non-zero = lethal
    max_slope_deg: 35         # and/or: cells steeper than this are lethal
vehicle:
  model: rocker_bogie         # point | four_wheel | rocker_bogie | segway_rmp
  limits: {v_max: 1.0, a_max: 0.5, omega_max: 1.0, kappa_max: 1.0, sigma_max: 0.5, pitch_max_deg: 17, roll_max_deg: 20}
  tables:                     # optional kinodynamic look-up tables (JSON, format below)
    pitch: tables/pitch_vmax.json
    roll_curvature: tables/roll_curvature_vmax.json
start: {x: 2.0, y: 3.0, heading_deg: 0, v: 0.0, omega: 0.0}
goal:  {x: 6.0, y: 3.0, heading_deg: 0, v: 0.0, omega: 0.0}
cost: {kind: time, alpha: 0.0}            # time | slope_dwell
solver:
  method: newton              # newton | newton_fd | ipopt | ceres | shooting | collocation
  intervals: 40               # for shooting / collocation
  max_iterations: 100
  tolerance: {position_m: 0.001, heading_rad: 0.001}
planner:
  kind: prm                   # prm | lattice | taeasl
  time_limit_s: 1.0
  seed: 1
  homotopy_classes: 3         # taeasl: how many distinct classes to return at most
  frame_radius_m: 10.0        # taeasl
)";

// The smallest valid problem: a generated terrain, a start and a goal.
inline const char* const kMinimal = R"(terrain:
  generate: {kind: hills}
start: {x: 2.0, y: 3.0, heading_deg: 0}
goal: {x: 6.0, y: 3.0, heading_deg: 90}
)";

inline ProblemSpec parse(const std::string& yaml, const fs::path& base_dir = "/proj") {
  return parseProblem(yaml, base_dir, "problem.yaml");
}

// The message of the InputError that parsing `yaml` throws ("" and a test failure if none).
inline std::string parseError(const std::string& yaml) {
  try {
    parse(yaml);
  } catch (const InputError& error) {
    return error.what();
  } catch (const std::exception& error) {
    ADD_FAILURE() << "unexpected exception type: " << error.what();
    return "";
  }
  ADD_FAILURE() << "no InputError for:\n" << yaml;
  return "";
}

// kMinimal with one more section (or a replaced one, when the key is terrain/start/goal).
inline std::string minimalWith(const std::string& extra) { return std::string(kMinimal) + extra; }

// A problem with `start` replaced.
inline std::string withStart(const std::string& start) {
  return "terrain: {generate: {kind: flat}}\nstart: " + start +
         "\ngoal: {x: 6.0, y: 3.0, heading_deg: 0}\n";
}

// A problem with `terrain` replaced.
inline std::string withTerrain(const std::string& terrain) {
  return "terrain: " + terrain +
         "\nstart: {x: 2.0, y: 3.0, heading_deg: 0}\ngoal: {x: 6.0, y: 3.0, heading_deg: 0}\n";
}

}  // namespace terratraj::apps::loader_test
