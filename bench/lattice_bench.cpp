// State lattice and TAEASL benchmarks (issue 7; 004_... fig. 4, 002_...). Figures and the exact
// commands are in docs/benchmarks.md, "State lattice and TAEASL (issue 7)".
//
//   BM_PrimitiveGeneration   generatePrimitives() of the default set (LatticeSpec{}: 0.5 m, 16
//                            headings) for the example limits; counters: primitives, solves,
//                            failures
//   BM_LatticeFirstSolution/<algorithm>/<size>/<vehicle>/<kind>
//                            time to the first solution (PlanResult::first_solution_ms) of A*
//                            and ARA* (initial epsilon 3 and 1.5), median over 5 map seeds, on
//                            <size>^2 maps of 0.25 m cells; start and goal 100 m apart on 512^2
//                            and 1024^2, the standard start and goal (51.2 m apart) on 256^2;
//                            graph construction timed separately; every trajectory re-checked
//                            with TrajectoryChecker (target: first solution under 50 ms on
//                            1024^2 hills)
//   BM_TaeaslClasses/<anchor>/<size>/<limit>
//                            TAEASL on forest maps (3 map seeds), 0.1 s and 1 s limits, default
//                            TaeaslOptions (3 classes, frame radius 10 m) anchored at the map
//                            centre or at the start-goal midpoint: classes returned, frames,
//                            classes created, expansions, when the first and last returned
//                            solution were found (PlanSolution::found_ms: the time of the
//                            class's last improvement), every solution re-checked, whether the
//                            signatures are distinct
// Primitives are generated once per process and shared by every lattice benchmark.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <memory>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "bench_worlds.hpp"
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/lattice_planner.hpp"
#include "terratraj/search/primitive_generator.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/terrain_generator.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace {

using namespace terratraj;
using bench::CheckTally;
using bench::exampleLimits;
using bench::generate;
using bench::Vehicle;
using bench::vehicleName;
using bench::World;

constexpr double kInfinity = std::numeric_limits<double>::infinity();
constexpr int kMapSeeds = 5;     // BM_LatticeFirstSolution
constexpr int kForestSeeds = 3;  // BM_TaeaslClasses

using Clock = std::chrono::steady_clock;

double millisecondsSince(const Clock::time_point& start) {
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count();
}

// Start and goal 100 m apart across the middle of the map; on maps narrower than 120 m the
// standard start and goal (10 % and 90 % of the width, mid-height).
std::pair<Eigen::Vector2d, Eigen::Vector2d> startGoal(const terrain::GridGeometry& geometry) {
  if (geometry.width() < 120.0) return terrain::standardStartGoal(geometry);
  const double x0 = 0.5 * geometry.width() - 50.0;
  const double y = 0.5 * geometry.height();
  return {{x0, y}, {x0 + 100.0, y}};
}

// One world per (kind, size, seed, vehicle), generated on first use.
World& world(terrain::TerrainKind kind, int size, std::uint64_t seed, Vehicle vehicle) {
  static std::map<std::tuple<int, int, std::uint64_t, int>, std::unique_ptr<World>> worlds;
  std::unique_ptr<World>& w =
      worlds[{static_cast<int>(kind), size, seed, static_cast<int>(vehicle)}];
  if (!w) {
    w = std::make_unique<World>(generate(kind, size, seed), vehicle, exampleLimits());
    const auto [start, goal] = startGoal(w->map.geometry());
    w->placed = w->place(start, goal);
  }
  return *w;
}

// The default primitive set, generated once per process.
const search::PrimitiveSet& primitives() {
  static const search::PrimitiveSet set =
      search::generatePrimitives(search::LatticeSpec{}, exampleLimits()).set;
  return set;
}

double median(std::vector<double> values) {
  if (values.empty()) return kInfinity;
  std::sort(values.begin(), values.end());
  const std::size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : 0.5 * (values[n / 2 - 1] + values[n / 2]);
}

double maximum(const std::vector<double>& values) {
  return values.empty() ? kInfinity : *std::max_element(values.begin(), values.end());
}

void BM_PrimitiveGeneration(benchmark::State& state) {
  search::PrimitiveGenerationResult result;
  for (auto _ : state) {
    result = search::generatePrimitives(search::LatticeSpec{}, exampleLimits());
  }
  state.counters["primitives"] = static_cast<double>(result.set.size());
  state.counters["solves"] = result.set.generation.solves;
  state.counters["failures"] = result.set.generation.failures;
  state.counters["headings_without"] = static_cast<double>(result.failures.size());
  const auto error = result.set.checkAgainst(search::LatticeSpec{}, nullptr);
  if (error) state.SetLabel("checkAgainst: " + *error);
}

struct Algorithm {
  const char* name;
  search::LatticeAlgorithm algorithm;
  double initial_epsilon;
};

const Algorithm kAlgorithms[] = {{"astar", search::LatticeAlgorithm::kAStar, 1.0},
                                 {"arastar3", search::LatticeAlgorithm::kAraStar, 3.0},
                                 {"arastar1.5", search::LatticeAlgorithm::kAraStar, 1.5}};

// First solution over map seeds 1..kMapSeeds.
void latticeFirstSolution(benchmark::State& state, Algorithm algorithm, int size, Vehicle vehicle,
                          terrain::TerrainKind kind) {
  const search::PrimitiveSet& set = primitives();
  std::vector<double> first_ms, graph_ms, cost_s, expansions, evaluations, invalid, distance;
  int runs = 0, unplaced = 0;
  double total_ms = 0.0, total_evaluations = 0.0;
  CheckTally tally;
  std::string failures;
  for (std::uint64_t seed = 1; seed <= kMapSeeds; ++seed) world(kind, size, seed, vehicle);
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= kMapSeeds; ++seed) {
      World& w = world(kind, size, seed, vehicle);
      if (!w.placed) {
        ++unplaced;
        continue;
      }
      ++runs;
      distance.push_back(w.distance());
      const Clock::time_point started = Clock::now();
      const search::LatticeGraph graph(w.problem, set);
      graph_ms.push_back(millisecondsSince(started));
      if (graph.error()) {
        state.SkipWithError(("graph: " + *graph.error()).c_str());
        return;
      }
      search::LatticePlannerOptions options;
      options.algorithm = algorithm.algorithm;
      options.initial_epsilon = algorithm.initial_epsilon;
      search::LatticePlanner planner(graph, options);
      const search::PlanResult result =
          planner.solve(search::TerminationCondition::timeLimit(10.0).stopAtFirstSolution());
      expansions.push_back(static_cast<double>(result.search.expansions));
      evaluations.push_back(static_cast<double>(result.search.edge_evaluations));
      invalid.push_back(static_cast<double>(result.search.invalid_edges));
      total_ms += result.planning_time_ms;
      total_evaluations += static_cast<double>(result.search.edge_evaluations);
      if (result.status != search::PlanStatus::kSolved || !result.first_solution_ms) {
        failures += " seed " + std::to_string(seed) + ": " + result.reason;
        continue;
      }
      first_ms.push_back(*result.first_solution_ms);
      cost_s.push_back(result.first_solution_cost_s);
      tally.add(search::TrajectoryChecker(w.problem).check(result.trajectory),
                "seed " + std::to_string(seed));
    }
  }
  state.counters["runs"] = runs;
  state.counters["solved"] = static_cast<double>(first_ms.size());
  state.counters["unplaced"] = unplaced;
  state.counters["checked_ok"] = tally.fraction();
  state.counters["median_first_ms"] = median(first_ms);
  state.counters["max_first_ms"] = maximum(first_ms);
  state.counters["median_graph_ms"] = median(graph_ms);
  state.counters["median_cost_s"] = median(cost_s);
  state.counters["median_expansions"] = median(expansions);
  state.counters["median_edge_evals"] = median(evaluations);
  state.counters["median_invalid_edges"] = median(invalid);
  state.counters["median_distance_m"] = median(distance);
  // Search time per edge evaluation (everything in solve() over the evaluations it made).
  state.counters["us_per_edge_eval"] =
      total_evaluations > 0.0 ? 1000.0 * total_ms / total_evaluations : 0.0;
  std::string label = tally.label();
  if (!failures.empty()) label += (label.empty() ? "" : ";") + std::string("unsolved:") + failures;
  if (!label.empty()) state.SetLabel(label);
}

// TAEASL on forest maps, seeds 1..kForestSeeds.
void taeaslClasses(benchmark::State& state, search::FrameAnchor anchor, int size,
                   double time_limit_s) {
  const search::PrimitiveSet& set = primitives();
  std::vector<double> classes, frames, created, expansions, first_ms, last_ms, total_ms,
      construct_ms, proven, distance;
  int runs = 0, distinct = 0, unsolved = 0;
  CheckTally tally;
  for (std::uint64_t seed = 1; seed <= kForestSeeds; ++seed) {
    world(terrain::TerrainKind::kForest, size, seed, Vehicle::kPoint);
  }
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= kForestSeeds; ++seed) {
      World& w = world(terrain::TerrainKind::kForest, size, seed, Vehicle::kPoint);
      if (!w.placed) continue;
      ++runs;
      distance.push_back(w.distance());
      const search::LatticeGraph graph(w.problem, set);
      if (graph.error()) {
        state.SkipWithError(("graph: " + *graph.error()).c_str());
        return;
      }
      search::TaeaslOptions options;
      options.anchor = anchor;
      const Clock::time_point started = Clock::now();
      search::TaeaslPlanner planner(graph, options);
      construct_ms.push_back(millisecondsSince(started));
      const search::PlanResult result =
          planner.solve(search::TerminationCondition::timeLimit(time_limit_s));
      frames.push_back(static_cast<double>(planner.frames().size()));
      created.push_back(static_cast<double>(result.search.homotopy_classes));
      expansions.push_back(static_cast<double>(result.search.expansions));
      classes.push_back(static_cast<double>(result.solutions.size()));
      total_ms.push_back(result.planning_time_ms);
      if (result.solutions.empty()) {
        ++unsolved;
        continue;
      }
      double first = kInfinity, last = 0.0;
      int proven_here = 0;
      std::set<std::string> signatures;
      for (std::size_t i = 0; i < result.solutions.size(); ++i) {
        const search::PlanSolution& solution = result.solutions[i];
        first = std::min(first, solution.found_ms);
        last = std::max(last, solution.found_ms);
        proven_here += solution.proven_optimal ? 1 : 0;
        signatures.insert(solution.homotopy);
        tally.add(search::TrajectoryChecker(w.problem).check(solution.trajectory),
                  "seed " + std::to_string(seed) + " solution " + std::to_string(i) + " '" +
                      solution.homotopy + "'");
      }
      first_ms.push_back(first);
      last_ms.push_back(last);
      proven.push_back(proven_here);
      distinct += signatures.size() == result.solutions.size() ? 1 : 0;
    }
  }
  state.counters["runs"] = runs;
  state.counters["unsolved"] = unsolved;
  state.counters["median_classes"] = median(classes);
  state.counters["min_classes"] =
      classes.empty() ? 0.0 : *std::min_element(classes.begin(), classes.end());
  state.counters["median_proven"] = median(proven);
  state.counters["median_frames"] = median(frames);
  state.counters["median_created"] = median(created);
  state.counters["median_expansions"] = median(expansions);
  state.counters["median_first_ms"] = median(first_ms);
  state.counters["median_last_ms"] = median(last_ms);
  state.counters["median_total_ms"] = median(total_ms);
  state.counters["median_frames_ms"] = median(construct_ms);
  state.counters["median_distance_m"] = median(distance);
  state.counters["checked_ok"] = tally.fraction();
  state.counters["checked"] = tally.checked();
  state.counters["distinct_runs"] = distinct;
  const std::string label = tally.label();
  if (!label.empty()) state.SetLabel(label);
}

void registerBenchmarks() {
  benchmark::RegisterBenchmark("BM_PrimitiveGeneration", BM_PrimitiveGeneration)
      ->Iterations(3)
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime();

  const std::tuple<Vehicle, terrain::TerrainKind> variants[] = {
      {Vehicle::kPoint, terrain::TerrainKind::kHills},
      {Vehicle::kRockerBogie, terrain::TerrainKind::kHills},
      {Vehicle::kPoint, terrain::TerrainKind::kForest}};
  for (const auto& [vehicle, kind] : variants) {
    for (const Algorithm& algorithm : kAlgorithms) {
      for (int size : {256, 512, 1024}) {
        const std::string name = std::string("BM_LatticeFirstSolution/") + algorithm.name + "/" +
                                 std::to_string(size) + "/" + vehicleName(vehicle) + "/" +
                                 terrain::terrainKindName(kind);
        benchmark::RegisterBenchmark(name.c_str(), latticeFirstSolution, algorithm, size, vehicle,
                                     kind)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }

  for (search::FrameAnchor anchor :
       {search::FrameAnchor::kMapCenter, search::FrameAnchor::kMidpoint}) {
    for (int size : {256, 512}) {
      for (int limit_ms : {100, 1000}) {
        const std::string name = std::string("BM_TaeaslClasses/") +
                                 search::frameAnchorName(anchor) + "/" + std::to_string(size) +
                                 "/" + std::to_string(limit_ms) + "ms";
        benchmark::RegisterBenchmark(name.c_str(), taeaslClasses, anchor, size, 0.001 * limit_ms)
            ->Iterations(1)
            ->Unit(benchmark::kMillisecond)
            ->UseRealTime();
      }
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  return terratraj::bench::runBenchmarks(argc, argv, registerBenchmarks);
}
