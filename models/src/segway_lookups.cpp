#include "terratraj/models/segway_lookups.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>

#include <nlohmann/json.hpp>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::models {
namespace {

constexpr double kGravity = 9.81;
constexpr double kPi = 3.14159265358979323846;
constexpr double kClimbLimit = 17.0 * kPi / 180.0;

void checkAxis(const std::vector<double>& axis, const std::string& what) {
  if (axis.size() < 2) throw InputError(what + ": needs at least two grid points");
  for (std::size_t i = 0; i < axis.size(); ++i) {
    if (!std::isfinite(axis[i]) || (i > 0 && !(axis[i] > axis[i - 1]))) {
      throw InputError(what + ": grid points must be finite and increase strictly");
    }
  }
}

// Index i and fraction t with axis[i] <= x <= axis[i + 1], clamped to the grid.
std::pair<std::size_t, double> locate(const std::vector<double>& axis, double x) {
  if (!(x > axis.front())) return {0, 0.0};
  if (x >= axis.back()) return {axis.size() - 2, 1.0};
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin()) - 1;
  return {i, (x - axis[i]) / (axis[i + 1] - axis[i])};
}

double linear(const std::vector<double>& axis, const std::vector<double>& values, double x) {
  const auto [i, t] = locate(axis, x);
  return (1 - t) * values[i] + t * values[i + 1];
}

nlohmann::json readJson(const std::filesystem::path& path, const std::string& kind) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be opened for reading");
  nlohmann::json json;
  try {
    json = nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not valid JSON (" + e.what() + ")");
  }
  if (!json.is_object() || json.value("kind", std::string()) != kind) {
    throw InputError(path.string() + ": kind: expected \"" + kind + "\"");
  }
  return json;
}

std::vector<double> numbers(const nlohmann::json& json, const char* key,
                            const std::filesystem::path& path) {
  if (!json.contains(key) || !json.at(key).is_array()) {
    throw InputError(path.string() + ": " + key + ": missing or not an array");
  }
  std::vector<double> values;
  for (const nlohmann::json& v : json.at(key)) {
    if (!v.is_number()) throw InputError(path.string() + ": " + key + ": must hold numbers");
    values.push_back(v.get<double>());
  }
  return values;
}

}  // namespace

SegwayPitchResponse::SegwayPitchResponse(std::vector<double> accelerations,
                                         std::vector<double> slopes, Eigen::MatrixXd pitch)
    : accelerations_(std::move(accelerations)),
      slopes_(std::move(slopes)),
      pitch_(std::move(pitch)) {
  checkAxis(accelerations_, "pitch response: acceleration_mps2");
  checkAxis(slopes_, "pitch response: slope_rad");
  if (pitch_.rows() != static_cast<Eigen::Index>(accelerations_.size()) ||
      pitch_.cols() != static_cast<Eigen::Index>(slopes_.size()) || !pitch_.allFinite()) {
    throw InputError("pitch response: pitch_rad must be (accelerations x slopes) finite numbers");
  }
}

double SegwayPitchResponse::pitch(double acceleration, double slope) const {
  const auto [i, s] = locate(accelerations_, acceleration);
  const auto [j, t] = locate(slopes_, slope);
  const Eigen::Index r = static_cast<Eigen::Index>(i), c = static_cast<Eigen::Index>(j);
  return (1 - s) * ((1 - t) * pitch_(r, c) + t * pitch_(r, c + 1)) +
         s * ((1 - t) * pitch_(r + 1, c) + t * pitch_(r + 1, c + 1));
}

SegwaySlopeBounds::SegwaySlopeBounds(std::vector<double> slopes, std::vector<double> v_max,
                                     std::vector<double> a_max)
    : slopes_(std::move(slopes)), v_max_(std::move(v_max)), a_max_(std::move(a_max)) {
  checkAxis(slopes_, "slope bounds: slope_rad");
  if (v_max_.size() != slopes_.size() || a_max_.size() != slopes_.size()) {
    throw InputError("slope bounds: v_max and a_max need one value per slope");
  }
  for (std::size_t i = 0; i < slopes_.size(); ++i) {
    if (!(v_max_[i] >= 0.0) || !(a_max_[i] >= 0.0) || !std::isfinite(v_max_[i]) ||
        !std::isfinite(a_max_[i])) {
      throw InputError("slope bounds: v_max and a_max must be finite and >= 0");
    }
  }
}

double SegwaySlopeBounds::speedLimit(double slope) const { return linear(slopes_, v_max_, slope); }

double SegwaySlopeBounds::accelerationLimit(double slope) const {
  return linear(slopes_, a_max_, slope);
}

double SegwaySlopeBounds::drivableSlope() const {
  const auto stopped = [&](double slope) {
    return !(speedLimit(slope) > 0.0) || !(accelerationLimit(slope) > 0.0);
  };
  if (stopped(0.0)) return 0.0;
  double drivable = std::numeric_limits<double>::infinity();
  // Linear between grid points and clamped outside: the first zero on each side is a grid
  // point (both bounds are >= 0).
  for (const double slope : slopes_) {
    if (stopped(slope)) drivable = std::min(drivable, std::abs(slope));
  }
  return drivable;
}

SegwayLookups defaultSegwayLookups() {
  std::vector<double> accelerations, slopes;
  for (int i = 0; i <= 8; ++i) accelerations.push_back(-2.0 + 0.5 * i);
  for (int d = -20; d <= 20; d += 5) slopes.push_back(d * kPi / 180.0);
  Eigen::MatrixXd pitch(accelerations.size(), slopes.size());
  for (std::size_t i = 0; i < accelerations.size(); ++i) {
    for (std::size_t j = 0; j < slopes.size(); ++j) {
      pitch(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = -std::atan(
          (accelerations[i] + kGravity * std::sin(slopes[j])) / (kGravity * std::cos(slopes[j])));
    }
  }
  std::vector<double> bound_slopes, v_max, a_max;
  for (const int d : {-25, -20, -17, -10, -5, 0, 5, 10, 17, 20, 25}) {
    const double slope = d * kPi / 180.0;
    const bool climbable = std::abs(slope) <= kClimbLimit + 1e-9;
    const double magnitude = std::abs(d);
    bound_slopes.push_back(slope);
    v_max.push_back(!climbable ? 0.0 : magnitude <= 5 ? 3.5 : 3.5 - 2.5 * (magnitude - 5) / 12.0);
    a_max.push_back(!climbable ? 0.0
                               : std::max(0.0, 2.0 - kGravity * std::sin(std::abs(slope)) * 0.5));
  }
  return {SegwayPitchResponse(accelerations, slopes, pitch),
          SegwaySlopeBounds(bound_slopes, v_max, a_max)};
}

SegwayLookups readSegwayLookups(const std::filesystem::path& pitch_response_file,
                                const std::filesystem::path& slope_bounds_file) {
  const nlohmann::json response = readJson(pitch_response_file, "segway_pitch_response");
  std::vector<double> accelerations = numbers(response, "acceleration_mps2", pitch_response_file);
  std::vector<double> slopes = numbers(response, "slope_rad", pitch_response_file);
  if (!response.contains("pitch_rad") || !response.at("pitch_rad").is_array() ||
      response.at("pitch_rad").size() != accelerations.size()) {
    throw InputError(pitch_response_file.string() + ": pitch_rad: needs one row per acceleration");
  }
  Eigen::MatrixXd pitch(accelerations.size(), slopes.size());
  for (std::size_t i = 0; i < accelerations.size(); ++i) {
    const nlohmann::json& row = response.at("pitch_rad")[i];
    if (!row.is_array() || row.size() != slopes.size()) {
      throw InputError(pitch_response_file.string() + ": pitch_rad[" + std::to_string(i) +
                       "]: needs one value per slope");
    }
    for (std::size_t j = 0; j < slopes.size(); ++j) {
      if (!row[j].is_number()) {
        throw InputError(pitch_response_file.string() + ": pitch_rad: must hold numbers");
      }
      pitch(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j].get<double>();
    }
  }
  const nlohmann::json bounds = readJson(slope_bounds_file, "segway_slope_bounds");
  try {
    return {SegwayPitchResponse(std::move(accelerations), std::move(slopes), std::move(pitch)),
            SegwaySlopeBounds(numbers(bounds, "slope_rad", slope_bounds_file),
                              numbers(bounds, "v_max", slope_bounds_file),
                              numbers(bounds, "a_max", slope_bounds_file))};
  } catch (const InputError& e) {
    throw InputError(pitch_response_file.string() + " / " + slope_bounds_file.string() + ": " +
                     e.what());
  }
}

}  // namespace terratraj::models
