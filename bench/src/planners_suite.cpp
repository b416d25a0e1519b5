// `terratraj bench planners`: the Kobilarov experiments (001_... V.A, figs. 6-7) and the
// lattice searches on the same problems: first-solution time, cost at 1 s and at the budget,
// for the kinodynamic PRM; first solution and best cost of ARA*; TAEASL's classes. Every final
// trajectory is re-checked independently (search::TrajectoryChecker).

#include <cmath>
#include <iomanip>
#include <limits>
#include <sstream>
#include <tuple>

#include "terratraj/bench/benchmark_suite.hpp"
#include "terratraj/bench/benchmark_world.hpp"
#include "terratraj/bench/ompl_peer.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/search/bang_bang_bound.hpp"
#include "terratraj/search/kinodynamic_prm.hpp"
#include "terratraj/search/lattice_graph.hpp"
#include "terratraj/search/lattice_planner.hpp"
#include "terratraj/search/primitive_generator.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/search/trajectory_checker.hpp"

namespace terratraj::bench {
namespace {

using terrain::TerrainKind;

// One planning problem of an experiment.
struct Variant {
  std::string experiment;  // "environment" (fig. 6) or "expansiveness" (fig. 7)
  TerrainKind kind;
  int size;
  double pitch_max_deg;
};

std::vector<Variant> variants(bool quick) {
  std::vector<Variant> out;
  const std::vector<TerrainKind> kinds =
      quick ? std::vector<TerrainKind>{TerrainKind::kHills, TerrainKind::kCorridor}
            : std::vector<TerrainKind>{TerrainKind::kHills, TerrainKind::kCorridor,
                                       TerrainKind::kObstacles, TerrainKind::kDeadEnd};
  const std::vector<int> sizes =
      quick ? std::vector<int>{128} : std::vector<int>{128, 256, 512, 1024};
  for (const TerrainKind kind : kinds) {
    for (const int size : sizes) out.push_back({"environment", kind, size, 17.0});
  }
  // 256 x 256 maps of growing difficulty (the trapped fraction measures it).
  const std::vector<std::tuple<TerrainKind, double>> difficulty{
      {TerrainKind::kFlat, 17.0},      {TerrainKind::kHills, 17.0},
      {TerrainKind::kHills, 12.0},     {TerrainKind::kHills, 9.0},
      {TerrainKind::kForest, 17.0},    {TerrainKind::kObstacles, 17.0},
      {TerrainKind::kCorridor, 17.0},  {TerrainKind::kDeadEnd, 17.0},
      {TerrainKind::kObstacles, 12.0}, {TerrainKind::kDeadEnd, 12.0}};
  const std::size_t count = quick ? 2 : difficulty.size();
  for (std::size_t i = 0; i < count; ++i) {
    out.push_back({"expansiveness", std::get<0>(difficulty[i]), quick ? 128 : 256,
                   std::get<1>(difficulty[i])});
  }
  return out;
}

// Cost at `ms` into a run: the last improvement before it (null before the first).
nlohmann::json costAt(const search::PlanResult& result, double ms) {
  double cost = std::numeric_limits<double>::infinity();
  for (const search::CostSample& sample : result.cost_history) {
    if (sample.time_ms <= ms) cost = sample.cost_s;
  }
  return jsonNumber(cost);
}

// The independent re-check: a trajectory's limits by search::TrajectoryChecker (relative
// tolerance 1e-3); the violations named when there are any.
search::CheckReport check(const search::PlanningProblem& problem, const models::Trajectory& t) {
  search::CheckTolerances tolerances;
  tolerances.relative = 1e-3;
  return search::TrajectoryChecker(problem, tolerances).check(t);
}
void addCheck(nlohmann::json& row, const search::PlanningProblem& problem,
              const models::Trajectory& t) {
  const search::CheckReport report = check(problem, t);
  row["check_ok"] = report.ok();
  if (report.ok()) return;
  nlohmann::json violations = nlohmann::json::array();
  for (const search::CheckViolation& v : report.violations) {
    violations.push_back(
        {{"limit", v.limit}, {"amount", jsonNumber(v.amount)}, {"sample", v.sample}});
  }
  row["violations"] = violations;
}

nlohmann::json prmRow(const bench::BenchmarkWorld& w, std::uint64_t seed, double budget_s) {
  search::PrmOptions options;
  options.seed = seed;
  search::KinodynamicPrm planner(w.problem, options);
  const search::PlanResult r = planner.solve(search::TerminationCondition::timeLimit(budget_s));
  nlohmann::json row = {{"status", search::planStatusName(r.status)},
                        {"first_ms", r.first_solution_ms ? jsonNumber(*r.first_solution_ms)
                                                         : nlohmann::json(nullptr)},
                        {"first_cost_s", jsonNumber(r.first_solution_cost_s)},
                        {"cost_1s", costAt(r, 1000.0)},
                        {"cost_10s", costAt(r, 10000.0)},
                        {"cost_final_s", jsonNumber(r.best_cost_s)},
                        {"budget_s", budget_s},
                        {"time_dependent", true},
                        {"trapped_fraction", r.trappedFraction()},
                        {"nodes", r.nodes}};
  row["cost_history"] = nlohmann::json::array();
  for (const search::CostSample& s : r.cost_history) {
    row["cost_history"].push_back({jsonNumber(s.time_ms), jsonNumber(s.cost_s)});
  }
  if (r.status == search::PlanStatus::kSolved) addCheck(row, w.problem, r.trajectory);
  return row;
}

// An OMPL peer on the same problem, through the same interface and verdict as the PRM; its
// solution re-checked like the PRM's. cost_1s comes from OMPL's control durations;
// cost_final_s is the re-integrated trajectory's duration. `status` is OMPL's own text,
// `solved` the verdict's (rejected solutions listed with their reason).
nlohmann::json omplRow(const bench::BenchmarkWorld& w, OmplPlanner kind, std::uint64_t seed,
                       double budget_s) {
  OmplPeerPlanner planner(w.problem, kind, seed);
  const search::PlanResult r = planner.solve(search::TerminationCondition::timeLimit(budget_s));
  const bool solved = r.status == search::PlanStatus::kSolved;
  nlohmann::json row = {{"status", planner.omplStatus()},
                        {"solved", solved},
                        {"first_ms", r.first_solution_ms ? jsonNumber(*r.first_solution_ms)
                                                         : nlohmann::json(nullptr)},
                        {"planning_ms", r.planning_time_ms},
                        {"budget_s", budget_s},
                        {"time_dependent", true}};
  row["cost_1s"] = costAt(r, 1000.0);
  row["cost_final_s"] = solved ? jsonNumber(r.best_cost_s) : nlohmann::json(nullptr);
  if (!r.rejected.empty()) row["rejected"] = r.rejected.front().reason;
  if (solved) addCheck(row, w.problem, r.trajectory);
  return row;
}

const search::PrimitiveSet& primitives() {
  static const search::PrimitiveSet set =
      search::generatePrimitives(search::LatticeSpec{}, bench::benchmarkLimits()).set;
  return set;
}

nlohmann::json latticeRows(const bench::BenchmarkWorld& w, double budget_s) {
  const search::LatticeGraph graph(w.problem, primitives());
  if (graph.error()) return {{"status", "error"}, {"reason", *graph.error()}};
  nlohmann::json out;
  search::LatticePlanner ara(graph);
  const search::PlanResult a = ara.solve(search::TerminationCondition::timeLimit(budget_s));
  out["ara"] = {{"status", search::planStatusName(a.status)},
                {"first_ms",
                 a.first_solution_ms ? jsonNumber(*a.first_solution_ms) : nlohmann::json(nullptr)},
                {"first_cost_s", jsonNumber(a.first_solution_cost_s)},
                {"best_cost_s", jsonNumber(a.best_cost_s)},
                {"planning_ms", a.planning_time_ms},
                {"time_dependent", true},
                {"expansions", a.search.expansions}};
  if (a.status == search::PlanStatus::kSolved) addCheck(out["ara"], w.problem, a.trajectory);
  search::TaeaslPlanner taeasl(graph);
  const search::PlanResult t = taeasl.solve(search::TerminationCondition::timeLimit(budget_s));
  nlohmann::json classes = nlohmann::json::array();
  bool all_ok = true;
  for (const search::PlanSolution& s : t.solutions) {
    classes.push_back({{"cost_s", jsonNumber(s.cost_s)}, {"found_ms", jsonNumber(s.found_ms)}});
    all_ok = all_ok && check(w.problem, s.trajectory).ok();
  }
  out["taeasl"] = {{"status", search::planStatusName(t.status)},
                   {"classes", classes},
                   {"planning_ms", t.planning_time_ms},
                   {"time_dependent", true},
                   {"check_ok", all_ok}};
  return out;
}

// A median as a short column ("-" when there is none).
std::string brief(const nlohmann::json& medians, const char* key) {
  std::ostringstream text;
  text << std::setprecision(4);
  if (medians.contains(key) && medians[key].is_number()) {
    text << medians[key].get<double>();
  } else {
    text << "-";
  }
  std::string s = text.str();
  return s + std::string(s.size() < 12 ? 13 - s.size() : 1, ' ');
}

class PlannersSuite final : public BenchmarkSuite {
 public:
  explicit PlannersSuite(const BenchmarkSettings& settings) : settings_(settings) {}

  std::string name() const override { return "planners"; }

  std::vector<BenchmarkCase> cases() const override {
    std::vector<BenchmarkCase> out;
    for (const Variant& v : variants(settings_.quick)) {
      for (int k = 0; k < settings_.seeds; ++k) {
        const std::uint64_t seed = settings_.seed + static_cast<std::uint64_t>(k);
        std::ostringstream id;
        id << v.experiment << "/" << terrain::terrainKindName(v.kind) << "/" << v.size << "/pitch"
           << v.pitch_max_deg << "/seed" << seed;
        out.push_back({id.str(), [this, v, seed] { return run(v, seed); }});
      }
    }
    return out;
  }

  nlohmann::json summarize(const nlohmann::json& rows) const override {
    // Per experiment and variant (kind, size, pitch): medians over the seeds.
    std::map<std::string, std::map<std::string, std::vector<double>>> groups;
    for (const nlohmann::json& row : rows) {
      if (!row.contains("prm")) continue;
      std::ostringstream key;
      key << row["experiment"].get<std::string>() << "/" << row["kind"].get<std::string>() << "/"
          << row["size"] << "/pitch" << row["pitch_max_deg"];
      auto& g = groups[key.str()];
      const nlohmann::json& prm = row["prm"];
      auto push = [&g](const char* name, const nlohmann::json& value) {
        if (value.is_number()) g[name].push_back(value.get<double>());
      };
      push("prm_first_ms", prm["first_ms"]);
      push("prm_first_cost_s", prm["first_cost_s"]);
      push("prm_cost_1s", prm["cost_1s"]);
      push("prm_cost_final_s", prm["cost_final_s"]);
      push("trapped_fraction", prm["trapped_fraction"]);
      push("lower_bound_s", row["lower_bound_s"]);
      if (row.contains("lattice") && row["lattice"].contains("ara")) {
        push("ara_first_ms", row["lattice"]["ara"]["first_ms"]);
        push("ara_best_cost_s", row["lattice"]["ara"]["best_cost_s"]);
      }
      for (const char* peer : {"ompl_rrt", "ompl_sst"}) {
        if (!row.contains(peer)) continue;
        push((std::string(peer) + "_first_ms").c_str(), row[peer]["first_ms"]);
        push((std::string(peer) + "_cost_1s").c_str(), row[peer]["cost_1s"]);
        push((std::string(peer) + "_cost_final_s").c_str(), row[peer]["cost_final_s"]);
        g[std::string(peer) + "_solved"].push_back(row[peer]["solved"].get<bool>() ? 1.0 : 0.0);
      }
      if (row.contains("lattice") && row["lattice"].contains("taeasl")) {
        g["taeasl_classes"].push_back(
            static_cast<double>(row["lattice"]["taeasl"]["classes"].size()));
      }
    }
    nlohmann::json out = nlohmann::json::object();
    // Peers against the PRM, per variant (medians) and over all variants (geometric means):
    // time to the first solution, and cost at equal time (1 s, and the budget).
    std::map<std::string, std::vector<double>> ratios;
    for (auto& [key, values] : groups) {
      for (auto& [name, v] : values) {
        const nlohmann::json d = distributionJson(v);
        const bool fraction = name.size() > 7 && name.compare(name.size() - 7, 7, "_solved") == 0;
        out[key][name] =
            d.contains("median") ? d[fraction ? "mean" : "median"] : nlohmann::json(nullptr);
      }
      const nlohmann::json& m = out[key];
      const auto ratio = [&m, &ratios](const std::string& name, const std::string& peer,
                                       const std::string& prm) {
        if (m.contains(peer) && m.contains(prm) && m[peer].is_number() && m[prm].is_number() &&
            m[prm].get<double>() > 0.0) {
          ratios[name].push_back(m[peer].get<double>() / m[prm].get<double>());
        }
      };
      for (const std::string peer : {"ompl_rrt", "ompl_sst", "ara"}) {
        ratio(peer + "_first_ms_over_prm", peer + "_first_ms", "prm_first_ms");
      }
      ratio("ompl_sst_cost_1s_over_prm", "ompl_sst_cost_1s", "prm_cost_1s");
      ratio("ompl_sst_cost_final_over_prm", "ompl_sst_cost_final_s", "prm_cost_final_s");
      ratio("ompl_rrt_cost_over_prm_first", "ompl_rrt_cost_final_s", "prm_first_cost_s");
    }
    nlohmann::json peers = nlohmann::json::object();
    for (const auto& [name, v] : ratios) {
      double log_sum = 0.0;
      for (const double r : v) log_sum += std::log(r);
      peers[name] = {{"geometric_mean", std::exp(log_sum / static_cast<double>(v.size()))},
                     {"variants", v.size()}};
    }
    nlohmann::json summary{{"median_by_variant", out}, {"peers_over_prm", peers}};
    if (!omplPeersAvailable()) {
      summary["ompl_peers"] = "unavailable (built with -DTERRATRAJ_WITH_OMPL=OFF)";
    }
    return summary;
  }

  std::string summaryText(const nlohmann::json& summary) const override {
    std::ostringstream text;
    text << "variant (medians)                        PRM first ms cost 1 s [s] final [s]    "
            "ARA* first ms ARA* cost [s] trapped\n";
    for (const auto& [key, m] : summary["median_by_variant"].items()) {
      text << key << std::string(key.size() < 40 ? 41 - key.size() : 1, ' ')
           << brief(m, "prm_first_ms") << brief(m, "prm_cost_1s") << brief(m, "prm_cost_final_s")
           << brief(m, "ara_first_ms") << brief(m, "ara_best_cost_s")
           << brief(m, "trapped_fraction") << '\n';
    }
    if (summary.contains("ompl_peers")) {
      text << "OMPL peers: " << summary["ompl_peers"].get<std::string>() << '\n';
    }
    text << "peers / PRM (geometric mean over variants):\n";
    for (const auto& [name, r] : summary["peers_over_prm"].items()) {
      text << "  " << name << " " << r["geometric_mean"].get<double>() << " (" << r["variants"]
           << " variants)\n";
    }
    return text.str();
  }

 private:
  nlohmann::json run(const Variant& v, std::uint64_t seed) const {
    const double budget =
        settings_.quick ? std::min(settings_.time_limit_s, 0.5) : settings_.time_limit_s;
    nlohmann::json row = {{"experiment", v.experiment},
                          {"kind", terrain::terrainKindName(v.kind)},
                          {"size", v.size},
                          {"pitch_max_deg", v.pitch_max_deg},
                          {"seed", seed}};
    bench::BenchmarkWorld w(bench::generateBenchmarkMap(v.kind, v.size, seed),
                            bench::BenchmarkVehicle::kPoint,
                            bench::benchmarkLimits(v.pitch_max_deg));
    const auto [start, goal] = terrain::standardStartGoal(w.map.geometry());
    if (!w.place(start, goal)) {
      row["status"] = "no start / goal on moderate ground";
      return row;
    }
    row["status"] = "done";
    row["distance_m"] = w.distance();
    row["lower_bound_s"] = w.lowerBoundTime();
    row["prm"] = prmRow(w, seed, budget);
    row["lattice"] = latticeRows(w, std::min(budget, 1.0));
    if (omplPeersAvailable()) {
      for (const OmplPlanner peer : {OmplPlanner::kRrt, OmplPlanner::kSst}) {
        row[omplPlannerName(peer)] = omplRow(w, peer, seed, budget);
      }
    }
    return row;
  }

  BenchmarkSettings settings_;
};

}  // namespace

std::unique_ptr<BenchmarkSuite> makePlannersSuite(const BenchmarkSettings& settings) {
  return std::make_unique<PlannersSuite>(settings);
}

}  // namespace terratraj::bench
