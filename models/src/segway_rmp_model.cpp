#include "terratraj/models/segway_rmp_model.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::models {
namespace {

constexpr int kSubsteps = 4;  // RK4 steps per propagate() call

double excess(double value, double limit) { return std::max(0.0, value - limit); }

}  // namespace

SegwayRmpModel::SegwayRmpModel(const terrain::TerrainSurface& surface, SegwayLookups lookups,
                               const SegwayLimits& limits)
    : surface_(surface), lookups_(std::move(lookups)), limits_(limits) {}

double SegwayRmpModel::curvatureLimit(double v) const {
  const double v2 = v * v;
  return v2 > 0.0 ? std::min(limits_.kappa_max, limits_.lateral_acceleration / v2)
                  : limits_.kappa_max;
}

std::optional<SegwayPose> SegwayRmpModel::pose(const SegwayState& state,
                                               double acceleration) const {
  const std::optional<terrain::TangentPlanePatch> patch =
      terrain::TangentPlanePatch::at(surface_, {state.x, state.y}, state.heading);
  if (!patch) return std::nullopt;
  const double slope = patch->pitch();
  return SegwayPose{*patch, slope, lookups_.pitch_response.pitch(acceleration, slope)};
}

SegwayConstraintViolations SegwayRmpModel::check(const SegwayState& state,
                                                 const Eigen::Vector2d& control,
                                                 const SegwayPose& pose) const {
  SegwayConstraintViolations v;
  const double speed = std::abs(state.v);
  const double curvature = speed > 0.0 ? state.omega / state.v : 0.0;
  v.curvature = excess(std::abs(state.omega), speed * curvatureLimit(speed));
  v.curvature_rate =
      excess(std::abs(control.y() - control.x() * curvature), speed * limits_.sigma_max);
  v.pitch = excess(std::abs(pose.platform_pitch), limits_.pitch_max);
  v.roll = excess(std::abs(pose.patch.roll()), limits_.roll_max);
  const double v_limit = std::abs(pose.slope) > limits_.max_slope
                             ? 0.0
                             : std::min(limits_.v_max, lookups_.bounds.speedLimit(pose.slope));
  v.speed = std::max(excess(state.v, v_limit), excess(-state.v, 0.0));
  const double a_limit = std::min(limits_.a_max, lookups_.bounds.accelerationLimit(pose.slope));
  v.acceleration = excess(std::abs(control.x()), a_limit);
  return v;
}

bool SegwayRmpModel::propagate(const SegwayState& state, const Eigen::Vector2d& control, double dt,
                               SegwayState& end) const {
  const std::optional<terrain::TangentPlanePatch> patch =
      terrain::TangentPlanePatch::at(surface_, {state.x, state.y}, state.heading);
  if (!patch) return false;
  // In the patch's plane: position (u, w), angle from T, speed, yaw rate; start at the origin
  // facing T. Controls are constant over dt.
  using Vector5 = Eigen::Matrix<double, 5, 1>;
  const auto rates = [&control](const Vector5& s) {
    return (Vector5() << s(3) * std::cos(s(2)), s(3) * std::sin(s(2)), s(4), control.x(),
            control.y())
        .finished();
  };
  Vector5 s;
  s << 0.0, 0.0, 0.0, state.v, state.omega;
  const double h = dt / kSubsteps;
  for (int i = 0; i < kSubsteps; ++i) {
    const Vector5 k1 = rates(s);
    const Vector5 k2 = rates(s + 0.5 * h * k1);
    const Vector5 k3 = rates(s + 0.5 * h * k2);
    const Vector5 k4 = rates(s + h * k3);
    s += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
  }
  const Eigen::Vector3d point = patch->toMap(s(0), s(1));
  const std::optional<terrain::TangentPlanePatch> next = patch->next(surface_, {s(0), s(1), s(2)});
  if (!next) return false;
  end.x = point.x();
  end.y = point.y();
  end.heading =
      state.heading + std::remainder(next->heading() - state.heading, 2.0 * 3.14159265358979323846);
  end.v = s(3);
  end.omega = s(4);
  return true;
}

}  // namespace terratraj::models
