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

// Piecewise linear through (axis, values), continued linearly beyond both ends, with every
// corner rounded by the parabola tangent to its two pieces over +-delta (C1): delta is 0.5 deg,
// at most a quarter of either piece. The parabola lies below a corner that bends down (a bound
// stricter there) and above one that bends up, by bend (delta - |u|)^2 / (4 delta) at u from the
// corner; there the bump bend delta / 4 (1 - (u / delta)^2)^2, larger everywhere in +-delta and
// C1 (0 with slope 0 at +-delta), is taken off, so the curve never exceeds the look-up.
double roundedCorners(const std::vector<double>& axis, const std::vector<double>& values, double x,
                      double* dx) {
  constexpr double kDelta = 0.5 * 3.14159265358979323846 / 180.0;  // [rad]
  const std::size_t n = axis.size();
  const auto piece_slope = [&](std::size_t i) {
    return (values[i + 1] - values[i]) / (axis[i + 1] - axis[i]);
  };
  std::size_t i =
      static_cast<std::size_t>(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin());
  i = std::clamp<std::size_t>(i, 1, n - 1) - 1;  // the piece [axis[i], axis[i + 1]]
  double f = values[i] + piece_slope(i) * (x - axis[i]);
  double df = piece_slope(i);
  // The corners within reach: at axis[i] and axis[i + 1] (interior knots only).
  for (std::size_t k = std::max<std::size_t>(i, 1); k <= std::min(i + 1, n - 2); ++k) {
    const double delta =
        std::min({kDelta, 0.25 * (axis[k] - axis[k - 1]), 0.25 * (axis[k + 1] - axis[k])});
    const double u = x - axis[k];
    if (std::abs(u) >= delta) continue;
    const double bend = piece_slope(k) - piece_slope(k - 1);
    f += bend * ((u + delta) * (u + delta) / (4.0 * delta) - std::max(0.0, u));
    df += bend * ((u + delta) / (2.0 * delta) - (u > 0.0 ? 1.0 : 0.0));
    if (bend > 0.0) {  // bends up: below the look-up by the bump
      const double w = 1.0 - (u / delta) * (u / delta);
      f -= 0.25 * bend * delta * w * w;
      df += bend * u * w / delta;
    }
  }
  if (dx != nullptr) *dx = df;
  return f;
}

// C1 cubic Hermite through (axis[i], value(i)), its slopes the differences of the neighbours
// (one-sided at the ends), continued linearly beyond the ends by the end slopes; the derivative
// into *dx. Linear in the values.
template <class Value>
double hermite(const std::vector<double>& axis, const Value& value, double x, double* dx) {
  const std::size_t n = axis.size();
  const auto slope = [&](std::size_t i) {
    const std::size_t lo = i == 0 ? 0 : i - 1, hi = i + 1 == n ? i : i + 1;
    return (value(hi) - value(lo)) / (axis[hi] - axis[lo]);
  };
  if (!(x > axis.front()) || x >= axis.back()) {
    const std::size_t end = x >= axis.back() ? n - 1 : 0;
    const double m = slope(end);
    *dx = m;
    return value(end) + m * (x - axis[end]);
  }
  const std::size_t i =
      static_cast<std::size_t>(std::upper_bound(axis.begin(), axis.end(), x) - axis.begin()) - 1;
  const double h = axis[i + 1] - axis[i], t = (x - axis[i]) / h;
  const double y0 = value(i), y1 = value(i + 1), m0 = slope(i) * h, m1 = slope(i + 1) * h;
  const double t2 = t * t, t3 = t2 * t;
  *dx = ((6 * t2 - 6 * t) * y0 + (3 * t2 - 4 * t + 1) * m0 + (6 * t - 6 * t2) * y1 +
         (3 * t2 - 2 * t) * m1) /
        h;
  return (2 * t3 - 3 * t2 + 1) * y0 + (t3 - 2 * t2 + t) * m0 + (3 * t2 - 2 * t3) * y1 +
         (t3 - t2) * m1;
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

double SegwayPitchResponse::smoothPitch(double acceleration, double slope, double* d_acceleration,
                                        double* d_slope) const {
  // Along the slopes at grid acceleration i, then along the accelerations (a tensor product).
  const auto along_slopes = [&](std::size_t i, double* d) {
    const auto value = [&](std::size_t j) {
      return pitch_(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    };
    return hermite(slopes_, value, slope, d);
  };
  double unused = 0.0, da = 0.0, ds = 0.0;
  const double p = hermite(
      accelerations_, [&](std::size_t i) { return along_slopes(i, &unused); }, acceleration, &da);
  // The derivative by slope: the same weights on the rows' derivatives.
  ds = hermite(
      accelerations_,
      [&](std::size_t i) {
        double d = 0.0;
        along_slopes(i, &d);
        return d;
      },
      acceleration, &unused);
  if (d_acceleration != nullptr) *d_acceleration = da;
  if (d_slope != nullptr) *d_slope = ds;
  return p;
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
  buildOptimiserKnots();
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

double SegwaySlopeBounds::optimiserSpeedLimit(double slope, double* d_slope) const {
  return roundedCorners(optimiser_slopes_, optimiser_v_, slope, d_slope);
}

double SegwaySlopeBounds::optimiserAccelerationLimit(double slope, double* d_slope) const {
  return roundedCorners(optimiser_slopes_, optimiser_a_, slope, d_slope);
}

void SegwaySlopeBounds::buildOptimiserKnots() {
  const auto stopped = [&](double s) {
    return !(speedLimit(s) > 0.0) || !(accelerationLimit(s) > 0.0);
  };
  // The edge on each side: the grid slope nearest 0 (0 included) where a bound is 0.
  double edge[2] = {std::numeric_limits<double>::infinity(),
                    std::numeric_limits<double>::infinity()};  // [downhill, uphill] magnitudes
  for (const double s : slopes_) {
    if (stopped(s)) edge[s > 0.0] = std::min(edge[s > 0.0], std::abs(s));
  }
  if (stopped(0.0)) edge[0] = edge[1] = 0.0;
  constexpr double kFar = 1.0;  // [rad] where the continued pieces get their second knot
  const auto extension = [&](int side, double& knot, double& v, double& a) {
    const double sign = side == 1 ? 1.0 : -1.0;
    if (std::isinf(edge[side])) {  // drivable to the end of the grid: constant beyond it
      knot = side == 1 ? slopes_.back() + kFar : slopes_.front() - kFar;
      v = speedLimit(knot);
      a = accelerationLimit(knot);
      return;
    }
    // The last piece before the edge, continued (descending by at least 1 per radian).
    constexpr double kInside = 1e-6;  // [rad]
    const double at = sign * edge[side], inside = sign * (edge[side] - kInside);
    knot = at + sign * kFar;
    v = speedLimit(at) - kFar * std::max(1.0, (speedLimit(inside) - speedLimit(at)) / kInside);
    a = accelerationLimit(at) -
        kFar * std::max(1.0, (accelerationLimit(inside) - accelerationLimit(at)) / kInside);
  };
  double knot = 0.0, v = 0.0, a = 0.0;
  extension(0, knot, v, a);
  optimiser_slopes_ = {knot};
  optimiser_v_ = {v};
  optimiser_a_ = {a};
  const auto add = [&](double s) {
    if (s > optimiser_slopes_.back() + 1e-9) {
      optimiser_slopes_.push_back(s);
      optimiser_v_.push_back(speedLimit(s));
      optimiser_a_.push_back(accelerationLimit(s));
    }
  };
  if (std::isfinite(edge[0])) add(-edge[0]);
  for (const double s : slopes_) {
    if (s > -edge[0] && s < edge[1]) add(s);
  }
  if (std::isfinite(edge[1])) add(edge[1]);
  extension(1, knot, v, a);
  optimiser_slopes_.push_back(knot);
  optimiser_v_.push_back(v);
  optimiser_a_.push_back(a);
}

PitchSpeedTable slopeSpeedTable(const SegwaySlopeBounds& bounds, const PitchSpeedTable* also,
                                double bin_width) {
  if (!(bin_width > 0.0)) throw InputError("slope speed table: bin_width must be > 0");
  const std::vector<double>& slopes = bounds.slopes();
  std::vector<double> edges;
  for (std::size_t i = 0; i + 1 < slopes.size(); ++i) {
    const int pieces =
        std::max(1, static_cast<int>(std::ceil((slopes[i + 1] - slopes[i]) / bin_width)));
    for (int k = 0; k < pieces; ++k) {
      edges.push_back(slopes[i] + (slopes[i + 1] - slopes[i]) * k / pieces);
    }
  }
  edges.push_back(slopes.back());
  if (also != nullptr) {
    const std::vector<double>& more = also->pitchEdges().edges();
    edges.insert(edges.end(), more.begin(), more.end());
    std::sort(edges.begin(), edges.end());
    // Edges closer than a micro-radian are one edge (the bins must strictly increase).
    edges.erase(
        std::unique(edges.begin(), edges.end(), [](double a, double b) { return b - a < 1e-6; }),
        edges.end());
  }
  std::vector<double> v_max;
  for (std::size_t i = 0; i + 1 < edges.size(); ++i) {
    double v = std::min(bounds.speedLimit(edges[i]), bounds.speedLimit(edges[i + 1]));
    if (also != nullptr) v = std::min(v, also->lookup(0.5 * (edges[i] + edges[i + 1])));
    v_max.push_back(v);
  }
  // Beyond the merged edges both rules clamp to their outermost values, as the table does.
  return PitchSpeedTable(BinEdges(std::move(edges), "slope speed table"), std::move(v_max));
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
