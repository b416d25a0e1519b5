// `terratraj bench refine`: the planners' candidates against their refinements (issue 8's set)
// on generated hills, corridor and forest maps. Every refinement is re-checked here,
// independently of the refiner: homotopy class recomputed over the same frames, limits by
// search::TrajectoryChecker.

#include <chrono>
#include <cstdlib>
#include <memory>
#include <optional>
#include <sstream>

#include "terratraj/bench/benchmark_suite.hpp"
#include "terratraj/bench/benchmark_world.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/models/trajectory_csv.hpp"
#include "terratraj/refine/candidate_refiner.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/primitive_generator.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/search/trajectory_checker.hpp"
#include "terratraj/terrain/obstacle_clusters.hpp"

namespace terratraj::bench {
namespace {

const char* const kPlanners[] = {"prm_first", "prm_1s", "taeasl"};
const std::pair<const char*, terrain::TerrainKind> kKinds[] = {
    {"hills", terrain::TerrainKind::kHills},
    {"corridor", terrain::TerrainKind::kCorridor},
    {"forest", terrain::TerrainKind::kForest}};
constexpr double kPitchMaxDeg = 25.0;

double duration(const models::Trajectory& t) { return t.samples.back().t - t.samples.front().t; }

std::vector<models::Trajectory> plan(const std::string& planner,
                                     const search::PlanningProblem& problem, std::uint64_t seed,
                                     double budget_s) {
  static const search::PrimitiveSet primitives =
      search::generatePrimitives(search::LatticeSpec{}, bench::benchmarkLimits(kPitchMaxDeg)).set;
  search::TerminationCondition condition = search::TerminationCondition::timeLimit(budget_s);
  if (planner == "prm_first") condition.stopAtFirstSolution();
  std::optional<search::LatticeGraph> graph;
  std::unique_ptr<search::Planner> planning;
  if (planner == "taeasl") {
    graph.emplace(problem, primitives);
    planning = std::make_unique<search::TaeaslPlanner>(*graph);
  } else {
    search::PrmOptions options;
    options.seed = seed;
    planning = std::make_unique<search::KinodynamicPrm>(problem, options);
  }
  const search::PlanResult r = planning->solve(condition);
  std::vector<models::Trajectory> out;
  for (const search::PlanSolution& s : r.solutions) out.push_back(s.trajectory);
  return out;
}

// With TERRATRAJ_REFINE_BENCH_DUMP=DIR, a candidate whose refinement failed is written there
// (to reproduce it with `terratraj refine`); returns the file, or "".
std::string dumpFailure(const models::Trajectory& candidate, const std::string& name) {
  const char* dir = std::getenv("TERRATRAJ_REFINE_BENCH_DUMP");
  if (dir == nullptr || *dir == '\0') return "";
  const std::string file = std::string(dir) + "/" + name + ".csv";
  models::writeTrajectoryCsv(candidate, file);
  return file;
}

nlohmann::json refineOne(const bench::BenchmarkWorld& w, const refine::CandidateRefiner& refiner,
                         const search::ReferenceFrames& frames, const models::Trajectory& candidate,
                         const std::string& name) {
  const auto started = std::chrono::steady_clock::now();
  const refine::RefinementResult r = refiner.refine(candidate);
  nlohmann::json out;
  out["refine_ms"] = millisecondsSince(started);
  out["status"] = ocp::solveStatusName(r.status);
  out["reason"] = r.reason;
  out["method"] = refine::refineMethodName(r.method);
  out["iterations"] = r.iterations;
  out["time_limit_reached"] = r.time_limit_reached;
  out["intervals"] = r.intervals;
  out["coarse_intervals"] = r.coarse_intervals;
  out["coarse_iterations"] = r.coarse_iterations;
  out["coarse_used"] = r.coarse_used;
  out["guess_shortcut_m"] = r.guess_shortcut_m;
  out["guess_retimed_s"] = r.guess_retimed_s;
  out["barrier"] = r.warm_start ? "warm" : "adaptive";
  out["candidate_s"] = duration(candidate);
  out["lower_bound_s"] = w.lowerBoundTime();
  if (r.status != ocp::SolveStatus::kConverged) {
    const std::string dumped = dumpFailure(candidate, name);
    if (!dumped.empty()) out["candidate_file"] = dumped;
    return out;
  }
  out["refined_s"] = r.verified.final_time;
  out["ratio"] = r.verified.final_time / duration(candidate);
  std::vector<Eigen::Vector2d> before, after;
  for (const auto& s : candidate.samples) before.emplace_back(s.x, s.y);
  for (const auto& s : r.verified.trajectory.samples) after.emplace_back(s.x, s.y);
  // Both closed at the exact start and goal: the candidate may stop anywhere in the goal region.
  const Eigen::Vector2d& from = w.problem.start.position;
  const Eigen::Vector2d& to = w.problem.goal.position;
  out["class_kept"] =
      frames.signatureBetween(from, before, to) == frames.signatureBetween(from, after, to);
  search::CheckTolerances tolerances;
  tolerances.relative = 1e-3;
  const search::CheckReport check =
      search::TrajectoryChecker(w.problem, tolerances).check(r.verified.trajectory);
  out["check_ok"] = check.ok();
  nlohmann::json violations = nlohmann::json::array();
  for (const search::CheckViolation& v : check.violations) {
    violations.push_back({{"limit", v.limit}, {"amount", jsonNumber(v.amount)}});
  }
  out["violations"] = violations;
  return out;
}

class RefineSuite final : public BenchmarkSuite {
 public:
  explicit RefineSuite(const BenchmarkSettings& settings) : settings_(settings) {}

  std::string name() const override { return "refine"; }

  std::vector<BenchmarkCase> cases() const override {
    std::vector<BenchmarkCase> out;
    for (const char* planner : kPlanners) {
      for (const auto& [kind_name, kind] : kKinds) {
        for (int k = 0; k < settings_.seeds; ++k) {
          const std::uint64_t seed = settings_.seed + static_cast<std::uint64_t>(k);
          const std::string id =
              std::string(planner) + "/" + kind_name + "/seed" + std::to_string(seed);
          out.push_back(
              {id, [this, planner = std::string(planner), kind_name = std::string(kind_name),
                    kind = kind, seed] { return run(planner, kind_name, kind, seed); }});
        }
      }
    }
    return out;
  }

  nlohmann::json summarize(const nlohmann::json& rows) const override {
    std::map<std::string, std::vector<double>> ratios, times, iterations;
    std::vector<double> all, bound, all_times;
    int candidates = 0, converged = 0, kept = 0, checked = 0;
    for (const nlohmann::json& row : rows) {
      for (const nlohmann::json& c : row.value("candidates", nlohmann::json::array())) {
        ++candidates;
        // Time and iterations of every refinement, converged or not (the time was spent).
        const std::string planner = row.value("planner", "");
        times[planner].push_back(c.value("refine_ms", 0.0));
        all_times.push_back(c.value("refine_ms", 0.0));
        iterations[planner].push_back(c.value("iterations", 0.0));
        if (c.value("status", "") != "converged") continue;
        ++converged;
        kept += c.value("class_kept", false);
        checked += c.value("check_ok", false);
        ratios[row.value("planner", "")].push_back(c["ratio"].get<double>());
        all.push_back(c["ratio"].get<double>());
        bound.push_back(c["refined_s"].get<double>() / c["lower_bound_s"].get<double>());
      }
    }
    nlohmann::json by_planner = nlohmann::json::object();
    for (auto& [planner, values] : ratios) by_planner[planner] = distributionJson(values);
    nlohmann::json ms_by_planner = nlohmann::json::object();
    for (auto& [planner, values] : times) ms_by_planner[planner] = distributionJson(values);
    nlohmann::json iterations_by_planner = nlohmann::json::object();
    for (auto& [planner, values] : iterations) {
      iterations_by_planner[planner] = distributionJson(values);
    }
    return {{"candidates", candidates},
            {"converged", converged},
            {"class_kept", kept},
            {"check_ok", checked},
            {"refined_over_candidate", distributionJson(all)},
            {"refined_over_lower_bound", distributionJson(bound)},
            {"by_planner", by_planner},
            {"refine_ms", distributionJson(all_times)},
            {"refine_ms_by_planner", ms_by_planner},
            {"iterations_by_planner", iterations_by_planner}};
  }

  std::string summaryText(const nlohmann::json& summary) const override {
    std::ostringstream text;
    text << "refinements: " << summary["converged"] << " of " << summary["candidates"]
         << " converged, " << summary["class_kept"] << " kept their class, " << summary["check_ok"]
         << " pass the independent check\n"
         << "refined / candidate time: mean "
         << figureText(summary["refined_over_candidate"], "mean") << '\n';
    for (const auto& [planner, d] : summary["by_planner"].items()) {
      text << "  " << planner << ": mean " << figureText(d, "mean") << " (" << d["count"]
           << " refinements)\n";
    }
    text << "time a refinement [ms]: median " << figureText(summary["refine_ms"], "median")
         << ", p90 " << figureText(summary["refine_ms"], "p90") << '\n';
    for (const auto& [planner, d] : summary["refine_ms_by_planner"].items()) {
      text << "  " << planner << ": median " << figureText(d, "median") << " ms, "
           << figureText(summary["iterations_by_planner"][planner], "median")
           << " Ipopt iterations (median)\n";
    }
    return text.str();
  }

 private:
  nlohmann::json run(const std::string& planner, const std::string& kind_name,
                     terrain::TerrainKind kind, std::uint64_t seed) const {
    const int size = settings_.quick ? 96 : 256;
    const double budget = settings_.quick ? 0.3 : 1.0;
    nlohmann::json row = {{"planner", planner},    {"kind", kind_name},  {"seed", seed},
                          {"map_cells", size},     {"vehicle", "point"}, {"budget_s", budget},
                          {"time_dependent", true}};
    bench::BenchmarkWorld w(bench::generateBenchmarkMap(kind, size, seed),
                            bench::BenchmarkVehicle::kPoint, bench::benchmarkLimits(kPitchMaxDeg));
    const auto [start, goal] = terrain::standardStartGoal(w.map.geometry());
    if (!w.place(start, goal)) {
      row["status"] = "no start / goal on moderate ground";
      return row;
    }
    ocp::BoundaryValueProblem bvp;
    bvp.start = {w.problem.start.position.x(), w.problem.start.position.y(), 0.0, 0.0, 0.0};
    bvp.goal = {w.problem.goal.position.x(), w.problem.goal.position.y(), 0.0, 0.0, 0.0};
    bvp.limits = w.problem.limits;
    search::ReferenceFrameOptions frame_options;
    frame_options.anchor = {0.5 * w.map.geometry().width(), 0.5 * w.map.geometry().height()};
    const search::ReferenceFrames frames =
        search::ReferenceFrames::build(w.map, terrain::findObstacleClusters(w.map), frame_options);
    const refine::CandidateRefiner refiner(w.problem, bvp, frames);
    const std::vector<models::Trajectory> found = plan(planner, w.problem, seed, budget);
    row["status"] = found.empty() ? "no candidate" : "done";
    row["candidates"] = nlohmann::json::array();
    for (std::size_t k = 0; k < found.size(); ++k) {
      const std::string name =
          planner + "_" + kind_name + "_seed" + std::to_string(seed) + "_" + std::to_string(k);
      row["candidates"].push_back(refineOne(w, refiner, frames, found[k], name));
    }
    return row;
  }

  BenchmarkSettings settings_;
};

}  // namespace

std::unique_ptr<BenchmarkSuite> makeRefineSuite(const BenchmarkSettings& settings) {
  return std::make_unique<RefineSuite>(settings);
}

}  // namespace terratraj::bench
