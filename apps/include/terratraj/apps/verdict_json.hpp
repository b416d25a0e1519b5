#pragma once
// The verdict (models::judgeTrajectory) and the independent check in the reports' JSON.

#include <nlohmann/json.hpp>

#include "terratraj/models/trajectory_checker.hpp"
#include "terratraj/models/trajectory_verdict.hpp"

namespace terratraj::apps {

/// An independent re-check: {ok, constraint_violation, violated_limits, violations: [{limit,
/// amount, value, bound, row (CSV data row from 1), t}]}.
nlohmann::json checkReportJson(const models::CheckReport& check);

/// The verdict's keys of a solve / refine report: check (checkReportJson), constraint_violation
/// (the largest limit, table or map violation, in the limit's units; goal errors excluded) and
/// violated_limit (its name, or null). With `checked` false (nothing to check), nulls.
nlohmann::json verdictJson(const models::TrajectoryVerdict& verdict, bool checked);

}  // namespace terratraj::apps
