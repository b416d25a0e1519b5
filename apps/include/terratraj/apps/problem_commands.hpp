#pragma once
// `terratraj check`: read and validate a problem file and its terrain.

#include <filesystem>

#include <nlohmann/json.hpp>

#include "terratraj/apps/command_context.hpp"
#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/models/terrain_following_model.hpp"

namespace terratraj::apps {

class ProblemScene;

/// Options of `terratraj check`.
struct CheckOptions {
  std::filesystem::path problem;
};

/// The JSON form of a problem as understood (radians, metres, local frame, resolved paths).
nlohmann::json problemJson(const ProblemSpec& problem, const ProblemScene& scene);

/// The vehicle's attitude resting at a boundary state (`which` = "start" / "goal" names it in
/// messages). Throws InputError naming the problem file when it cannot rest there.
models::AttitudeResult restingAttitude(const models::TerrainFollowingModel& model,
                                       const BoundaryState& state, const char* which,
                                       const ProblemSpec& problem);

class ProblemScene;

/// The checks `solve`, `plan` and `refine` apply to a loaded problem before their work, beyond
/// the scene's own (terrain, tables, start and goal poses and attitudes): the transcription
/// settings (solve with shooting / collocation), the planning problem (plan, refine), the
/// lattice goal region (plan with a lattice planner), the refinement settings (refine). Throws
/// InputError naming the key and the commands that refuse it.
void checkForEveryCommand(const ProblemSpec& problem, const ProblemScene& scene);

/// Loads the problem and its terrain and applies exactly the checks of `solve`, `plan` and
/// `refine` (ProblemScene, checkForEveryCommand). Throws InputError naming the file / key /
/// value at fault.
int runCheck(const CheckOptions& options, CommandContext& context);

}  // namespace terratraj::apps
