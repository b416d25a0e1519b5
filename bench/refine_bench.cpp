// Refinement of planner candidates (issue 8): how much the optimal-control core improves the
// searches' trajectories, and whether every refinement holds the limits and keeps its class.
// Figures and the exact command are in docs/benchmarks.md, "Refinement".
//
//   BM_Refine/<planner>/<kind>/<vehicle>
//       <kind> in hills, corridor, forest: 256 x 256 maps of 0.25 m (64 m), map seeds 1..3,
//       the standard start and goal (51.2 m apart, at rest, heading east) moved onto moderate
//       ground; <planner>: prm_first (the PRM's first solution), prm_1s (the PRM after 1 s),
//       taeasl (1 s, 3 classes, frames anchored at the map centre, radius 10 m). Every
//       candidate is refined (search::CandidateRefiner, default options: collocation or
//       polynomial controls by the auto rule). Counters:
//         candidates, converged      refinements run, and converged (solver, re-simulation,
//                                    limits, class)
//         ratio_mean, ratio_min, ratio_max
//                                    refined duration / candidate duration, converged only
//         bound_ratio_mean           refined duration / the bang-bang time along the straight
//                                    line (a lower bound of any trajectory: how much was left)
//         candidate_bound_ratio_mean the same for the candidates
//         kept                       fraction of converged refinements in their class
//                                    (signature recomputed here over the same frames)
//         checked_ok                 fraction of converged refinements the TrajectoryChecker
//                                    (run here, relative tolerance 1e-3) finds within every
//                                    limit; failures are named in the label
//         refine_ms_mean             wall time of one refinement
// The candidate stops anywhere in the goal region (0.5 m, 0.35 rad, 0.1 m/s); the refinement
// drives to the goal itself, at rest: the ratios include that extra distance.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "bench_worlds.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/search/candidate_refiner.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/primitive_generator.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"

namespace {

using namespace terratraj;
using bench::CheckTally;
using bench::Vehicle;
using bench::World;

constexpr int kMapSeeds = 3;
constexpr int kMapSize = 256;

enum class Planner { kPrmFirst, kPrm1s, kTaeasl };

World& world(terrain::TerrainKind kind, std::uint64_t seed, Vehicle vehicle) {
  static std::map<std::tuple<int, std::uint64_t, int>, std::unique_ptr<World>> worlds;
  std::unique_ptr<World>& w = worlds[{static_cast<int>(kind), seed, static_cast<int>(vehicle)}];
  if (!w) {
    w = std::make_unique<World>(bench::generate(kind, kMapSize, seed), vehicle,
                                bench::exampleLimits(25.0));
    const auto [start, goal] = terrain::standardStartGoal(w->map.geometry());
    w->placed = w->place(start, goal);
  }
  return *w;
}

const search::PrimitiveSet& primitives() {
  static const search::PrimitiveSet set =
      search::generatePrimitives(search::LatticeSpec{}, bench::exampleLimits(25.0)).set;
  return set;
}

// The candidates of one plan (empty when it found none).
std::vector<models::Trajectory> candidates(Planner planner, const search::PlanningProblem& problem,
                                           std::uint64_t seed) {
  std::vector<models::Trajectory> out;
  if (planner == Planner::kTaeasl) {
    const search::LatticeGraph graph(problem, primitives());
    const search::TaeaslPlanner taeasl(graph);
    const search::PlanResult r = taeasl.solve(search::TerminationCondition::timeLimit(1.0));
    for (const search::PlanSolution& s : r.solutions) out.push_back(s.trajectory);
    return out;
  }
  search::PrmOptions options;
  options.seed = seed;
  search::KinodynamicPrm prm(problem, options);
  search::TerminationCondition condition = search::TerminationCondition::timeLimit(1.0);
  if (planner == Planner::kPrmFirst) condition.stopAtFirstSolution();
  const search::PlanResult r = prm.solve(condition);
  if (r.status == search::PlanStatus::kSolved) out.push_back(r.trajectory);
  return out;
}

// With TERRATRAJ_REFINE_BENCH_DUMP=DIR, a candidate whose refinement failed is written there
// (to reproduce it with `terratraj refine`).
void dumpFailure(const models::Trajectory& candidate, const std::string& benchmark,
                 std::uint64_t seed, std::size_t k) {
  const char* dir = std::getenv("TERRATRAJ_REFINE_BENCH_DUMP");
  if (dir == nullptr || *dir == '\0') return;
  std::string name = benchmark;
  std::replace(name.begin(), name.end(), '/', '_');
  models::writeTrajectoryCsv(candidate, std::string(dir) + "/" + name + "_seed" +
                                            std::to_string(seed) + "_" + std::to_string(k) +
                                            ".csv");
}

double mean(const std::vector<double>& v) {
  double sum = 0.0;
  for (double x : v) sum += x;
  return v.empty() ? 0.0 : sum / static_cast<double>(v.size());
}

void refineBenchmark(benchmark::State& state, const std::string& name, Planner planner,
                     terrain::TerrainKind kind, Vehicle vehicle) {
  std::vector<double> ratios, bound_ratios, candidate_bound_ratios, refine_ms;
  int runs = 0, converged = 0, kept = 0;
  CheckTally tally;
  std::string notes;
  for (auto _ : state) {
    for (std::uint64_t seed = 1; seed <= kMapSeeds; ++seed) {
      World& w = world(kind, seed, vehicle);
      if (!w.placed) {
        notes += " seed " + std::to_string(seed) + ": no start / goal;";
        continue;
      }
      ocp::BoundaryValueProblem bvp;
      bvp.start = {w.problem.start.position.x(), w.problem.start.position.y(), 0.0, 0.0, 0.0};
      bvp.goal = {w.problem.goal.position.x(), w.problem.goal.position.y(), 0.0, 0.0, 0.0};
      bvp.limits = w.problem.limits;
      search::ReferenceFrameOptions frame_options;
      frame_options.anchor = {0.5 * w.map.geometry().width(), 0.5 * w.map.geometry().height()};
      const search::ReferenceFrames frames = search::ReferenceFrames::build(
          w.map, terrain::findObstacleClusters(w.map), frame_options);
      const search::CandidateRefiner refiner(w.problem, bvp, frames);
      const std::vector<models::Trajectory> found = candidates(planner, w.problem, seed);
      if (found.empty()) notes += " seed " + std::to_string(seed) + ": no candidate;";
      for (std::size_t k = 0; k < found.size(); ++k) {
        ++runs;
        const auto started = std::chrono::steady_clock::now();
        const search::RefinementResult r = refiner.refine(found[k]);
        refine_ms.push_back(
            std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - started)
                .count());
        if (r.status != ocp::SolveStatus::kConverged) {
          notes += " seed " + std::to_string(seed) + " #" + std::to_string(k) + ": " +
                   ocp::solveStatusName(r.status) + " (" + r.reason.substr(0, 160) + ");";
          dumpFailure(found[k], name, seed, k);
          continue;
        }
        ++converged;
        const double before = found[k].samples.back().t - found[k].samples.front().t;
        const double after = r.verified.final_time;
        ratios.push_back(after / before);
        bound_ratios.push_back(after / w.lowerBoundTime());
        candidate_bound_ratios.push_back(before / w.lowerBoundTime());
        // Independent of the refiner: the class recomputed and the limits re-checked here.
        std::vector<Eigen::Vector2d> xy_before, xy_after;
        for (const auto& s : found[k].samples) xy_before.emplace_back(s.x, s.y);
        for (const auto& s : r.verified.trajectory.samples) xy_after.emplace_back(s.x, s.y);
        if (frames.signatureOf(xy_before) == frames.signatureOf(xy_after)) ++kept;
        search::CheckTolerances tolerances;
        tolerances.relative = 1e-3;
        tally.add(search::TrajectoryChecker(w.problem, tolerances).check(r.verified.trajectory),
                  "seed " + std::to_string(seed) + " #" + std::to_string(k));
      }
    }
  }
  const auto minmax = ratios.empty() ? std::make_pair(ratios.end(), ratios.end())
                                     : std::minmax_element(ratios.begin(), ratios.end());
  state.counters["candidates"] = runs;
  state.counters["converged"] = converged;
  state.counters["ratio_mean"] = mean(ratios);
  state.counters["ratio_min"] = ratios.empty() ? 0.0 : *minmax.first;
  state.counters["ratio_max"] = ratios.empty() ? 0.0 : *minmax.second;
  state.counters["bound_ratio_mean"] = mean(bound_ratios);
  state.counters["candidate_bound_ratio_mean"] = mean(candidate_bound_ratios);
  state.counters["kept"] = converged > 0 ? static_cast<double>(kept) / converged : 0.0;
  state.counters["checked_ok"] = tally.fraction();
  state.counters["refine_ms_mean"] = mean(refine_ms);
  state.SetLabel(tally.label() + notes);
}

void registerBenchmarks() {
  const std::pair<const char*, Planner> planners[] = {
      {"prm_first", Planner::kPrmFirst}, {"prm_1s", Planner::kPrm1s}, {"taeasl", Planner::kTaeasl}};
  const std::pair<const char*, terrain::TerrainKind> kinds[] = {
      {"hills", terrain::TerrainKind::kHills},
      {"corridor", terrain::TerrainKind::kCorridor},
      {"forest", terrain::TerrainKind::kForest}};
  for (const auto& [planner_name, planner] : planners) {
    for (const auto& [kind_name, kind] : kinds) {
      const std::string name = std::string("BM_Refine/") + planner_name + "/" + kind_name + "/" +
                               bench::vehicleName(Vehicle::kPoint);
      benchmark::RegisterBenchmark(name.c_str(), refineBenchmark, name, planner, kind,
                                   Vehicle::kPoint)
          ->Iterations(1)
          ->Unit(benchmark::kSecond)
          ->UseRealTime();
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  return terratraj::bench::runBenchmarks(argc, argv, registerBenchmarks);
}
