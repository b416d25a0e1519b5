#include "end_state_check.hpp"

#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "terratraj/models/trajectory_checker.hpp"

namespace terratraj::refine::detail {
namespace {

constexpr double kDegreesPerRadian = 180.0 / 3.14159265358979323846;
/// Beyond the verdict's slack: the ends within the solver's tolerance move the bound a little.
constexpr double kEndMargin = 0.01;

models::GoalReachability unreachable(std::string reason) {
  models::GoalReachability out;
  out.reachable = false;
  out.reason = std::move(reason);
  return out;
}

}  // namespace

std::optional<models::GoalReachability> checkEndStates(const models::TerrainFollowingModel& vehicle,
                                                       const ocp::BoundaryValueProblem& problem) {
  const std::pair<const char*, const ocp::VehicleState*> ends[] = {{"start", &problem.start},
                                                                   {"goal", &problem.goal}};
  const models::CheckTolerances verdict;
  for (const auto& [name, state] : ends) {
    models::AttitudeWorkspace workspace;
    models::AttitudeResult attitude;
    if (vehicle.compute({state->x, state->y, state->heading}, workspace, attitude) !=
        models::AttitudeStatus::kOk) {
      continue;  // the problem's validation names a pose the vehicle cannot rest at
    }
    const double slope = attitude.attitude.pitch;
    std::ostringstream why;
    why.precision(3);
    const models::SegwayLookups* segway = problem.tables.segway;
    if (segway != nullptr && !(segway->bounds.speedLimit(slope) > 0.0 &&
                               segway->bounds.accelerationLimit(slope) > 0.0)) {
      why << "the goal cannot be reached: at the " << name << " the Segway stands on a slope of "
          << slope * kDegreesPerRadian
          << " deg along its heading, where its look-ups allow no speed or "
          << "acceleration (they allow slopes under "
          << segway->bounds.drivableSlope() * kDegreesPerRadian << " deg)";
      return unreachable(why.str());
    }
    const double speed = std::abs(state->v);
    if (!(speed > 0.0)) continue;
    const double curvature = state->omega / state->v;
    const double cap = problem.tables.speedCap(attitude.attitude, curvature, problem.limits.v_max);
    if (speed <= (1.0 + kEndMargin) * cap + verdict.relative * cap + verdict.absolute) continue;
    why << "the goal cannot be reached: at the " << name << " the vehicle moves at " << speed
        << " m/s on a slope of " << slope * kDegreesPerRadian << " deg along its heading (roll "
        << attitude.attitude.roll * kDegreesPerRadian << " deg, curvature " << curvature
        << " 1/m), where its " << (segway != nullptr ? "look-ups" : "speed tables")
        << " allow at most " << cap << " m/s";
    return unreachable(why.str());
  }
  return std::nullopt;
}

}  // namespace terratraj::refine::detail
