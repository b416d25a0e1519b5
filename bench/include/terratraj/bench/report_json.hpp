#pragma once
// The JSON forms the benchmark suites and the CLI's reports share: a number (JSON has no NaN or
// infinity: such values, an unknown figure or a clearance on a map without obstacles, are
// written as null) and the attempts of a seeded solve. The bench library is the lowest layer
// that writes JSON reports; apps' reports use these too.

#include <cmath>
#include <vector>

#include <nlohmann/json.hpp>

#include "terratraj/refine/seeded_solver.hpp"

namespace terratraj::bench {

/// `value`, or null when it is not finite.
inline nlohmann::json jsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

/// A seeded solve's `attempts`: per seed tried, seed, method, status, reason, verified cost
/// (null without a re-simulation), time_ms.
nlohmann::json attemptsJson(const std::vector<refine::SeedAttempt>& attempts);

}  // namespace terratraj::bench
