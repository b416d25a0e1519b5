#pragma once
// What the planner benchmarks share: bench::BenchmarkWorld (generated maps, the example
// limits, start and goal on moderate ground) under short names, a tally of the independent
// re-checks (failures named, so that none goes unseen), and main().

#include <benchmark/benchmark.h>

#include <Eigen/Core>
#include <cmath>
#include <cstdint>
#include <map>
#include <memory>
#include <sstream>
#include <string>

#include "terratraj/bench/benchmark_world.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::bench {

inline constexpr double kCell = bench::kBenchmarkCell;  ///< [m]
/// The problem files' limits; pitch_max is the expansiveness knob.
inline models::VehicleLimits exampleLimits(double pitch_max_deg = 17.0) {
  return bench::benchmarkLimits(pitch_max_deg);
}
using Vehicle = bench::BenchmarkVehicle;
inline const char* vehicleName(Vehicle vehicle) { return bench::benchmarkVehicleName(vehicle); }
inline terrain::ElevationMap generate(terrain::TerrainKind kind, int size, std::uint64_t seed) {
  return bench::generateBenchmarkMap(kind, size, seed);
}
using World = bench::BenchmarkWorld;

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
