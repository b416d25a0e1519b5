// The pieces of the commands' JSON reports that more than one command writes (report_json.hpp).

#include "terratraj/apps/report_json.hpp"

#include <cmath>

#include "terratraj/apps/verdict_json.hpp"
#include "terratraj/bench/report_json.hpp"
#include "terratraj/ocp/solution_verdict.hpp"

namespace terratraj::apps {

using bench::jsonNumber;

namespace {

// The largest limit, table or map violation of a refined trajectory, from the verdict's check
// (null before a re-simulation).
nlohmann::json refinedViolation(const refine::RefinementResult& r) {
  if (!r.refined_figures) return nullptr;
  return ocp::largestLimitViolation(r.verdict.check).first;
}

}  // namespace

nlohmann::json iterationHistoryJson(const std::vector<ocp::IterationRecord>& history,
                                    bool heading_error) {
  nlohmann::json rows = nlohmann::json::array();
  for (const ocp::IterationRecord& r : history) {
    nlohmann::json row{{"iteration", r.iteration},
                       {"terminal_error", jsonNumber(r.terminal_error)},
                       {"cost", jsonNumber(r.cost)},
                       {"lagrangian_gradient", jsonNumber(r.lagrangian_gradient)},
                       {"step", jsonNumber(r.step)}};
    if (heading_error) row["heading_error"] = jsonNumber(r.heading_error);
    rows.push_back(std::move(row));
  }
  return rows;
}

nlohmann::json verifiedTrajectoryJson(const ocp::VerifiedTrajectory& v) {
  return {
      {"final_time_s", v.ok ? jsonNumber(v.final_time) : nullptr},
      {"cost", v.ok ? jsonNumber(v.cost) : nullptr},
      {"length_m", v.ok ? jsonNumber(v.length) : nullptr},
      {"terminal_error",
       {{"position_m", v.ok ? jsonNumber(v.terminal_error.head<2>().norm()) : nullptr},
        {"heading_rad", v.ok ? jsonNumber(std::abs(v.terminal_error.z())) : nullptr}}},
      {"max_abs_pitch_rad", jsonNumber(v.max_abs_pitch)},
      {"max_abs_roll_rad", jsonNumber(v.max_abs_roll)},
      {"max_speed", jsonNumber(v.max_speed)},
      {"constraint_violation", jsonNumber(v.violation.amount)},
      {"violated_limit",
       v.violation.limit.empty() ? nlohmann::json(nullptr) : nlohmann::json(v.violation.limit)},
      {"slope_dwell_rad2_s", jsonNumber(v.slope_dwell)},
      {"verified", v.ok},
  };
}

nlohmann::json trajectoryFiguresJson(const refine::TrajectoryFigures& f) {
  return {{"cost", jsonNumber(f.cost)},
          {"duration_s", jsonNumber(f.duration_s)},
          {"length_m", jsonNumber(f.length_m)},
          {"max_abs_pitch_rad", jsonNumber(f.max_abs_pitch)},
          {"max_abs_roll_rad", jsonNumber(f.max_abs_roll)},
          {"max_speed", jsonNumber(f.max_speed)},
          {"min_clearance_m", jsonNumber(f.min_clearance_m)},
          {"constraint_violation", f.check.max_violation},
          {"check", checkReportJson(f.check)},
          {"homotopy", f.homotopy}};
}

nlohmann::json refinedSolutionJson(const refine::RefinementResult& r,
                                   const std::optional<std::filesystem::path>& file) {
  nlohmann::json json{{"status", ocp::solveStatusName(r.status)},
                      {"reason", r.reason},
                      {"cost_s", nullptr},
                      {"cost", nullptr},
                      {"file", file ? nlohmann::json(file->string()) : nlohmann::json(nullptr)},
                      {"method", refine::refineMethodName(r.method)},
                      {"method_rule", r.method_rule},
                      {"iterations", r.iterations},
                      {"solve_time_ms", r.solve_time_ms},
                      {"time_limit_reached", r.time_limit_reached},
                      {"intervals", r.intervals},
                      {"clearance_constraint_m", r.clearance_used_m},
                      {"margin_rounds", r.margin_rounds},
                      {"guess_shortcut_m", r.guess_shortcut_m},
                      {"guess_retimed_s", r.guess_retimed_s},
                      {"coarse_intervals", r.coarse_intervals},
                      {"barrier", r.warm_start ? "warm" : "adaptive"},
                      {"corridor_radius_m", r.corridor_radius_m},
                      {"homotopy", nullptr},
                      {"homotopy_kept", r.homotopy_kept},
                      {"cost_ratio", jsonNumber(r.costRatio())}};
  if (r.refined_figures) {
    json.update(trajectoryFiguresJson(*r.refined_figures));
    json["cost_s"] = jsonNumber(r.refined_figures->duration_s);
    json["constraint_violation"] = refinedViolation(r);
  }
  return json;
}

}  // namespace terratraj::apps
