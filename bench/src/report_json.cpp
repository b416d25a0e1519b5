#include "terratraj/bench/report_json.hpp"

#include "terratraj/ocp/solve_result.hpp"

namespace terratraj::bench {

nlohmann::json attemptsJson(const std::vector<refine::SeedAttempt>& attempts) {
  nlohmann::json rows = nlohmann::json::array();
  for (const refine::SeedAttempt& a : attempts) {
    rows.push_back({{"seed", a.seed},
                    {"method", a.method},
                    {"status", ocp::solveStatusName(a.status)},
                    {"reason", a.reason},
                    {"cost", jsonNumber(a.cost)},
                    {"time_ms", a.time_ms},
                    {"budget_s", jsonNumber(a.budget_s)},
                    {"time_given_s", jsonNumber(a.time_given_s)},
                    {"round", a.round},
                    {"time_limit_reached", a.time_limit_reached}});
  }
  return rows;
}

}  // namespace terratraj::bench
