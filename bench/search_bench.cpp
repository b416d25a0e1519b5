// Kinodynamic PRM benchmarks (issue 6; 001_... V.A). Figures and the exact commands are in
// docs/benchmarks.md, "Kinodynamic PRM".
//
//   FirstSolution  median first-solution time on 1024 x 1024 hills (0.25 m), start and goal
//                  100 m apart, over map seeds x planner seeds (target: median < 10 ms)
//   Anytime        the same maps: cost after 1 s (several planner seeds) against a long run
//                  (target: within 10 %)
//   Environment    001_... fig. 6: first solution, cost after 1 s and 10 s and after the long
//                  run, for hills / corridor / obstacles / dead_end at 128 ... 1024 cells
//   Expansiveness  001_... fig. 7: the same against the trapped fraction, 256 x 256 maps of
//                  growing difficulty
// The long runs last TERRATRAJ_PRM_LONG_S seconds (default 30).

#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bench_worlds.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/terrain/terrain_generator.hpp"

namespace {

using namespace terratraj;
using bench::exampleLimits;
using bench::generate;
using bench::World;

constexpr double kInfinity = std::numeric_limits<double>::infinity();

double longRunSeconds() {
  const char* text = std::getenv("TERRATRAJ_PRM_LONG_S");
  const double value = text != nullptr ? std::atof(text) : 0.0;
  return value > 0.0 ? value : 30.0;
}

World& hills1024(std::uint64_t seed) {
  static std::map<std::uint64_t, std::unique_ptr<World>> worlds;
  std::unique_ptr<World>& world = worlds[seed];
  if (!world) {
    world = std::make_unique<World>(generate(terrain::TerrainKind::kHills, 1024, seed),
                                    bench::Vehicle::kPoint, exampleLimits());
    world->place({78.0, 128.0}, {178.0, 128.0});
  }
  return *world;
}

// Cost at `ms` into a run: the last improvement before it (+infinity before the first).
double costAt(const search::PlanResult& result, double ms) {
  double cost = kInfinity;
  for (const search::CostSample& sample : result.cost_history) {
    if (sample.time_ms <= ms) cost = sample.cost_s;
  }
  return cost;
}

double median(std::vector<double> values) {
  if (values.empty()) return kInfinity;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double quantile(std::vector<double> values, double q) {
  if (values.empty()) return kInfinity;
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1) + 0.5)];
}

// First-solution time over 3 maps x state.range(0) planner seeds.
void BM_FirstSolution(benchmark::State& state) {
  const int planner_seeds = static_cast<int>(state.range(0));
  std::vector<double> first_ms, costs;
  int runs = 0;
  int solved_per_map[3] = {0, 0, 0};
  for (auto _ : state) {
    for (std::uint64_t map_seed = 1; map_seed <= 3; ++map_seed) {
      World& world = hills1024(map_seed);
      for (int seed = 1; seed <= planner_seeds; ++seed) {
        search::PrmOptions options;
        options.seed = static_cast<std::uint64_t>(seed);
        search::KinodynamicPrm planner(world.problem, options);
        const search::PlanResult result =
            planner.solve(search::TerminationCondition::timeLimit(3.0).stopAtFirstSolution());
        ++runs;
        solved_per_map[map_seed - 1] += result.first_solution_ms ? 1 : 0;
        if (result.first_solution_ms) {
          first_ms.push_back(*result.first_solution_ms);
          costs.push_back(result.first_solution_cost_s);
        }
      }
    }
  }
  state.counters["runs"] = runs;
  state.counters["solved"] = static_cast<double>(first_ms.size());
  state.counters["median_first_ms"] = median(first_ms);
  state.counters["p90_first_ms"] = quantile(first_ms, 0.9);
  state.counters["max_first_ms"] = quantile(first_ms, 1.0);
  state.counters["median_first_cost_s"] = median(costs);
  for (std::uint64_t map_seed = 1; map_seed <= 3; ++map_seed) {
    const World& world = hills1024(map_seed);
    const std::string suffix = "_map" + std::to_string(map_seed);
    state.counters["solved" + suffix] = solved_per_map[map_seed - 1];
    state.counters["distance_m" + suffix] =
        (world.problem.goal.position - world.problem.start.position).norm();
  }
}
BENCHMARK(BM_FirstSolution)->Arg(20)->Iterations(1)->Unit(benchmark::kMillisecond)->UseRealTime();

// Cost after 1 s (planner seeds 1..5) against one long run, per map.
void BM_Anytime(benchmark::State& state) {
  const std::uint64_t map_seed = static_cast<std::uint64_t>(state.range(0));
  World& world = hills1024(map_seed);
  std::vector<double> one_second;
  double converged = kInfinity, first = kInfinity;
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= 5; ++seed) {
      search::PrmOptions options;
      options.seed = seed;
      search::KinodynamicPrm planner(world.problem, options);
      const search::PlanResult result = planner.solve(search::TerminationCondition::timeLimit(1.0));
      one_second.push_back(result.best_cost_s);
      converged = std::min(converged, result.best_cost_s);
    }
    search::PrmOptions options;
    options.seed = 100;
    search::KinodynamicPrm planner(world.problem, options);
    const search::PlanResult result =
        planner.solve(search::TerminationCondition::timeLimit(longRunSeconds()));
    converged = std::min(converged, result.best_cost_s);
    first = result.first_solution_cost_s;
    state.counters["long_run_nodes"] = static_cast<double>(result.nodes);
  }
  const double bound = search::BangBangBound(world.problem.limits.v_max, world.problem.limits.a_max)
                           .toGoal(world.problem.start, world.problem.goal);
  state.counters["bound_s"] = bound;
  state.counters["first_cost_s"] = first;
  state.counters["median_cost_1s"] = median(one_second);
  state.counters["worst_cost_1s"] = quantile(one_second, 1.0);
  state.counters["converged_cost_s"] = converged;
  state.counters["median_1s_over_converged"] = median(one_second) / converged;
  state.counters["worst_1s_over_converged"] = quantile(one_second, 1.0) / converged;
}
BENCHMARK(BM_Anytime)->DenseRange(1, 3)->Iterations(1)->Unit(benchmark::kSecond)->UseRealTime();

// One long run; the curve gives first, 1 s, 10 s and final costs.
void reportLongRun(benchmark::State& state, World& world) {
  search::PlanResult result;
  for (auto _ : state) {
    search::KinodynamicPrm planner(world.problem);
    result = planner.solve(search::TerminationCondition::timeLimit(longRunSeconds()));
  }
  state.counters["first_ms"] = result.first_solution_ms ? *result.first_solution_ms : kInfinity;
  state.counters["first_cost_s"] = result.first_solution_cost_s;
  state.counters["cost_1s"] = costAt(result, 1000.0);
  state.counters["cost_10s"] = costAt(result, 10000.0);
  state.counters["cost_long"] = result.best_cost_s;
  state.counters["trapped_fraction"] = result.trappedFraction();
  state.counters["nodes"] = static_cast<double>(result.nodes);
  state.counters["area_m2"] = world.map.geometry().width() * world.map.geometry().height();
}

void BM_Environment(benchmark::State& state) {
  const auto kind = static_cast<terrain::TerrainKind>(state.range(0));
  const int size = static_cast<int>(state.range(1));
  World world(generate(kind, size, 1), bench::Vehicle::kPoint, exampleLimits());
  const auto [start, goal] = terrain::standardStartGoal(world.map.geometry());
  if (!world.place(start, goal)) {
    state.SkipWithError("no valid start / goal");
    return;
  }
  state.SetLabel(terrain::terrainKindName(kind));
  reportLongRun(state, world);
}
BENCHMARK(BM_Environment)
    ->ArgsProduct({{static_cast<int>(terrain::TerrainKind::kHills),
                    static_cast<int>(terrain::TerrainKind::kCorridor),
                    static_cast<int>(terrain::TerrainKind::kObstacles),
                    static_cast<int>(terrain::TerrainKind::kDeadEnd)},
                   {128, 256, 512, 1024}})
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// 256 x 256 maps of growing difficulty: (kind, pitch_max in degrees).
const std::vector<std::tuple<terrain::TerrainKind, double>>& expansivenessVariants() {
  static const std::vector<std::tuple<terrain::TerrainKind, double>> variants{
      {terrain::TerrainKind::kFlat, 17.0},      {terrain::TerrainKind::kHills, 17.0},
      {terrain::TerrainKind::kHills, 12.0},     {terrain::TerrainKind::kHills, 9.0},
      {terrain::TerrainKind::kForest, 17.0},    {terrain::TerrainKind::kObstacles, 17.0},
      {terrain::TerrainKind::kCorridor, 17.0},  {terrain::TerrainKind::kDeadEnd, 17.0},
      {terrain::TerrainKind::kObstacles, 12.0}, {terrain::TerrainKind::kDeadEnd, 12.0}};
  return variants;
}

void BM_Expansiveness(benchmark::State& state) {
  const auto [kind, pitch_deg] = expansivenessVariants()[static_cast<std::size_t>(state.range(0))];
  World world(generate(kind, 256, 1), bench::Vehicle::kPoint, exampleLimits(pitch_deg));
  const auto [start, goal] = terrain::standardStartGoal(world.map.geometry());
  if (!world.place(start, goal)) {
    state.SkipWithError("no valid start / goal");
    return;
  }
  state.SetLabel(std::string(terrain::terrainKindName(kind)) + " pitch_max " +
                 std::to_string(static_cast<int>(pitch_deg)) + " deg");
  reportLongRun(state, world);
}
BENCHMARK(BM_Expansiveness)
    ->DenseRange(0, 9)
    ->Iterations(1)
    ->Unit(benchmark::kSecond)
    ->UseRealTime();

// Cost of one extension (8 m toward a milestone) on 1024 x 1024 hills.
void BM_Extension(benchmark::State& state) {
  World& world = hills1024(1);
  search::ExtensionIntegrator integrator(world.problem, {0.125, 0.5});
  search::Extension extension;
  search::ExtensionRequest request;
  request.target = world.problem.start.position + Eigen::Vector2d(6.0, 5.0);
  request.target_speed = request.turn_speed = 1.0;
  request.max_length = 8.0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(integrator.extend(world.problem.start, request, extension));
  }
  state.counters["samples"] = static_cast<double>(extension.points.size());
}
BENCHMARK(BM_Extension)->Unit(benchmark::kMicrosecond);

}  // namespace

BENCHMARK_MAIN();
