#include "terratraj/apps/verdict_json.hpp"

#include "terratraj/bench/report_json.hpp"
#include "terratraj/ocp/solution_verdict.hpp"

namespace terratraj::apps {

using bench::jsonNumber;

nlohmann::json checkReportJson(const models::CheckReport& check) {
  nlohmann::json violations = nlohmann::json::array();
  nlohmann::json violated = nlohmann::json::array();
  for (const models::CheckViolation& v : check.violations) {
    violations.push_back({{"limit", v.limit},
                          {"amount", jsonNumber(v.amount)},
                          {"value", jsonNumber(v.value)},
                          {"bound", jsonNumber(v.bound)},
                          {"row", v.sample + 1},
                          {"t", jsonNumber(v.t)}});
    violated.push_back(v.limit);
  }
  return {{"ok", check.ok()},
          {"constraint_violation", check.max_violation},
          {"violated_limits", violated},
          {"violations", violations}};
}

nlohmann::json verdictJson(const models::TrajectoryVerdict& verdict, bool checked) {
  if (!checked) {
    return {{"check", nullptr}, {"constraint_violation", nullptr}, {"violated_limit", nullptr}};
  }
  const auto [amount, limit] = ocp::largestLimitViolation(verdict.check);
  return {{"check", checkReportJson(verdict.check)},
          {"constraint_violation", amount},
          {"violated_limit", limit.empty() ? nlohmann::json(nullptr) : nlohmann::json(limit)}};
}

}  // namespace terratraj::apps
