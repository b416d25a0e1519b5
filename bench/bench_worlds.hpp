#pragma once
// What the planner benchmarks share: generated maps of 0.25 m cells, the example problem's
// limits, a vehicle on a map with start and goal placed on moderate ground, and a tally of the
// independent re-checks (failures named, so that none goes unseen).

#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::bench {

inline constexpr double kCell = 0.25;  ///< [m]

/// The problem files' limits (examples/plan_problem.yaml); pitch_max is the expansiveness knob.
inline models::VehicleLimits exampleLimits(double pitch_max_deg = 17.0) {
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

/// The attitude models the benchmarks use.
enum class Vehicle { kPoint, kRockerBogie };

inline const char* vehicleName(Vehicle vehicle) {
  return vehicle == Vehicle::kPoint ? "point" : "rocker_bogie";
}

inline std::unique_ptr<models::TerrainFollowingModel> makeVehicle(
    Vehicle vehicle, const terrain::TerrainSurface& surface) {
  if (vehicle == Vehicle::kRockerBogie) {
    return std::make_unique<models::RockerBogieAttitudeModel>(surface);
  }
  return std::make_unique<models::PointAttitudeModel>(surface);
}

/// A generated map of size x size cells of kCell.
inline terrain::ElevationMap generate(terrain::TerrainKind kind, int size, std::uint64_t seed) {
  terrain::GeneratorOptions options;
  options.kind = kind;
  options.rows = options.cols = size;
  options.cell = kCell;
  options.seed = seed;
  return terrain::generateTerrain(options);
}

/// A map, a vehicle on it and a planning problem. Not copyable: the problem points into it.
struct World {
  World(terrain::ElevationMap map_in, Vehicle kind, const models::VehicleLimits& limits)
      : map(std::move(map_in)),
        surface(map, terrain::Interpolation::kBicubic),
        vehicle(makeVehicle(kind, surface)),
        problem(map, *vehicle) {
    problem.limits = limits;
  }
  World(const World&) = delete;
  World& operator=(const World&) = delete;
  /// Whether the vehicle rests at `p` (heading east) within half its pitch and roll limits:
  /// start and goal are put on moderate ground, not on the edge of what the vehicle can climb.
  bool moderate(const Eigen::Vector2d& p) const {
    models::AttitudeWorkspace workspace;
    models::AttitudeResult result;
    if (vehicle->compute({p.x(), p.y(), 0.0}, workspace, result) != models::AttitudeStatus::kOk) {
      return false;
    }
    return std::abs(result.attitude.pitch) <= 0.5 * problem.limits.pitch_max &&
           std::abs(result.attitude.roll) <= 0.5 * problem.limits.roll_max;
  }
  /// Puts start and goal at the given points (at rest, heading east), each moved north 0.5 m
  /// at a time until it is valid and on moderate ground.
  bool place(const Eigen::Vector2d& start, const Eigen::Vector2d& goal) {
    problem.start = search::PlannerState{};
    problem.start.position = start;
    problem.goal.position = goal;
    for (Eigen::Vector2d* p : {&problem.start.position, &problem.goal.position}) {
      int i = 0;
      for (; i < 200 && !(moderate(*p) && !problem.validate()); ++i) p->y() += 0.5;
      if (i == 200) return false;
    }
    return !problem.validate();
  }
  double distance() const { return (problem.goal.position - problem.start.position).norm(); }

  terrain::ElevationMap map;
  terrain::TerrainSurface surface;
  std::unique_ptr<models::TerrainFollowingModel> vehicle;
  search::PlanningProblem problem;
  bool placed = false;
};

/// Collects checker outcomes; failures are named in label() ("limit x count, worst amount").
class CheckTally {
 public:
  void add(const search::CheckReport& report, const std::string& where) {
    ++checked_;
    if (report.ok()) {
      ++ok_;
      return;
    }
    for (const search::CheckViolation& v : report.violations) {
      Failure& f = failures_[v.limit];
      ++f.count;
      if (v.amount > f.worst) {
        f.worst = v.amount;
        f.where = where + " sample " + std::to_string(v.sample);
      }
    }
  }
  double fraction() const { return checked_ == 0 ? 0.0 : static_cast<double>(ok_) / checked_; }
  int checked() const { return checked_; }
  std::string label() const {
    std::ostringstream text;
    for (const auto& [limit, f] : failures_) {
      text << (text.tellp() > 0 ? "; " : "") << "check failed: " << limit << " x" << f.count
           << " (worst " << f.worst << ", " << f.where << ")";
    }
    return text.str();
  }

 private:
  struct Failure {
    int count = 0;
    double worst = 0.0;
    std::string where;
  };
  int checked_ = 0;
  int ok_ = 0;
  std::map<std::string, Failure> failures_;
};

/// The main() of a benchmark binary whose benchmarks `registerBenchmarks` registers.
template <typename Register>
int runBenchmarks(int argc, char** argv, Register&& registerBenchmarks) {
  registerBenchmarks();
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

}  // namespace terratraj::bench
