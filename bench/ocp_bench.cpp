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
#include "terratraj/ocp/direct_transcription.hpp"

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

// Direct transcription (Hermite-Simpson collocation, exact Hessian) on rough terrain: rest to
// rest from (2, 2, 0) to (14, 10, 90 deg) across the generated hills, from a straight-line
// guess. Arguments: N; cost 0 time, 1 slope dwell (alpha = 2); model 0 point, 1 rocker-bogie;
// scheme 0 Hermite-Simpson, 1 trapezoidal.
void BM_CollocationRough(benchmark::State& state) {
  static const Rough rough;
  static const models::PointAttitudeModel point{rough.surface};
  const models::TerrainFollowingModel& vehicle =
      state.range(2) == 0 ? static_cast<const models::TerrainFollowingModel&>(point)
                          : rough.vehicle;
  ocp::BoundaryValueProblem problem;
  problem.start = {2.0, 2.0, 0.0, 0.0, 0.0};
  problem.goal = {14.0, 10.0, 1.5707963267948966, 0.0, 0.0};
  problem.limits = ocp::fixtures::looseLimits();
  problem.limits.v_max = 1.0;
  problem.limits.a_max = 0.5;
  problem.limits.kappa_max = 1.0;
  problem.limits.sigma_max = 2.0;
  if (state.range(1) == 1) problem.cost = {ocp::CostKind::kSlopeDwell, 2.0};
  const ocp::TranscriptionGuess guess = *ocp::guessFromPath({{2.0, 2.0}, {14.0, 10.0}}, problem);
  ocp::DirectTranscriptionOptions options;
  options.intervals = static_cast<int>(state.range(0));
  options.scheme = state.range(3) == 0 ? ocp::TranscriptionScheme::kHermiteSimpson
                                       : ocp::TranscriptionScheme::kTrapezoidal;
  options.model.control_effort_weight = 1e-3;
  int iterations = 0, converged = 0, solves = 0;
  double total_ms = 0.0;
  for (auto _ : state) {
    const ocp::TranscriptionSolution s =
        ocp::solveDirectTranscription(vehicle, problem, guess, options);
    iterations += s.result.iterations;
    total_ms += s.result.solve_time_ms;
    converged += s.result.status == ocp::SolveStatus::kConverged ? 1 : 0;
    ++solves;
  }
  state.counters["converged"] = static_cast<double>(converged) / solves;
  state.counters["iterations"] = static_cast<double>(iterations) / solves;
  state.counters["ms_per_iteration"] = iterations > 0 ? total_ms / iterations : 0.0;
}
BENCHMARK(BM_CollocationRough)
    ->ArgsProduct({{50, 100, 200}, {0, 1}, {0, 1}, {0, 1}})
    ->Iterations(3)
    ->Unit(benchmark::kMillisecond);

// Issue 17's speed target on one set: direct transcription with 100 intervals against newton
// on the same problems, the rough lattice's 94 edges with the rocker-bogie (the problems of
// BM_RoughLattice94). Each edge is solved by newton (flat guess + solver) and by collocation
// from a straight-line guess (the same information), Ipopt with the exact Hessian. Counters:
// per-problem median and p90 times of both, their ratio, collocation's success rate and
// iterations. Argument: scheme 0 Hermite-Simpson, 1 trapezoidal.
void BM_CollocationVsNewtonRoughLattice(benchmark::State& state) {
  static const Rough rough;
  ocp::BoundaryValueOptions newton;
  newton.method = ocp::BoundaryValueMethod::kNewton;
  ocp::DirectTranscriptionOptions options;
  options.intervals = 100;
  options.scheme = state.range(0) == 0 ? ocp::TranscriptionScheme::kHermiteSimpson
                                       : ocp::TranscriptionScheme::kTrapezoidal;
  options.model.control_effort_weight = 1e-3;
  std::vector<double> newton_ms, collocation_ms, ratios, iterations;
  int converged = 0, solves = 0;
  for (auto _ : state) {
    for (const ocp::BoundaryValueProblem& problem : rough.set) {
      const ocp::BoundaryValueSolution n =
          ocp::solveBoundaryValue(rough.vehicle, problem, newton, &rough.map);
      const ocp::TranscriptionGuess guess = *ocp::guessFromPath(
          {{problem.start.x, problem.start.y}, {problem.goal.x, problem.goal.y}}, problem);
      const ocp::TranscriptionSolution c =
          ocp::solveDirectTranscription(rough.vehicle, problem, guess, options);
      newton_ms.push_back(n.total_time_ms);
      collocation_ms.push_back(c.result.solve_time_ms);
      ratios.push_back(c.result.solve_time_ms / std::max(n.total_time_ms, 1e-6));
      iterations.push_back(c.result.iterations);
      converged += c.result.status == ocp::SolveStatus::kConverged ? 1 : 0;
      ++solves;
    }
  }
  state.counters["collocation_success"] = static_cast<double>(converged) / std::max(1, solves);
  state.counters["collocation_iterations_median"] = percentile(iterations, 0.5);
  state.counters["newton_ms_median"] = percentile(newton_ms, 0.5);
  state.counters["collocation_ms_median"] = percentile(collocation_ms, 0.5);
  state.counters["collocation_ms_p90"] = percentile(collocation_ms, 0.9);
  state.counters["ratio_of_medians"] =
      percentile(collocation_ms, 0.5) / std::max(percentile(newton_ms, 0.5), 1e-6);
  state.counters["ratio_median"] = percentile(ratios, 0.5);
}
BENCHMARK(BM_CollocationVsNewtonRoughLattice)
    ->DenseRange(0, 1)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

}  // namespace

BENCHMARK_MAIN();
