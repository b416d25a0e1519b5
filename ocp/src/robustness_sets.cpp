#include "terratraj/ocp/robustness_sets.hpp"

#include <cmath>
#include <random>

#include "terratraj/ocp/problem_sets.hpp"

namespace terratraj::ocp::problem_sets {
namespace {

constexpr double kPi = 3.14159265358979323846;

BoundaryValueProblem roverProblem(const VehicleState& start, const VehicleState& goal) {
  BoundaryValueProblem problem;
  problem.start = start;
  problem.goal = goal;
  problem.limits = roverLimits();
  problem.cost.kind = CostKind::kTime;
  return problem;
}

}  // namespace

models::VehicleLimits roverLimits() {
  models::VehicleLimits limits;
  limits.v_max = 1.0;
  limits.a_max = 0.5;
  limits.omega_max = 1.0;
  limits.kappa_max = 1.0;
  limits.sigma_max = 20.0;
  limits.pitch_max = 25.0 * kPi / 180.0;
  limits.roll_max = 25.0 * kPi / 180.0;
  return limits;
}

terrain::ElevationMap openFlatMap() {
  terrain::GridGeometry g;
  g.rows = g.cols = 120;
  g.cell = 0.25;
  return terrain::ElevationMap(g);
}

std::vector<BoundaryValueProblem> constantSpeedTurns(int count, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<BoundaryValueProblem> problems;
  for (int i = 0; i < count; ++i) {
    const double distance = 2.0 + 8.0 * unit(random);
    const double bearing = 2.0 * kPi * unit(random);
    const double heading = wrapAngle(2.0 * kPi * unit(random));
    problems.push_back(roverProblem({15.0, 15.0, 0.0, 1.0, 0.0},
                                    {15.0 + distance * std::cos(bearing),
                                     15.0 + distance * std::sin(bearing), heading, 1.0, 0.0}));
  }
  return problems;
}

std::vector<BoundaryValueProblem> turnBacks(int count, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::vector<BoundaryValueProblem> problems;
  for (int i = 0; i < count; ++i) {
    const double distance = 2.0 + 3.0 * unit(random);
    const double bearing = kPi + (kPi / 4.0) * (2.0 * unit(random) - 1.0);
    const double heading = wrapAngle(kPi + (kPi / 3.0) * (2.0 * unit(random) - 1.0));
    problems.push_back(roverProblem({15.0, 15.0, 0.0, 0.0, 0.0},
                                    {15.0 + distance * std::cos(bearing),
                                     15.0 + distance * std::sin(bearing), heading, 0.0, 0.0}));
  }
  return problems;
}

std::vector<BoundaryValueProblem> terrainProblems(const terrain::ElevationMap& map,
                                                  const models::TerrainFollowingModel& vehicle,
                                                  const models::VehicleLimits& limits, int count,
                                                  std::uint64_t seed) {
  const terrain::GridGeometry& g = map.geometry();
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const auto rests = [&](double x, double y, double heading) {
    if (!clearAround(map, x, y, 1.5)) return false;
    models::AttitudeWorkspace workspace;
    models::AttitudeResult attitude;
    return vehicle.compute({x, y, heading}, workspace, attitude) == models::AttitudeStatus::kOk &&
           std::abs(attitude.attitude.pitch) < 0.9 * limits.pitch_max &&
           std::abs(attitude.attitude.roll) < 0.9 * limits.roll_max;
  };
  std::vector<BoundaryValueProblem> problems;
  for (long draw = 0; draw < 200L * count && static_cast<int>(problems.size()) < count; ++draw) {
    const double x0 = g.width() * unit(random), y0 = g.height() * unit(random);
    const double distance = 4.0 + 8.0 * unit(random);
    const double bearing = 2.0 * kPi * unit(random);
    const double x1 = x0 + distance * std::cos(bearing), y1 = y0 + distance * std::sin(bearing);
    const double h0 = wrapAngle(bearing + (2.0 * unit(random) - 1.0));
    const double h1 = wrapAngle(bearing + (2.0 * unit(random) - 1.0));
    if (!rests(x0, y0, h0) || !rests(x1, y1, h1)) continue;
    const double v = problems.size() % 2 == 0 ? 0.0 : 0.5 * limits.v_max;
    BoundaryValueProblem problem;
    problem.start = {x0, y0, h0, v, 0.0};
    problem.goal = {x1, y1, h1, v, 0.0};
    problem.limits = limits;
    problems.push_back(problem);
  }
  return problems;
}

}  // namespace terratraj::ocp::problem_sets
