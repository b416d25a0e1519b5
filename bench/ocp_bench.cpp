// Boundary-value solver convergence (issue: Boundary-value solver). Per solver and problem
// set: success rate, iterations (median, p90) and solve time per trajectory (median, p90), as
// counters. Each benchmark iteration solves the whole set once.
// Run: ./build/bench/ocp_bench   (figures and the exact command in docs/benchmarks.md)

#include <benchmark/benchmark.h>

#include <algorithm>
#include <memory>
#include <vector>

#include "boundary_value_fixtures.hpp"
#include "terratraj/models/point_attitude_model.hpp"
#include "terratraj/models/rocker_bogie_attitude_model.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"

namespace {

using namespace terratraj;

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const std::size_t i = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1) + 0.5);
  return values[std::min(i, values.size() - 1)];
}

void solveSet(benchmark::State& state, const models::TerrainFollowingModel& vehicle,
              const terrain::ElevationMap& map, const std::vector<ocp::BoundaryValueProblem>& set,
              ocp::BoundaryValueMethod method) {
  ocp::BoundaryValueOptions options;
  options.method = method;
  std::vector<double> times, iterations;
  int converged = 0, solves = 0;
  for (auto _ : state) {
    for (const ocp::BoundaryValueProblem& problem : set) {
      const ocp::BoundaryValueSolution s = ocp::solveBoundaryValue(vehicle, problem, options, &map);
      ++solves;
      // Solve time = flat initial guess + solver (not the re-simulation for the report).
      times.push_back(s.total_time_ms);
      iterations.push_back(s.solver.iterations);
      converged += s.status == ocp::SolveStatus::kConverged;
    }
  }
  state.counters["success_rate"] = static_cast<double>(converged) / std::max(1, solves);
  state.counters["iterations_median"] = percentile(iterations, 0.5);
  state.counters["iterations_p90"] = percentile(iterations, 0.9);
  state.counters["time_ms_median"] = percentile(times, 0.5);
  state.counters["time_ms_p90"] = percentile(times, 0.9);
}

struct Rough {
  terrain::ElevationMap map = ocp::fixtures::roughMap();
  terrain::TerrainSurface surface{map, terrain::Interpolation::kBicubic};
  models::RockerBogieAttitudeModel vehicle{surface};
  std::vector<ocp::BoundaryValueProblem> set = ocp::fixtures::roughLattice();
};
struct Flat {
  terrain::ElevationMap map = ocp::fixtures::flatMap();
  terrain::TerrainSurface surface{map, terrain::Interpolation::kBicubic};
  models::PointAttitudeModel vehicle{surface};
  std::vector<ocp::BoundaryValueProblem> set = ocp::fixtures::flatFan();
};

void BM_RoughLattice94(benchmark::State& state) {
  static const Rough rough;
  solveSet(state, rough.vehicle, rough.map, rough.set,
           static_cast<ocp::BoundaryValueMethod>(state.range(0)));
}
void BM_FlatFan45(benchmark::State& state) {
  static const Flat flat;
  solveSet(state, flat.vehicle, flat.map, flat.set,
           static_cast<ocp::BoundaryValueMethod>(state.range(0)));
}

// Arguments: 0 newton, 1 newton_fd, 2 ipopt, 3 ceres.
BENCHMARK(BM_RoughLattice94)->DenseRange(0, 3)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FlatFan45)->DenseRange(0, 3)->Iterations(1)->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
