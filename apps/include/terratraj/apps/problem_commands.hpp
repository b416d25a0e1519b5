#pragma once
// `terratraj check`: read and validate a problem file and its terrain.

#include <filesystem>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::apps {

/// Options of `terratraj check`.
struct CheckOptions {
  std::filesystem::path problem;
};

/// The JSON form of a problem as understood (radians, metres, local frame, resolved paths).
nlohmann::json problemJson(const ProblemSpec& problem);

/// The vehicle's attitude resting at a boundary state (`which` = "start" / "goal" names it in
/// messages). Throws InputError naming the problem file when it cannot rest there.
models::AttitudeResult restingAttitude(const models::TerrainFollowingModel& model,
                                       const BoundaryState& state, const char* which,
                                       const ProblemSpec& problem);

/// Loads the problem and its terrain and checks the start and goal against it. Throws
/// InputError naming the file / key / value at fault.
int runCheck(const CheckOptions& options, CommandContext& context);

}  // namespace terratraj::apps
