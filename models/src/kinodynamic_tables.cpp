#include "terratraj/models/kinodynamic_tables.hpp"

#include <algorithm>
#include <cmath>
#include <functional>
#include <sstream>

#include "terratraj/terrain/input_error.hpp"

namespace terratraj::models {
namespace {

// Mean of the top `fraction` of the values (at least one); values is reordered.
double meanOfTop(std::vector<double>& values, double fraction) {
  const std::size_t count = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::ceil(fraction * static_cast<double>(values.size()) - 1e-9)));
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(count - 1),
                   values.end(), std::greater<>());
  double sum = 0.0;
  for (std::size_t i = 0; i < count; ++i) sum += values[i];
  return sum / static_cast<double>(count);
}

// Fills the interior gaps of one line of bins (filled[k] false) by linear interpolation
// between the nearest filled bins on each side; gaps at the ends stay as they are.
template <typename Get, typename Set>
void fillLine(int n, const std::vector<char>& filled, Get get, Set set) {
  int previous = -1;
  for (int k = 0; k < n; ++k) {
    if (!filled[static_cast<std::size_t>(k)]) continue;
    if (previous >= 0 && k - previous > 1) {
      for (int m = previous + 1; m < k; ++m) {
        const double t = static_cast<double>(m - previous) / (k - previous);
        set(m, (1 - t) * get(previous) + t * get(k));
      }
    }
    previous = k;
  }
}

void validate(const DataTableOptions& options) {
  if (!(options.top_fraction > 0.0 && options.top_fraction <= 1.0)) {
    std::ostringstream message;
    message << "top fraction must lie in (0, 1] (got " << options.top_fraction << ")";
    throw InputError(message.str());
  }
}

double cap(double v, const PhysicsTableParameters& p) {
  return std::min(std::max(v, 0.0), p.speed_cap);
}

}  // namespace

BinEdges uniformEdges(double lo, double hi, int bins, const std::string& what) {
  if (!(lo < hi) || bins < 1 || !std::isfinite(lo) || !std::isfinite(hi)) {
    throw InputError(what + ": needs lo < hi and at least one bin");
  }
  std::vector<double> edges(static_cast<std::size_t>(bins) + 1);
  for (int i = 0; i <= bins; ++i) edges[static_cast<std::size_t>(i)] = lo + (hi - lo) * i / bins;
  return BinEdges(std::move(edges), what);
}

BinEdges defaultPitchEdges() { return uniformEdges(-0.4, 0.4, 16, "pitch edges"); }
BinEdges defaultRollEdges() { return uniformEdges(-0.4, 0.4, 16, "roll edges"); }
BinEdges defaultCurvatureEdges() { return uniformEdges(-1.0, 1.0, 20, "curvature edges"); }

double physicsRollCurvatureLimit(double roll, double curvature, const PhysicsTableParameters& p) {
  if (curvature == 0.0) return p.speed_cap;
  const double sign = curvature > 0.0 ? 1.0 : -1.0;
  const double offset = p.half_track * std::cos(roll) - sign * p.cog_height * std::sin(roll);
  if (offset <= 0.0) return 0.0;
  return cap(std::sqrt(p.gravity * offset / (std::abs(curvature) * p.cog_height)), p);
}

double physicsPitchLimit(double pitch, const PhysicsTableParameters& p) {
  const double brake = p.gravity * (p.friction * std::cos(pitch) + std::sin(pitch));
  if (brake <= 0.0) return 0.0;
  return cap(std::sqrt(2.0 * brake * 2.0 * p.vehicle_length * std::cos(pitch)), p);
}

PitchSpeedTable physicsPitchTable(const BinEdges& pitch_edges, const PhysicsTableParameters& p) {
  std::vector<double> v(static_cast<std::size_t>(pitch_edges.binCount()));
  for (int i = 0; i < pitch_edges.binCount(); ++i) {
    v[static_cast<std::size_t>(i)] = physicsPitchLimit(pitch_edges.centre(i), p);
  }
  return PitchSpeedTable(pitch_edges, std::move(v));
}

RollCurvatureSpeedTable physicsRollCurvatureTable(const BinEdges& roll_edges,
                                                  const BinEdges& curvature_edges,
                                                  const PhysicsTableParameters& p) {
  Eigen::MatrixXd v(roll_edges.binCount(), curvature_edges.binCount());
  for (int i = 0; i < roll_edges.binCount(); ++i) {
    for (int j = 0; j < curvature_edges.binCount(); ++j) {
      v(i, j) = physicsRollCurvatureLimit(roll_edges.centre(i), curvature_edges.centre(j), p);
    }
  }
  return RollCurvatureSpeedTable(roll_edges, curvature_edges, std::move(v));
}

DrivingStates drivingStates(const Trajectory& log, const std::string& source_name) {
  for (const TrajectoryColumn column :
       {TrajectoryColumn::kRoll, TrajectoryColumn::kPitch, TrajectoryColumn::kV}) {
    if (!log.has(column)) {
      throw InputError(source_name + ": needs a '" + trajectoryColumnName(column) + "' column");
    }
  }
  const bool has_curvature = log.has(TrajectoryColumn::kCurvature);
  const bool has_omega = log.has(TrajectoryColumn::kOmega);
  if (!has_curvature && !has_omega) {
    throw InputError(source_name + ": needs a 'curvature' or an 'omega' column");
  }
  DrivingStates states;
  const std::size_t n = log.samples.size();
  states.roll.reserve(n);
  states.pitch.reserve(n);
  states.curvature.reserve(n);
  states.speed.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    const TrajectorySample& s = log.samples[i];
    double curvature = has_curvature ? s.curvature : std::nan("");
    if (std::isnan(curvature) && has_omega && !std::isnan(s.omega)) {
      curvature = s.v != 0.0 ? s.omega / s.v : 0.0;
    }
    if (std::isnan(s.roll) || std::isnan(s.pitch) || std::isnan(s.v) || std::isnan(curvature)) {
      throw InputError(source_name + ": data row " + std::to_string(i + 1) +
                       " lacks roll, pitch, v or curvature (nan)");
    }
    states.roll.push_back(s.roll);
    states.pitch.push_back(s.pitch);
    states.curvature.push_back(curvature);
    states.speed.push_back(std::abs(s.v));
  }
  return states;
}

PitchSpeedTable dataPitchTable(const DrivingStates& states, const BinEdges& pitch_edges,
                               const DataTableOptions& options) {
  validate(options);
  const int n = pitch_edges.binCount();
  std::vector<std::vector<double>> speeds(static_cast<std::size_t>(n));
  for (std::size_t i = 0; i < states.speed.size(); ++i) {
    speeds[static_cast<std::size_t>(pitch_edges.binOf(states.pitch[i]))].push_back(states.speed[i]);
  }
  std::vector<double> v_max(static_cast<std::size_t>(n), 0.0);
  std::vector<char> filled(static_cast<std::size_t>(n), 0);
  for (int k = 0; k < n; ++k) {
    std::vector<double>& bin = speeds[static_cast<std::size_t>(k)];
    if (bin.empty()) continue;
    v_max[static_cast<std::size_t>(k)] = meanOfTop(bin, options.top_fraction);
    filled[static_cast<std::size_t>(k)] = 1;
  }
  if (options.fill_empty) {
    fillLine(
        n, filled, [&](int k) { return v_max[static_cast<std::size_t>(k)]; },
        [&](int k, double value) { v_max[static_cast<std::size_t>(k)] = value; });
  }
  return PitchSpeedTable(pitch_edges, std::move(v_max));
}

RollCurvatureSpeedTable dataRollCurvatureTable(const DrivingStates& states,
                                               const BinEdges& roll_edges,
                                               const BinEdges& curvature_edges,
                                               const DataTableOptions& options) {
  validate(options);
  const int rows = roll_edges.binCount(), cols = curvature_edges.binCount();
  std::vector<std::vector<double>> speeds(static_cast<std::size_t>(rows * cols));
  for (std::size_t i = 0; i < states.speed.size(); ++i) {
    const int bin =
        roll_edges.binOf(states.roll[i]) * cols + curvature_edges.binOf(states.curvature[i]);
    speeds[static_cast<std::size_t>(bin)].push_back(states.speed[i]);
  }
  Eigen::MatrixXd v_max = Eigen::MatrixXd::Zero(rows, cols);
  std::vector<char> filled(static_cast<std::size_t>(rows * cols), 0);
  for (int r = 0; r < rows; ++r) {
    for (int c = 0; c < cols; ++c) {
      std::vector<double>& bin = speeds[static_cast<std::size_t>(r * cols + c)];
      if (bin.empty()) continue;
      v_max(r, c) = meanOfTop(bin, options.top_fraction);
      filled[static_cast<std::size_t>(r * cols + c)] = 1;
    }
  }
  if (options.fill_empty) {
    // Along curvature within each roll row, then along roll for what is still empty.
    std::vector<char> after_rows = filled;
    for (int r = 0; r < rows; ++r) {
      std::vector<char> line(filled.begin() + r * cols, filled.begin() + (r + 1) * cols);
      fillLine(
          cols, line, [&](int c) { return v_max(r, c); },
          [&](int c, double value) {
            v_max(r, c) = value;
            after_rows[static_cast<std::size_t>(r * cols + c)] = 1;
          });
    }
    for (int c = 0; c < cols; ++c) {
      std::vector<char> line(static_cast<std::size_t>(rows));
      for (int r = 0; r < rows; ++r)
        line[static_cast<std::size_t>(r)] = after_rows[static_cast<std::size_t>(r * cols + c)];
      fillLine(
          rows, line, [&](int r) { return v_max(r, c); },
          [&](int r, double value) { v_max(r, c) = value; });
    }
  }
  return RollCurvatureSpeedTable(roll_edges, curvature_edges, std::move(v_max));
}

ViolationReport analyseViolations(const DrivingStates& states, const PitchSpeedTable* pitch,
                                  const RollCurvatureSpeedTable* roll_curvature, double tolerance) {
  ViolationReport report;
  report.states = states.speed.size();
  std::size_t pitch_count = 0, roll_curvature_count = 0, combined = 0;
  for (std::size_t i = 0; i < report.states; ++i) {
    bool violates = false;
    const double v = states.speed[i];
    if (pitch != nullptr) {
      const double excess = v - pitch->lookup(states.pitch[i]);
      if (excess > tolerance) {
        ++pitch_count;
        violates = true;
        report.max_excess = std::max(report.max_excess, excess);
      }
    }
    if (roll_curvature != nullptr) {
      const double excess = v - roll_curvature->lookup(states.roll[i], states.curvature[i]);
      if (excess > tolerance) {
        ++roll_curvature_count;
        violates = true;
        report.max_excess = std::max(report.max_excess, excess);
      }
    }
    combined += violates;
  }
  const double n = report.states > 0 ? static_cast<double>(report.states) : 1.0;
  if (pitch != nullptr) report.pitch_fraction = static_cast<double>(pitch_count) / n;
  if (roll_curvature != nullptr) {
    report.roll_curvature_fraction = static_cast<double>(roll_curvature_count) / n;
  }
  report.combined_fraction = static_cast<double>(combined) / n;
  return report;
}

}  // namespace terratraj::models
