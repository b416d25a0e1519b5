#include "terratraj/models/velocity_table.hpp"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::models {
namespace {

// Cubic Hermite through (c(k), v(k)), k = 0..n-1, with finite-difference slopes (zero at the
// ends), constant outside [c(0), c(n-1)]. Linear in the values v, C1 in x.
template <typename Centre, typename Value>
double hermite(int n, const Centre& c, const Value& v, double x, double* d_x) {
  if (n == 1 || !(x > c(0))) {
    if (d_x != nullptr) *d_x = 0.0;
    return v(0);
  }
  if (x >= c(n - 1)) {
    if (d_x != nullptr) *d_x = 0.0;
    return v(n - 1);
  }
  int i = 0;
  while (i + 2 < n && x >= c(i + 1)) ++i;
  const auto slope = [&](int k) {
    return (k == 0 || k == n - 1) ? 0.0 : (v(k + 1) - v(k - 1)) / (c(k + 1) - c(k - 1));
  };
  const double h = c(i + 1) - c(i);
  const double t = (x - c(i)) / h;
  const double t2 = t * t, t3 = t2 * t;
  const double vi = v(i), vj = v(i + 1), mi = slope(i) * h, mj = slope(i + 1) * h;
  if (d_x != nullptr) {
    *d_x = ((6 * t2 - 6 * t) * vi + (3 * t2 - 4 * t + 1) * mi + (-6 * t2 + 6 * t) * vj +
            (3 * t2 - 2 * t) * mj) /
           h;
  }
  return (2 * t3 - 3 * t2 + 1) * vi + (t3 - 2 * t2 + t) * mi + (-2 * t3 + 3 * t2) * vj +
         (t3 - t2) * mj;
}

void checkSpeeds(const double* values, std::size_t count, const std::string& what) {
  for (std::size_t i = 0; i < count; ++i) {
    if (!std::isfinite(values[i]) || values[i] < 0.0) {
      std::ostringstream message;
      message << what << ": v_max values must be finite and >= 0 (got " << values[i] << ")";
      throw InputError(message.str());
    }
  }
}

nlohmann::json readJson(const std::filesystem::path& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path.string() + ": cannot be opened for reading");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(path.string() + ": not valid JSON (" + e.what() + ")");
  }
}

std::vector<double> numberArray(const nlohmann::json& json, const char* key,
                                const std::filesystem::path& path) {
  const std::string where = path.string() + ": " + key;
  if (!json.contains(key)) throw InputError(where + ": missing");
  const nlohmann::json& array = json.at(key);
  if (!array.is_array()) throw InputError(where + ": must be an array of numbers");
  std::vector<double> values;
  for (const nlohmann::json& item : array) {
    if (!item.is_number()) throw InputError(where + ": must be an array of numbers");
    values.push_back(item.get<double>());
  }
  return values;
}

void expectKind(const nlohmann::json& json, const std::string& kind,
                const std::filesystem::path& path) {
  if (!json.is_object() || !json.contains("kind") || !json.at("kind").is_string()) {
    throw InputError(path.string() + ": kind: missing (expected \"pitch\" or \"roll_curvature\")");
  }
  const std::string found = json.at("kind").get<std::string>();
  if (found != kind) {
    throw InputError(path.string() + ": kind: expected \"" + kind + "\", got \"" + found + "\"");
  }
}

void writeText(const std::string& text, const std::filesystem::path& path) {
  std::ofstream out(path);
  out << text << '\n';
  if (!out) throw InputError(path.string() + ": cannot be written");
}

}  // namespace

BinEdges::BinEdges(std::vector<double> edges, const std::string& what) : edges_(std::move(edges)) {
  if (edges_.size() < 2) throw InputError(what + ": needs at least two edges");
  for (std::size_t i = 0; i < edges_.size(); ++i) {
    if (!std::isfinite(edges_[i])) throw InputError(what + ": edges must be finite numbers");
    if (i > 0 && !(edges_[i] > edges_[i - 1])) {
      std::ostringstream message;
      message << what << ": edges must increase strictly (" << edges_[i - 1] << " then "
              << edges_[i] << ")";
      throw InputError(message.str());
    }
  }
}

int BinEdges::binOf(double x) const {
  const auto it = std::upper_bound(edges_.begin(), edges_.end(), x);
  const int bin = static_cast<int>(it - edges_.begin()) - 1;
  return std::clamp(bin, 0, binCount() - 1);
}

PitchSpeedTable::PitchSpeedTable(BinEdges pitch_edges, std::vector<double> v_max)
    : pitch_edges_(std::move(pitch_edges)), v_max_(std::move(v_max)) {
  if (static_cast<int>(v_max_.size()) != pitch_edges_.binCount()) {
    throw InputError("pitch table: v_max has " + std::to_string(v_max_.size()) + " values for " +
                     std::to_string(pitch_edges_.binCount()) + " bins");
  }
  checkSpeeds(v_max_.data(), v_max_.size(), "pitch table");
}

double PitchSpeedTable::lookup(double pitch) const {
  return v_max_[static_cast<std::size_t>(pitch_edges_.binOf(pitch))];
}

double PitchSpeedTable::smoothLookup(double pitch, double* d_pitch) const {
  const auto centre = [this](int k) { return pitch_edges_.centre(k); };
  const auto value = [this](int k) { return v_max_[static_cast<std::size_t>(k)]; };
  const double v = hermite(pitch_edges_.binCount(), centre, value, pitch, d_pitch);
  if (v < 0.0) {
    if (d_pitch != nullptr) *d_pitch = 0.0;
    return 0.0;
  }
  return v;
}

RollCurvatureSpeedTable::RollCurvatureSpeedTable(BinEdges roll_edges, BinEdges curvature_edges,
                                                 Eigen::MatrixXd v_max)
    : roll_edges_(std::move(roll_edges)),
      curvature_edges_(std::move(curvature_edges)),
      v_max_(std::move(v_max)) {
  if (v_max_.rows() != roll_edges_.binCount() || v_max_.cols() != curvature_edges_.binCount()) {
    throw InputError("roll_curvature table: v_max is " + std::to_string(v_max_.rows()) + " x " +
                     std::to_string(v_max_.cols()) + " for " +
                     std::to_string(roll_edges_.binCount()) + " roll x " +
                     std::to_string(curvature_edges_.binCount()) + " curvature bins");
  }
  checkSpeeds(v_max_.data(), static_cast<std::size_t>(v_max_.size()), "roll_curvature table");
}

double RollCurvatureSpeedTable::lookup(double roll, double curvature) const {
  return v_max_(roll_edges_.binOf(roll), curvature_edges_.binOf(curvature));
}

double RollCurvatureSpeedTable::smoothLookup(double roll, double curvature, double* d_roll,
                                             double* d_curvature) const {
  const int n_roll = roll_edges_.binCount();
  const int n_curvature = curvature_edges_.binCount();
  const auto curvature_centre = [this](int k) { return curvature_edges_.centre(k); };
  const auto roll_centre = [this](int k) { return roll_edges_.centre(k); };
  // Each roll row interpolated along curvature, then those values along roll.
  const auto row_value = [&](int i) {
    return hermite(
        n_curvature, curvature_centre, [&](int j) { return v_max_(i, j); }, curvature, nullptr);
  };
  const auto row_slope = [&](int i) {
    double d = 0.0;
    hermite(
        n_curvature, curvature_centre, [&](int j) { return v_max_(i, j); }, curvature, &d);
    return d;
  };
  const double v = hermite(n_roll, roll_centre, row_value, roll, d_roll);
  if (d_curvature != nullptr) *d_curvature = hermite(n_roll, roll_centre, row_slope, roll, nullptr);
  if (v < 0.0) {
    if (d_roll != nullptr) *d_roll = 0.0;
    if (d_curvature != nullptr) *d_curvature = 0.0;
    return 0.0;
  }
  return v;
}

std::string readTableKind(const std::filesystem::path& path) {
  const nlohmann::json json = readJson(path);
  if (!json.is_object() || !json.contains("kind") || !json.at("kind").is_string()) {
    throw InputError(path.string() + ": kind: missing (expected \"pitch\" or \"roll_curvature\")");
  }
  const std::string kind = json.at("kind").get<std::string>();
  if (kind != "pitch" && kind != "roll_curvature") {
    throw InputError(path.string() + ": kind: \"" + kind +
                     "\" is not a table kind (expected \"pitch\" or \"roll_curvature\")");
  }
  return kind;
}

PitchSpeedTable readPitchTable(const std::filesystem::path& path) {
  const nlohmann::json json = readJson(path);
  expectKind(json, "pitch", path);
  BinEdges edges(numberArray(json, "pitch_edges_rad", path), path.string() + ": pitch_edges_rad");
  try {
    return PitchSpeedTable(std::move(edges), numberArray(json, "v_max", path));
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

RollCurvatureSpeedTable readRollCurvatureTable(const std::filesystem::path& path) {
  const nlohmann::json json = readJson(path);
  expectKind(json, "roll_curvature", path);
  BinEdges roll(numberArray(json, "roll_edges_rad", path), path.string() + ": roll_edges_rad");
  BinEdges curvature(numberArray(json, "curvature_edges", path),
                     path.string() + ": curvature_edges");
  if (!json.contains("v_max") || !json.at("v_max").is_array()) {
    throw InputError(path.string() + ": v_max: must be an array of rows (one per roll bin)");
  }
  const nlohmann::json& rows = json.at("v_max");
  Eigen::MatrixXd v_max(static_cast<Eigen::Index>(rows.size()), curvature.binCount());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const nlohmann::json& row = rows[i];
    if (!row.is_array() || static_cast<int>(row.size()) != curvature.binCount()) {
      throw InputError(path.string() + ": v_max[" + std::to_string(i) + "]: must hold " +
                       std::to_string(curvature.binCount()) + " numbers (one per curvature bin)");
    }
    for (std::size_t j = 0; j < row.size(); ++j) {
      if (!row[j].is_number()) {
        throw InputError(path.string() + ": v_max[" + std::to_string(i) + "][" + std::to_string(j) +
                         "]: must be a number");
      }
      v_max(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = row[j].get<double>();
    }
  }
  try {
    return RollCurvatureSpeedTable(std::move(roll), std::move(curvature), std::move(v_max));
  } catch (const InputError& e) {
    throw InputError(path.string() + ": " + e.what());
  }
}

std::string tableJson(const PitchSpeedTable& table) {
  nlohmann::json json{
      {"kind", "pitch"}, {"pitch_edges_rad", table.pitchEdges().edges()}, {"v_max", table.vMax()}};
  return json.dump();
}

std::string tableJson(const RollCurvatureSpeedTable& table) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < table.vMax().rows(); ++i) {
    std::vector<double> row(static_cast<std::size_t>(table.vMax().cols()));
    for (Eigen::Index j = 0; j < table.vMax().cols(); ++j)
      row[static_cast<std::size_t>(j)] = table.vMax()(i, j);
    rows.push_back(row);
  }
  nlohmann::json json{{"kind", "roll_curvature"},
                      {"roll_edges_rad", table.rollEdges().edges()},
                      {"curvature_edges", table.curvatureEdges().edges()},
                      {"v_max", rows}};
  return json.dump();
}

void writeTable(const PitchSpeedTable& table, const std::filesystem::path& path) {
  writeText(tableJson(table), path);
}

void writeTable(const RollCurvatureSpeedTable& table, const std::filesystem::path& path) {
  writeText(tableJson(table), path);
}

}  // namespace terratraj::models
