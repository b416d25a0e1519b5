#include "terratraj/ocp/path_constraints.hpp"

#include <algorithm>
#include <array>
#include <cmath>

namespace terratraj::ocp {
namespace {

// Variable indices of a PathPoint.
enum Var { kX = 0, kY, kHeading, kV, kOmega, kVDot, kOmegaDot };

constexpr std::array<const char*, 14> kRowNames{
    "v_max",     "v_min",     "a_max",     "a_max",     "omega_max", "omega_max", "kappa_max",
    "kappa_max", "sigma_max", "sigma_max", "pitch_max", "pitch_max", "roll_max",  "roll_max"};
constexpr std::array<const char*, kSegwayPathRows> kSegwayRowNames{
    "segway_slope_v_max", "segway_slope_a_max", "segway_slope_a_max", "segway_platform_pitch",
    "segway_platform_pitch"};

// Below this speed [m/s] curvature is not defined; the table's curvature argument is clamped.
constexpr double kMinCurvatureSpeed = 0.05;

}  // namespace

PathConstraints::PathConstraints(const models::VehicleLimits& limits, const SpeedTables& tables,
                                 double segway_bound_scale)
    : limits_(limits), tables_(tables), count_(14), segway_bound_scale_(segway_bound_scale) {
  if (tables_.pitch != nullptr) pitch_table_row_ = count_++;
  if (tables_.roll_curvature != nullptr) roll_curvature_row_ = count_++;
  if (tables_.segway != nullptr) {
    segway_row_ = count_;
    count_ += kSegwayPathRows;
  }
}

bool vanishesAtRest(std::string_view limit) {
  return limit == "v_min" || limit == "kappa_max" || limit == "sigma_max";
}

const char* PathConstraints::name(int row) const {
  if (row < 14) return kRowNames[static_cast<std::size_t>(row)];
  if (row == pitch_table_row_) return "table_pitch";
  if (row == roll_curvature_row_) return "table_roll_curvature";
  return kSegwayRowNames[static_cast<std::size_t>(row - segway_row_)];
}

void PathConstraints::evaluate(const PathPoint& p, double* g,
                               Eigen::Matrix<double, Eigen::Dynamic, kPathVariables>* jac) const {
  const models::VehicleLimits& l = limits_;
  const double roll = p.attitude.attitude.roll;
  const double pitch = p.attitude.attitude.pitch;
  const Eigen::RowVector3d d_roll = p.attitude.jacobian.row(1);
  const Eigen::RowVector3d d_pitch = p.attitude.jacobian.row(2);
  if (jac != nullptr) jac->setZero(count_, kPathVariables);
  const auto set = [&](int row, int var, double value) {
    if (jac != nullptr) (*jac)(row, var) = value;
  };
  g[0] = p.v - l.v_max;
  set(0, kV, 1.0);
  g[1] = -p.v;
  set(1, kV, -1.0);
  g[2] = p.v_dot - l.a_max;
  set(2, kVDot, 1.0);
  g[3] = -p.v_dot - l.a_max;
  set(3, kVDot, -1.0);
  g[4] = p.omega - l.omega_max;
  set(4, kOmega, 1.0);
  g[5] = -p.omega - l.omega_max;
  set(5, kOmega, -1.0);
  g[6] = p.omega - l.kappa_max * p.v;
  set(6, kOmega, 1.0);
  set(6, kV, -l.kappa_max);
  g[7] = -p.omega - l.kappa_max * p.v;
  set(7, kOmega, -1.0);
  set(7, kV, -l.kappa_max);
  const double sigma = p.omega_dot * p.v - p.omega * p.v_dot;
  const double bound = l.sigma_max * p.v * p.v;
  g[8] = sigma - bound;
  g[9] = -sigma - bound;
  for (int sign = 1, row = 8; row <= 9; ++row, sign = -1) {
    set(row, kOmegaDot, sign * p.v);
    set(row, kV, sign * p.omega_dot - 2.0 * l.sigma_max * p.v);
    set(row, kOmega, -sign * p.v_dot);
    set(row, kVDot, -sign * p.omega);
  }
  g[10] = pitch - l.pitch_max;
  g[11] = -pitch - l.pitch_max;
  g[12] = roll - l.roll_max;
  g[13] = -roll - l.roll_max;
  if (jac != nullptr) {
    jac->block<1, 3>(10, 0) = d_pitch;
    jac->block<1, 3>(11, 0) = -d_pitch;
    jac->block<1, 3>(12, 0) = d_roll;
    jac->block<1, 3>(13, 0) = -d_roll;
  }
  if (tables_.pitch != nullptr) {
    const int row = pitch_table_row_;
    double d = 0.0;
    g[row] = p.v - tables_.pitch->smoothLookup(pitch, &d);
    set(row, kV, 1.0);
    if (jac != nullptr) jac->block<1, 3>(row, 0) = -d * d_pitch;
  }
  if (tables_.segway != nullptr) evaluateSegway(p, g, jac);
  if (tables_.roll_curvature != nullptr) {
    const int row = roll_curvature_row_;
    const double v = std::max(p.v, kMinCurvatureSpeed);
    const double kappa = p.omega / v;
    double d_r = 0.0, d_k = 0.0;
    g[row] = p.v - tables_.roll_curvature->smoothLookup(roll, kappa, &d_r, &d_k);
    if (jac != nullptr) {
      (*jac)(row, kV) = 1.0 + (p.v > kMinCurvatureSpeed ? d_k * p.omega / (v * v) : 0.0);
      (*jac)(row, kOmega) = -d_k / v;
      jac->block<1, 3>(row, 0) = -d_r * d_roll;
    }
  }
}

void PathConstraints::evaluateSegway(
    const PathPoint& p, double* g,
    Eigen::Matrix<double, Eigen::Dynamic, kPathVariables>* jac) const {
  const models::SegwayLookups& segway = *tables_.segway;
  const double slope = p.attitude.attitude.pitch;  // along the heading, nose up > 0
  const Eigen::RowVector3d d_slope = p.attitude.jacobian.row(2);
  double dv_ds = 0.0, da_ds = 0.0, dp_da = 0.0, dp_ds = 0.0;
  const double scale = segway_bound_scale_;
  const double v_limit = scale * segway.bounds.optimiserSpeedLimit(slope, &dv_ds);
  const double a_limit = scale * segway.bounds.optimiserAccelerationLimit(slope, &da_ds);
  dv_ds *= scale;
  da_ds *= scale;
  const double platform = segway.pitch_response.smoothPitch(p.v_dot, slope, &dp_da, &dp_ds);
  const int row = segway_row_;
  g[row] = p.v - v_limit;
  g[row + 1] = p.v_dot - a_limit;
  g[row + 2] = -p.v_dot - a_limit;
  g[row + 3] = platform - limits_.pitch_max;
  g[row + 4] = -platform - limits_.pitch_max;
  if (jac == nullptr) return;
  (*jac)(row, kV) = 1.0;
  jac->block<1, 3>(row, 0) = -dv_ds * d_slope;
  (*jac)(row + 1, kVDot) = 1.0;
  jac->block<1, 3>(row + 1, 0) = -da_ds * d_slope;
  (*jac)(row + 2, kVDot) = -1.0;
  jac->block<1, 3>(row + 2, 0) = -da_ds * d_slope;
  for (int sign = 1, r = row + 3; r <= row + 4; ++r, sign = -1) {
    (*jac)(r, kVDot) = sign * dp_da;
    jac->block<1, 3>(r, 0) = sign * dp_ds * d_slope;
  }
}

void PathConstraints::accumulateViolation(const PathPoint& p, LimitViolation& worst) const {
  const models::VehicleLimits& l = limits_;
  const auto consider = [&](double amount, const char* limit) {
    if (amount > worst.amount) worst = {amount, limit, p.t};
  };
  consider(p.v - l.v_max, "v_max");
  consider(-p.v, "v_min");
  consider(std::abs(p.v_dot) - l.a_max, "a_max");
  consider(std::abs(p.omega) - l.omega_max, "omega_max");
  if (p.v > kMinCurvatureSpeed) {
    consider(std::abs(p.omega / p.v) - l.kappa_max, "kappa_max");
    consider(std::abs((p.omega_dot * p.v - p.omega * p.v_dot) / (p.v * p.v)) - l.sigma_max,
             "sigma_max");
  }
  consider(std::abs(p.attitude.attitude.pitch) - l.pitch_max, "pitch_max");
  consider(std::abs(p.attitude.attitude.roll) - l.roll_max, "roll_max");
  if (tables_.pitch != nullptr) {
    consider(p.v - tables_.pitch->lookup(p.attitude.attitude.pitch), "table_pitch");
  }
  if (tables_.roll_curvature != nullptr && p.v > kMinCurvatureSpeed) {
    consider(p.v - tables_.roll_curvature->lookup(p.attitude.attitude.roll, p.omega / p.v),
             "table_roll_curvature");
  }
}

}  // namespace terratraj::ocp
