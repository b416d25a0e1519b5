#pragma once
// The OMPL side of the OMPL peers (internal to bench/src/ompl_peer.cpp): the compound state
// (SE2, speed and curvature, time), the extension integrator as OMPL's state propagator and
// validity checker, the control samplers, the goal region that records every improvement, the
// time objective, and the re-integration of OMPL's solution path.

#include <ompl/base/Goal.h>
#include <ompl/base/OptimizationObjective.h>
#include <ompl/base/PlannerTerminationCondition.h>
#include <ompl/base/goals/GoalSampleableRegion.h>
#include <ompl/base/spaces/RealVectorStateSpace.h>
#include <ompl/base/spaces/SE2StateSpace.h>
#include <ompl/control/ControlSampler.h>
#include <ompl/control/DirectedControlSampler.h>
#include <ompl/control/PathControl.h>
#include <ompl/control/SpaceInformation.h>
#include <ompl/control/StatePropagator.h>
#include <ompl/control/planners/rrt/RRT.h>
#include <ompl/control/planners/sst/SST.h>
#include <ompl/control/spaces/RealVectorControlSpace.h>
#include <ompl/util/Console.h>
#include <ompl/util/RandomNumbers.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <memory>
#include <optional>

#include "terratraj/search/extension_integrator.hpp"
#include "terratraj/search/plan_result.hpp"

namespace terratraj::bench::detail {

namespace ob = ompl::base;
namespace oc = ompl::control;

constexpr double kStepS = 0.25;         // OMPL's propagation step [s]
constexpr unsigned kMaxSteps = 120;     // longest control: 30 s (approach loops included)
constexpr double kExtensionM = 8.0;     // as the PRM's extension_length_m
constexpr double kApproachLegM = 36.0;  // legs of an approach: as the PRM's goal connection
constexpr double kMaxTimeS = 1e6;       // bound of the time coordinate [s]

// The OMPL state: SE2 (x, y, heading), (v, curvature), and the time since the start (SST's
// cost; weight 0 in distances).
inline search::PlannerState plannerState(const ob::State* state) {
  const auto* c = state->as<ob::CompoundState>();
  const auto* se2 = c->as<ob::SE2StateSpace::StateType>(0);
  const auto* vk = c->as<ob::RealVectorStateSpace::StateType>(1);
  search::PlannerState s;
  s.position = {se2->getX(), se2->getY()};
  s.heading = se2->getYaw();
  s.v = vk->values[0];
  s.curvature = vk->values[1];
  return s;
}
inline double stateTime(const ob::State* state) {
  return state->as<ob::CompoundState>()->as<ob::RealVectorStateSpace::StateType>(2)->values[0];
}
inline void setState(ob::State* state, const search::PlannerState& s, double t) {
  auto* c = state->as<ob::CompoundState>();
  auto* se2 = c->as<ob::SE2StateSpace::StateType>(0);
  se2->setXY(s.position.x(), s.position.y());
  se2->setYaw(std::remainder(s.heading, 2.0 * M_PI));
  auto* vk = c->as<ob::RealVectorStateSpace::StateType>(1);
  vk->values[0] = s.v;
  vk->values[1] = s.curvature;
  c->as<ob::RealVectorStateSpace::StateType>(2)->values[0] = t;
}

constexpr int kControlDims = 5;        // target x, y [m], speed [m/s], heading [rad], approach [m]
constexpr double kMinApproachM = 0.5;  // shorter approaches steer straight at the target
constexpr double kMaxApproachM = 8.0;  // the PRM's goal approach: 1.5 .. 8 m behind the goal
constexpr double kSampledApproachMinM = 1.5;

// What a control asks: drive to (x, y) arriving at speed v; with an approach distance d, first
// to the point d behind it along `heading` (as the PRM's goal approach), so that the target is
// reached along that heading.
struct Steer {
  search::ExtensionRequest to_target;
  std::optional<search::ExtensionRequest> to_via;
};

inline Steer steerOf(const double* u, const search::PlannerState& from,
                     const models::VehicleLimits& limits) {
  Steer steer;
  steer.to_target.target = {u[0], u[1]};
  steer.to_target.target_speed = u[2];
  steer.to_target.turn_speed = std::max(u[2], 0.25);
  steer.to_target.max_length = kExtensionM;
  const double back = u[4];
  if (back < kMinApproachM) return steer;
  const Eigen::Vector2d via =
      steer.to_target.target - back * Eigen::Vector2d(std::cos(u[3]), std::sin(u[3]));
  (void)from;
  steer.to_target.max_length = kApproachLegM;
  search::ExtensionRequest to_via;
  to_via.target = via;
  to_via.target_speed = std::min(limits.v_max, std::sqrt(u[2] * u[2] + 2.0 * limits.a_max * back));
  to_via.turn_speed = to_via.target_speed;
  to_via.max_length = kApproachLegM;
  steer.to_via = to_via;
  return steer;
}

// Runs a control's extensions from `from` into `out` (one path, times from 0). False when
// either is trapped.
inline bool runSteer(search::ExtensionIntegrator& integrator, const search::PlannerState& from,
                     const Steer& steer, search::Extension& scratch, search::Extension& out) {
  if (!steer.to_via) {
    integrator.extend(from, steer.to_target, out);
    return search::extensionSucceeded(out.status);
  }
  integrator.extend(from, *steer.to_via, out);
  // Truncated before the via point: the approach is not reached; the motion ends there.
  if (out.status != search::ExtensionStatus::kReached) {
    return search::extensionSucceeded(out.status);
  }
  integrator.extend(out.end, steer.to_target, scratch);
  if (!search::extensionSucceeded(scratch.status)) return false;
  const double t0 = out.duration, s0 = out.length;
  for (std::size_t k = 1; k < scratch.points.size(); ++k) {
    search::PathPoint p = scratch.points[k];
    p.t += t0;
    p.s += s0;
    out.points.push_back(p);
  }
  out.end = scratch.end;
  out.duration += scratch.duration;
  out.length += scratch.length;
  out.status = scratch.status;
  return true;
}

// The state `elapsed` seconds into an extension (linear between its points; its end after it).
// The extension's path point at time t (t within the path). Between two points the speed
// changes at a constant rate (the profile's), so the arc length grows quadratically in time:
// the point is placed at that arc length (linear in s between the points), not linearly in t,
// which would put it ahead of where the speed can have taken it.
inline search::PathPoint pointAt(const search::Extension& e, double t) {
  const auto next = std::upper_bound(e.points.begin() + 1, e.points.end() - 1, t,
                                     [](double x, const search::PathPoint& p) { return x < p.t; });
  const search::PathPoint& b = *next;
  const search::PathPoint& a = *(next - 1);
  const double dt = b.t - a.t;
  const double tau = std::clamp(t - a.t, 0.0, std::max(dt, 0.0));
  const double acceleration = dt > 0.0 ? (b.v - a.v) / dt : 0.0;
  const double travelled = a.v * tau + 0.5 * acceleration * tau * tau;
  const double w = b.s > a.s ? std::clamp(travelled / (b.s - a.s), 0.0, 1.0) : 0.0;
  search::PathPoint p;
  p.position = a.position + w * (b.position - a.position);
  p.z = a.z + w * (b.z - a.z);
  p.heading = a.heading + w * std::remainder(b.heading - a.heading, 2.0 * M_PI);
  p.roll = a.roll + w * (b.roll - a.roll);
  p.pitch = a.pitch + w * (b.pitch - a.pitch);
  p.curvature = a.curvature + w * (b.curvature - a.curvature);
  p.s = a.s + w * (b.s - a.s);
  p.v = a.v + acceleration * tau;
  p.t = t;
  return p;
}

// The state `elapsed` seconds into an extension (its end after it).
inline search::PlannerState along(const search::Extension& e, double elapsed) {
  if (elapsed >= e.points.back().t || e.points.size() < 2) return e.end;
  const search::PathPoint p = pointAt(e, elapsed);
  search::PlannerState s;
  s.position = p.position;
  s.heading = p.heading;
  s.v = p.v;
  s.curvature = p.curvature;
  return s;
}

// An OMPL control is an extension request; applying it for k steps follows the one extension
// from the state where it was first applied (cached), exactly as the PRM's edges.
class ExtensionPropagator final : public oc::StatePropagator {
 public:
  ExtensionPropagator(const oc::SpaceInformationPtr& si, const search::PlanningProblem& problem)
      : oc::StatePropagator(si),
        limits_(problem.limits),
        integrator_(problem, search::IntegrationSettings{}) {}

  void propagate(const ob::State* state, const oc::Control* control, double duration,
                 ob::State* result) const override {
    const search::PlannerState from = plannerState(state);
    const double t0 = stateTime(state);
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    const bool continuing = cached_ && std::equal(u, u + kControlDims, control_) && t0 == last_t_ &&
                            from.position == last_.position && from.heading == last_.heading &&
                            from.v == last_.v && from.curvature == last_.curvature;
    if (!continuing) {
      std::copy(u, u + kControlDims, control_);
      ok_ = runSteer(integrator_, from, steerOf(u, from, limits_), scratch_, extension_);
      elapsed_ = 0.0;
      cached_ = true;
    }
    elapsed_ += duration;
    search::PlannerState next = ok_ ? along(extension_, elapsed_) : from;
    if (!ok_) next.position.x() = std::numeric_limits<double>::quiet_NaN();  // invalid
    setState(result, next, t0 + duration);
    last_ = plannerState(result);
    last_t_ = t0 + duration;
  }

  /// Runs the motion of `control` from `from` and keeps it as the cached motion, so that the
  /// propagation that follows from `from` continues along it instead of running it again.
  /// Returns its duration [s]; negative when it is trapped.
  double prime(const ob::State* from, const oc::Control* control) const {
    const search::PlannerState start = plannerState(from);
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    std::copy(u, u + kControlDims, control_);
    ok_ = runSteer(integrator_, start, steerOf(u, start, limits_), scratch_, extension_);
    elapsed_ = 0.0;
    cached_ = true;
    last_ = start;
    last_t_ = stateTime(from);
    return ok_ ? extension_.duration : -1.0;
  }

  /// The motion of `control` from `from` (for the re-integrated solution).
  bool motion(const search::PlannerState& from, const oc::Control* control,
              search::Extension& out) const {
    const double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    return runSteer(integrator_, from, steerOf(u, from, limits_), scratch_, out);
  }

 private:
  models::VehicleLimits limits_;
  mutable search::ExtensionIntegrator integrator_;
  mutable search::Extension extension_, scratch_;
  mutable double control_[kControlDims] = {};
  mutable bool cached_ = false, ok_ = false;
  mutable double elapsed_ = 0.0, last_t_ = 0.0;
  mutable search::PlannerState last_;
};

// Valid: finite, on the map, on a cell neither lethal nor no data, and an attitude within the
// pitch and roll limits. (Between the states the extension integrator checked the path.)
class TerrainValidityChecker final : public ob::StateValidityChecker {
 public:
  TerrainValidityChecker(const ob::SpaceInformationPtr& si, const search::PlanningProblem& problem)
      : ob::StateValidityChecker(si), problem_(problem) {}
  bool isValid(const ob::State* state) const override {
    const search::PlannerState s = plannerState(state);
    if (!std::isfinite(s.position.x()) || !std::isfinite(s.position.y())) return false;
    const terrain::ElevationMap& map = *problem_.map;
    const std::optional<terrain::CellIndex> cell = map.geometry().cellAt(s.position);
    if (!cell || map.isNoData(*cell) || map.isLethal(*cell)) return false;
    if (problem_.vehicle->compute({s.position.x(), s.position.y(), s.heading}, workspace_,
                                  attitude_) != models::AttitudeStatus::kOk) {
      return false;
    }
    return std::abs(attitude_.attitude.pitch) <= problem_.limits.pitch_max &&
           std::abs(attitude_.attitude.roll) <= problem_.limits.roll_max;
  }

 private:
  const search::PlanningProblem& problem_;
  mutable models::AttitudeWorkspace workspace_;
  mutable models::AttitudeResult attitude_;
};

// RRT's steering function: the control toward the sampled state is the extension request to
// its position and speed; it is applied for as long as the extension lasts.
class SteeringControlSampler final : public oc::DirectedControlSampler {
 public:
  /// `jitter` [rad]: the approach axis is within this of the target heading (the PRM uses 0.8
  /// of the goal's heading tolerance).
  SteeringControlSampler(const oc::SpaceInformation* si, const ExtensionPropagator& propagator,
                         double jitter)
      : oc::DirectedControlSampler(si), jitter_(jitter), propagator_(propagator) {}
  unsigned int sampleTo(oc::Control* control, const ob::State* source, ob::State* dest) override {
    const search::PlannerState target = plannerState(dest);
    double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    u[0] = target.position.x();
    u[1] = target.position.y();
    u[2] = target.v;
    // Arrive along the sampled heading (steering from state to state), through an approach
    // point at a random distance and angle behind it, as the PRM's goal connection.
    u[3] = target.heading + rng_.uniformReal(-jitter_, jitter_);
    u[4] = rng_.uniformReal(kSampledApproachMinM, kMaxApproachM);
    const double duration = propagator_.prime(source, control);
    if (duration <= 0.0) return 0;
    const unsigned steps =
        std::clamp<unsigned>(static_cast<unsigned>(std::ceil(duration / kStepS)), 1u, kMaxSteps);
    return si_->propagateWhileValid(source, control, static_cast<int>(steps), dest);
  }
  unsigned int sampleTo(oc::Control* control, const oc::Control* /*previous*/,
                        const ob::State* source, ob::State* dest) override {
    return sampleTo(control, source, dest);
  }

 private:
  double jitter_;
  const ExtensionPropagator& propagator_;
  ompl::RNG rng_;
};

// SST's random controls: a uniform extension request, or (5 %) the goal approached along its
// heading, as RRT's goal bias (SST itself has none).
class GoalBiasedControlSampler final : public oc::ControlSampler {
 public:
  GoalBiasedControlSampler(const oc::ControlSpace* space, const search::GoalRegion& goal)
      : oc::ControlSampler(space), goal_(goal) {}
  void sample(oc::Control* control) override {
    double* u = control->as<oc::RealVectorControlSpace::ControlType>()->values;
    const ob::RealVectorBounds& b = space_->as<oc::RealVectorControlSpace>()->getBounds();
    if (rng_.uniform01() < kGoalBias) {
      u[0] = goal_.position.x();
      u[1] = goal_.position.y();
      u[2] = goal_.v;
      const double jitter = 0.8 * goal_.heading_tolerance;
      u[3] = goal_.heading + rng_.uniformReal(-jitter, jitter);
      u[4] = rng_.uniformReal(kSampledApproachMinM, kMaxApproachM);
      return;
    }
    for (int i = 0; i < kControlDims; ++i) u[i] = rng_.uniformReal(b.low[i], b.high[i]);
  }

 private:
  static constexpr double kGoalBias = 0.05;
  search::GoalRegion goal_;
};

// Every improvement of the best goal state, in planning time summed over the solve() calls.
struct SolutionRecorder {
  std::chrono::steady_clock::time_point started = std::chrono::steady_clock::now();
  double offset_ms = 0.0;  // planning time of the earlier calls [ms]
  std::vector<search::CostSample> improvements;
};

// The problem's goal region; goal samples are the goal pose at the goal speed.
// Every state the planner tests against the goal passes here: the first one inside the region
// and each one reached sooner than the best so far are recorded (planning time, the state's
// time coordinate = the trajectory's duration). OMPL's SST adds its solution path only when
// solve() returns, so this is how its first-solution time and cost curve are measured.
class GoalRegionAdapter final : public ob::GoalSampleableRegion {
 public:
  GoalRegionAdapter(const ob::SpaceInformationPtr& si, const search::GoalRegion& goal,
                    SolutionRecorder& recorder)
      : ob::GoalSampleableRegion(si), goal_(goal), recorder_(recorder) {
    setThreshold(goal.position_tolerance);
  }
  bool isSatisfied(const ob::State* state, double* distance) const override {
    const bool inside = ob::GoalSampleableRegion::isSatisfied(state, distance);
    if (inside) record(state);
    return inside;
  }
  bool isSatisfied(const ob::State* state) const override { return isSatisfied(state, nullptr); }
  double distanceGoal(const ob::State* state) const override {
    const search::PlannerState s = plannerState(state);
    const double position = goal_.positionError(s);
    // Heading or speed outside their tolerances keep the state out of the region.
    const bool rest_ok = goal_.headingError(s) <= goal_.heading_tolerance &&
                         std::abs(s.v - goal_.v) <= goal_.speed_tolerance;
    return rest_ok ? position : position + 10.0 * goal_.position_tolerance;
  }
  void sampleGoal(ob::State* state) const override {
    search::PlannerState s;
    s.position = goal_.position;
    s.heading = goal_.heading;
    s.v = goal_.v;
    setState(state, s, 0.0);
  }
  unsigned int maxSampleCount() const override { return std::numeric_limits<unsigned>::max(); }

 private:
  void record(const ob::State* state) const {
    const double duration = stateTime(state);
    if (!recorder_.improvements.empty() && duration >= recorder_.improvements.back().cost_s) {
      return;
    }
    const double ms =
        recorder_.offset_ms + std::chrono::duration<double, std::milli>(
                                  std::chrono::steady_clock::now() - recorder_.started)
                                  .count();
    recorder_.improvements.push_back({ms, duration});
  }

  search::GoalRegion goal_;
  SolutionRecorder& recorder_;
};

// SST's cost: the duration of a motion (the difference of the time coordinates).
class TimeObjective final : public ob::OptimizationObjective {
 public:
  explicit TimeObjective(const ob::SpaceInformationPtr& si) : ob::OptimizationObjective(si) {
    description_ = "trajectory duration";
  }
  ob::Cost stateCost(const ob::State* /*state*/) const override { return identityCost(); }
  ob::Cost motionCost(const ob::State* a, const ob::State* b) const override {
    return ob::Cost(stateTime(b) - stateTime(a));
  }
};

// The solution re-integrated: each control's motion from the state OMPL reached, for the
// control's duration.
inline models::Trajectory reintegrate(const ExtensionPropagator& propagator,
                                      const search::PlanningProblem& problem,
                                      oc::PathControl& path) {
  models::Trajectory trajectory;
  trajectory.has_column.fill(true);
  search::Extension e;
  double t0 = 0.0;
  for (std::size_t i = 0; i < path.getControlCount(); ++i) {
    if (!propagator.motion(plannerState(path.getState(i)), path.getControl(i), e)) break;
    const double duration = std::min(path.getControlDuration(i), e.duration);
    double last_t = -1.0;
    for (std::size_t k = trajectory.samples.empty() ? 0 : 1; k < e.points.size(); ++k) {
      if (e.points[k].t > duration + 1e-9) break;
      trajectory.samples.push_back(search::trajectorySample(e.points[k], t0));
      last_t = e.points[k].t;
    }
    // A control cut before its extension ends: the point where OMPL's next state starts (the
    // propagator's interpolation), so that the trajectory has no gap at the joint.
    if (last_t < duration - 1e-9 && e.points.size() >= 2) {
      search::PathPoint joint = pointAt(e, duration);
      // The attitude at the joint from the vehicle model, not interpolated (the checker
      // recomputes it there).
      models::AttitudeWorkspace workspace;
      models::AttitudeResult attitude;
      if (problem.vehicle->compute({joint.position.x(), joint.position.y(), joint.heading},
                                   workspace, attitude) == models::AttitudeStatus::kOk) {
        joint.z = attitude.attitude.z;
        joint.roll = attitude.attitude.roll;
        joint.pitch = attitude.attitude.pitch;
      }
      trajectory.samples.push_back(search::trajectorySample(joint, t0));
    }
    t0 += duration;
  }
  return trajectory;
}

}  // namespace terratraj::bench::detail
