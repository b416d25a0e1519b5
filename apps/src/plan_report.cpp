// The plan report (planReportJson, plan_command.hpp): the contract's keys, every solution with
// its independent check, rejected solutions, the planner's statistics and cost history.

#include <algorithm>

#include "terratraj/apps/plan_command.hpp"
#include "terratraj/apps/verdict_json.hpp"
#include "terratraj/bench/report_json.hpp"

namespace terratraj::apps {

using bench::jsonNumber;

nlohmann::json planReportJson(const search::PlanResult& result, const PlanReportInfo& info) {
  nlohmann::json history = nlohmann::json::array();
  for (const search::CostSample& sample : result.cost_history) {
    history.push_back({{"time_ms", sample.time_ms}, {"cost_s", sample.cost_s}});
  }
  const auto fileAt = [&info](std::size_t k) {
    return k < info.files.size() ? nlohmann::json(info.files[k].string()) : nlohmann::json(nullptr);
  };
  const auto checkJson = [&info](std::size_t k) {
    return k < info.checks.size() ? checkReportJson(info.checks[k]) : nlohmann::json(nullptr);
  };
  nlohmann::json solutions = nlohmann::json::array();
  for (std::size_t k = 0; k < result.solutions.size(); ++k) {
    const search::PlanSolution& s = result.solutions[k];
    solutions.push_back({{"cost_s", jsonNumber(s.cost_s)},
                         {"length_m", jsonNumber(s.length_m)},
                         {"homotopy", s.homotopy},
                         {"file", fileAt(k)},
                         {"search_cost_s", jsonNumber(s.search_cost_s)},
                         {"proven_optimal", s.proven_optimal},
                         {"found_ms", s.found_ms},
                         {"check", checkJson(k)}});
  }
  nlohmann::json rejected = nlohmann::json::array();
  for (const search::RejectedSolution& r : result.rejected) {
    rejected.push_back(
        {{"cost_s", jsonNumber(r.cost_s)}, {"homotopy", r.homotopy}, {"reason", r.reason}});
  }
  const search::PlanStatistics& st = result.statistics;
  nlohmann::json statistics{{"iterations", st.iterations},
                            {"attempts", st.attempts},
                            {"trapped", st.trapped},
                            {"pruned", st.pruned},
                            {"goal_attempts", st.goal_attempts},
                            {"goal_connections", st.goal_connections},
                            {"improvements", st.improvements},
                            {"pruned_nodes", st.pruned_nodes}};
  if (info.planner != "prm") {
    const search::SearchStatistics& ss = result.search;
    statistics = {{"expansions", ss.expansions},
                  {"generated", ss.generated},
                  {"edge_evaluations", ss.edge_evaluations},
                  {"invalid_edges", ss.invalid_edges},
                  {"cache_hits", ss.cache_hits},
                  {"rounds", ss.rounds},
                  {"final_epsilon", ss.final_epsilon},
                  {"homotopy_classes", ss.homotopy_classes},
                  {"frames", ss.frames},
                  {"pruned_signatures", ss.pruned_signatures}};
  }
  nlohmann::json json{
      {"status", search::planStatusName(result.status)},
      {"planner", info.planner},
      {"time_limit_s", info.time_limit_s},
      {"first_solution_ms", result.first_solution_ms ? nlohmann::json(*result.first_solution_ms)
                                                     : nlohmann::json(nullptr)},
      {"planning_time_ms", result.planning_time_ms},
      {"nodes", result.nodes},
      {"trapped_fraction", result.trappedFraction()},
      {"solutions", solutions},
      {"rejected_solutions", rejected},
      {"seed", info.seed},
      {"reason", result.reason},
      {"best_cost_s", jsonNumber(result.best_cost_s)},
      {"first_solution_cost_s", jsonNumber(result.first_solution_cost_s)},
      {"statistics", statistics},
      {"cost_history", history},
  };
  if (!info.checks.empty()) {
    double worst = 0.0;
    nlohmann::json violated = nlohmann::json::array();
    for (const search::CheckReport& check : info.checks) {
      worst = std::max(worst, check.max_violation);
      for (const search::CheckViolation& v : check.violations) {
        if (std::find(violated.begin(), violated.end(), v.limit) == violated.end()) {
          violated.push_back(v.limit);
        }
      }
    }
    json["constraint_violation"] = worst;
    json["violated_limits"] = violated;
  }
  for (const auto& [key, value] : info.extra.items()) json[key] = value;
  return json;
}

}  // namespace terratraj::apps
