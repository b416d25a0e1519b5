#include "terratraj/models/driving_log_simulator.hpp"

#include <algorithm>
#include <cmath>
#include <random>

#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rover_kinematics.hpp"
#include "terratraj/terrain/input_error.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace terratraj::models {
namespace {

constexpr double kPi = 3.14159265358979323846;
constexpr int kSubsteps = 10;         // integration steps per sample
constexpr double kEdgeMargin = 12.0;  // [m] turn back toward the centre within this

class Uniform {
 public:
  explicit Uniform(std::uint64_t seed) : engine_(seed) {}
  double operator()(double lo, double hi) {
    return lo + (hi - lo) * static_cast<double>(engine_() >> 11) * 0x1.0p-53;
  }

 private:
  std::mt19937_64 engine_;
};

void validate(const DrivingLogOptions& o) {
  const bool ok =
      o.duration > 0.0 && o.sample_period > 0.0 && o.terrain_size >= 16 && o.terrain_cell > 0.0 &&
      o.speed_cap > 0.0 && o.lateral_acceleration > 0.0 && o.acceleration > 0.0 && o.noise >= 0.0 &&
      o.noise < 1.0 && o.max_curvature > 0.0 && o.curvature_rate > 0.0 && o.steer_period > 0.0 &&
      o.avoid_curvature > 0.0 && o.downhill_slowdown >= 0.0 && o.downhill_slowdown < 1.0;
  if (!ok) throw InputError("driving-log simulator: invalid options");
}

}  // namespace

Trajectory simulateDrivingLog(const DrivingLogOptions& o) {
  validate(o);
  terrain::GeneratorOptions course;
  course.kind = terrain::TerrainKind::kHills;
  course.rows = course.cols = o.terrain_size;
  course.cell = o.terrain_cell;
  course.seed = o.seed;
  const terrain::ElevationMap map = terrain::generateTerrain(course);
  const terrain::TerrainSurface surface(map, terrain::kDefaultInterpolation);
  const PointAttitudeModel model(surface);
  const RoverKinematics kinematics(model);
  AttitudeWorkspace workspace;
  RoverRates rates;
  Uniform uniform(o.seed ^ 0x9e3779b97f4a7c15ULL);

  const double size = map.geometry().width();
  Eigen::Vector3d state(0.5 * size, 0.5 * size, uniform(-kPi, kPi));
  double v = 0.0, curvature = 0.0, target = 0.0, next_steer = 0.0, speed_factor = 1.0;
  const long samples = static_cast<long>(std::floor(o.duration / o.sample_period)) + 1;
  const double h = o.sample_period / kSubsteps;
  Trajectory log;
  log.has_column.fill(true);
  log.samples.reserve(static_cast<std::size_t>(samples));
  for (long k = 0; k < samples; ++k) {
    const double t = static_cast<double>(k) * o.sample_period;
    if (t >= next_steer) {
      target = uniform(-o.max_curvature, o.max_curvature);
      speed_factor = 1.0 - o.noise * uniform(0.0, 1.0);
      next_steer += o.steer_period;
    }
    // Near the edge: turn toward the centre as hard as allowed.
    const Eigen::Vector2d to_centre = Eigen::Vector2d(0.5 * size, 0.5 * size) - state.head<2>();
    if (state.x() < kEdgeMargin || state.y() < kEdgeMargin || state.x() > size - kEdgeMargin ||
        state.y() > size - kEdgeMargin) {
      const double bearing =
          std::remainder(std::atan2(to_centre.y(), to_centre.x()) - state.z(), 2 * kPi);
      target = bearing > 0.0 ? o.max_curvature : -o.max_curvature;
    }
    if (kinematics.rates(state, v, v * curvature, workspace, rates) != AttitudeStatus::kOk) break;
    const double roll = rates.attitude.attitude.roll;
    const double pitch = rates.attitude.attitude.pitch;
    // The avoided region: no hard turn with the roll against it, ever.
    const auto avoid = [&o](double kappa, double roll_now) {
      if (kappa * roll_now > 0.0 && std::abs(roll_now) > o.avoid_roll) {
        return std::clamp(kappa, -0.98 * o.avoid_curvature, 0.98 * o.avoid_curvature);
      }
      return kappa;
    };
    const double wanted = avoid(target, roll);
    curvature = avoid(curvature, roll);
    const double comfort = std::min(o.speed_cap, std::sqrt(o.lateral_acceleration /
                                                           std::max(std::abs(curvature), 1e-9))) *
                           (1.0 - o.downhill_slowdown * std::max(0.0, -pitch) / 0.4);
    log.samples.push_back({t, state.x(), state.y(), rates.attitude.attitude.z, state.z(), roll,
                           pitch, v, v * curvature, curvature});
    const double wanted_speed = comfort * speed_factor;
    for (int s = 0; s < kSubsteps; ++s) {
      curvature += std::clamp(wanted - curvature, -o.curvature_rate * h, o.curvature_rate * h);
      v += std::clamp(wanted_speed - v, -o.acceleration * h, o.acceleration * h);
      if (kinematics.rates(state, v, v * curvature, workspace, rates) != AttitudeStatus::kOk) break;
      curvature = avoid(curvature, rates.attitude.attitude.roll);
      rates.rate.z() = v * curvature * std::cos(rates.attitude.attitude.roll) /
                       std::cos(rates.attitude.attitude.pitch);
      state += h * rates.rate;
    }
  }
  return log;
}

}  // namespace terratraj::models
