#include "terratraj/search/benchmark_world.hpp"

#include <cmath>

#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/search/bang_bang_bound.hpp"

namespace terratraj::search {

models::VehicleLimits benchmarkLimits(double pitch_max_deg) {
  models::VehicleLimits limits;
  limits.v_max = 1.0;
  limits.a_max = 0.5;
  limits.omega_max = 1.0;
  limits.kappa_max = 1.0;
  limits.sigma_max = 0.5;
  limits.pitch_max = pitch_max_deg * models::kRadiansPerDegree;
  limits.roll_max = 20.0 * models::kRadiansPerDegree;
  return limits;
}

const char* benchmarkVehicleName(BenchmarkVehicle vehicle) {
  return vehicle == BenchmarkVehicle::kPoint ? "point" : "rocker_bogie";
}

std::unique_ptr<models::TerrainFollowingModel> makeBenchmarkVehicle(
    BenchmarkVehicle vehicle, const terrain::TerrainSurface& surface) {
  if (vehicle == BenchmarkVehicle::kRockerBogie) {
    return std::make_unique<models::RockerBogieAttitudeModel>(surface);
  }
  return std::make_unique<models::PointAttitudeModel>(surface);
}

terrain::ElevationMap generateBenchmarkMap(terrain::TerrainKind kind, int size,
                                           std::uint64_t seed) {
  terrain::GeneratorOptions options;
  options.kind = kind;
  options.rows = options.cols = size;
  options.cell = kBenchmarkCell;
  options.seed = seed;
  return terrain::generateTerrain(options);
}

BenchmarkWorld::BenchmarkWorld(terrain::ElevationMap map_in, BenchmarkVehicle kind,
                               const models::VehicleLimits& limits)
    : map(std::move(map_in)),
      surface(map, terrain::Interpolation::kBicubic),
      vehicle(makeBenchmarkVehicle(kind, surface)),
      problem(map, *vehicle) {
  problem.limits = limits;
}

bool BenchmarkWorld::moderate(const Eigen::Vector2d& p) const {
  models::AttitudeWorkspace workspace;
  models::AttitudeResult result;
  if (vehicle->compute({p.x(), p.y(), 0.0}, workspace, result) != models::AttitudeStatus::kOk) {
    return false;
  }
  return std::abs(result.attitude.pitch) <= 0.5 * problem.limits.pitch_max &&
         std::abs(result.attitude.roll) <= 0.5 * problem.limits.roll_max;
}

bool BenchmarkWorld::place(const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
  problem.start = PlannerState{};
  problem.start.position = start;
  problem.goal.position = goal;
  for (Eigen::Vector2d* p : {&problem.start.position, &problem.goal.position}) {
    int i = 0;
    for (; i < 200 && !(moderate(*p) && !problem.validate()); ++i) p->y() += 0.5;
    if (i == 200) return false;
  }
  return !problem.validate();
}

double BenchmarkWorld::distance() const {
  return (problem.goal.position - problem.start.position).norm();
}

double BenchmarkWorld::lowerBoundTime() const {
  return bangBangTime(distance(), 0.0, 0.0, 0.0, problem.limits.v_max, problem.limits.a_max);
}

}  // namespace terratraj::search
