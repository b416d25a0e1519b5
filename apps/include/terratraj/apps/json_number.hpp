#pragma once
// jsonNumber: a double for the JSON reports. JSON has no NaN or infinity: such values (an
// unknown figure, a clearance on a map without obstacles) are written as null.

#include <cmath>

#include <nlohmann/json.hpp>

namespace terratraj::apps {

/// `value`, or null when it is not finite.
inline nlohmann::json jsonNumber(double value) {
  return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr);
}

}  // namespace terratraj::apps
