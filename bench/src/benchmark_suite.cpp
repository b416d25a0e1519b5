#include "terratraj/bench/benchmark_suite.hpp"

#include <sstream>

#include <algorithm>
#include <cmath>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::bench {
namespace {

double percentile(const std::vector<double>& sorted, double p) {
  const double position = p * static_cast<double>(sorted.size() - 1);
  const std::size_t below = static_cast<std::size_t>(std::floor(position));
  const std::size_t above = std::min(below + 1, sorted.size() - 1);
  const double weight = position - static_cast<double>(below);
  return sorted[below] * (1.0 - weight) + sorted[above] * weight;
}

template <typename T>
T required(const nlohmann::json& json, const char* key, const std::string& source) {
  if (!json.contains(key)) throw InputError(source + ": settings." + key + " is missing");
  try {
    return json.at(key).get<T>();
  } catch (const nlohmann::json::exception&) {
    throw InputError(source + ": settings." + key + " has the wrong type");
  }
}

}  // namespace

nlohmann::json BenchmarkSettings::toJson() const {
  return {{"quick", quick},
          {"seed", seed},
          {"seeds", seeds},
          {"time_limit_s", time_limit_s},
          {"data_dir", data_dir.string()},
          {"interpolation", terrain::interpolationName(interpolation)}};
}

BenchmarkSettings BenchmarkSettings::fromJson(const nlohmann::json& json,
                                              const std::string& source) {
  if (!json.is_object()) throw InputError(source + ": settings is not an object");
  BenchmarkSettings s;
  s.quick = required<bool>(json, "quick", source);
  s.seed = required<std::uint64_t>(json, "seed", source);
  s.seeds = required<int>(json, "seeds", source);
  s.time_limit_s = required<double>(json, "time_limit_s", source);
  s.data_dir = required<std::string>(json, "data_dir", source);
  s.interpolation = terrain::Interpolation::kBicubic;
  if (json.contains("interpolation")) {
    const std::optional<terrain::Interpolation> method =
        terrain::parseInterpolation(required<std::string>(json, "interpolation", source));
    if (!method) throw InputError(source + ": settings.interpolation is not a surface's name");
    s.interpolation = *method;
  }
  return s;
}

std::vector<std::string> benchmarkSuiteNames() {
  return {"convergence", "robustness", "planners", "refine", "tables"};
}

std::unique_ptr<BenchmarkSuite> makeBenchmarkSuite(const std::string& name,
                                                   const BenchmarkSettings& settings) {
  if (settings.seeds < 1) throw InputError("--seeds must be >= 1");
  if (!(settings.time_limit_s > 0.0) || !std::isfinite(settings.time_limit_s)) {
    throw InputError("--time-limit must be a positive number of seconds");
  }
  if (name == "convergence") return makeConvergenceSuite(settings);
  if (name == "planners") return makePlannersSuite(settings);
  if (name == "refine") return makeRefineSuite(settings);
  if (name == "tables") return makeTablesSuite(settings);
  if (name == "robustness") return makeRobustnessSuite(settings);
  throw InputError("unknown benchmark suite '" + name +
                   "' (convergence, robustness, planners, refine, tables)");
}

nlohmann::json distributionJson(std::vector<double> values) {
  if (values.empty()) return {{"count", 0}};
  std::sort(values.begin(), values.end());
  double sum = 0.0;
  for (const double v : values) sum += v;
  return {{"count", values.size()},         {"median", percentile(values, 0.5)},
          {"p90", percentile(values, 0.9)}, {"min", values.front()},
          {"max", values.back()},           {"mean", sum / static_cast<double>(values.size())}};
}

std::string figureText(const nlohmann::json& distribution, const char* key) {
  if (!distribution.is_object() || !distribution.contains(key) || !distribution[key].is_number()) {
    return "n/a";
  }
  std::ostringstream text;
  text << distribution[key].get<double>();
  return text.str();
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace terratraj::bench
