#include "terratraj/refine/refinement_options.hpp"

#include <array>
#include <cmath>
#include <utility>

#include "format_number.hpp"

namespace terratraj::refine {
namespace {

constexpr std::array<std::pair<RefineMethod, const char*>, 5> kMethodNames{{
    {RefineMethod::kAuto, "auto"},
    {RefineMethod::kCollocation, "collocation"},
    {RefineMethod::kShooting, "shooting"},
    {RefineMethod::kNewton, "newton"},
    {RefineMethod::kIpopt, "ipopt"},
}};

using detail::formatNumber;

}  // namespace

const char* refineMethodName(RefineMethod method) {
  for (const auto& [m, name] : kMethodNames) {
    if (m == method) return name;
  }
  return "?";
}

std::optional<RefineMethod> parseRefineMethod(std::string_view name) {
  for (const auto& [m, text] : kMethodNames) {
    if (name == text) return m;
  }
  return std::nullopt;
}

std::vector<std::string> refineMethodNames() {
  std::vector<std::string> names;
  for (const auto& entry : kMethodNames) names.emplace_back(entry.second);
  return names;
}

std::optional<std::string> validateRefinementOptions(const RefinementOptions& o) {
  if (!(o.interval_length_m > 0.0) || !std::isfinite(o.interval_length_m)) {
    return "interval_length_m must be a finite number > 0 (got " +
           formatNumber(o.interval_length_m) + ")";
  }
  if (o.min_intervals < 1) return "min_intervals must be >= 1";
  if (o.max_intervals < o.min_intervals) return "max_intervals must be >= min_intervals";
  if (!(o.min_clearance_m >= 0.0) || !std::isfinite(o.min_clearance_m)) {
    return "min_clearance_m must be a finite number >= 0 (got " + formatNumber(o.min_clearance_m) +
           ")";
  }
  if (!(o.guess_spacing_m > 0.0)) return "guess_spacing_m must be > 0";
  if (!(o.worse_tolerance >= 0.0) || !std::isfinite(o.worse_tolerance)) {
    return "worse_tolerance must be a finite number >= 0";
  }
  if (!(o.endpoint_tolerance_m > 0.0) || !std::isfinite(o.endpoint_tolerance_m)) {
    return "endpoint_tolerance_m must be a finite number > 0";
  }
  if (o.time_limit_s && !(*o.time_limit_s >= 0.0)) return "time_limit_s must be >= 0";
  if (o.margin_retries < 0) return "margin_retries must be >= 0";
  if (!(o.shortcut_clearance_m >= 0.0) || !std::isfinite(o.shortcut_clearance_m)) {
    return "shortcut_clearance_m must be a finite number >= 0";
  }
  if (!(o.shortcut_gain > 0.0 && o.shortcut_gain <= 1.0)) return "shortcut_gain must be in (0, 1]";
  if (!(o.warm_start_time_ratio >= 1.0)) return "warm_start_time_ratio must be >= 1";
  if (!(o.corridor_radius_m >= 0.0) || !std::isfinite(o.corridor_radius_m)) {
    return "corridor_radius_m must be a finite number >= 0 (got " +
           formatNumber(o.corridor_radius_m) + ")";
  }
  if (!(o.coarse_interval_length_m > 0.0) || !std::isfinite(o.coarse_interval_length_m)) {
    return "coarse_interval_length_m must be a finite number > 0 (got " +
           formatNumber(o.coarse_interval_length_m) + ")";
  }
  if (!(o.speed_margin >= 0.0 && o.speed_margin < 0.5)) {
    return "speed_margin must be in [0, 0.5) (got " + formatNumber(o.speed_margin) + ")";
  }
  if (!(o.limit_margin >= 0.0 && o.limit_margin < 0.5)) {
    return "limit_margin must be in [0, 0.5) (got " + formatNumber(o.limit_margin) + ")";
  }
  return ocp::validateTranscriptionOptions(o.transcription);
}

RefineMethod chooseRefineMethod(const RefinementOptions& options, double length_m,
                                double min_clearance_m, int curvature_sign_changes,
                                std::string& rule) {
  if (options.method != RefineMethod::kAuto) {
    rule = "as configured";
    return options.method;
  }
  if (length_m > options.parametric_max_length_m) {
    rule = "collocation: the candidate is " + formatNumber(length_m) +
           " m long (polynomial controls up to " + formatNumber(options.parametric_max_length_m) +
           " m)";
    return RefineMethod::kCollocation;
  }
  if (min_clearance_m < options.parametric_min_clearance_m) {
    rule = "collocation: the candidate passes " + formatNumber(min_clearance_m) +
           " m from impassable cells (polynomial controls need " +
           formatNumber(options.parametric_min_clearance_m) +
           " m: they have no clearance constraint)";
    return RefineMethod::kCollocation;
  }
  if (curvature_sign_changes > options.parametric_max_curvature_sign_changes) {
    rule = "collocation: the candidate's curvature changes sign " +
           std::to_string(curvature_sign_changes) + " times (the yaw-rate polynomial " +
           "follows at most " + std::to_string(options.parametric_max_curvature_sign_changes) + ")";
    return RefineMethod::kCollocation;
  }
  rule = "ipopt (polynomial controls): short (" + formatNumber(length_m) +
         " m), clear of obstacles (" + formatNumber(min_clearance_m) + " m) and few turns (" +
         std::to_string(curvature_sign_changes) + " curvature sign changes)";
  return RefineMethod::kIpopt;
}

}  // namespace terratraj::refine
