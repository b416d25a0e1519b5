#include "terratraj/ocp/transcription_model.hpp"

#include <algorithm>
#include <cmath>

namespace terratraj::ocp {
namespace {

enum Var { kX = 0, kY, kHeading, kV, kOmega, kVDot, kOmegaDot };

// PathConstraints rows of the terrain pitch (replaced by the platform pitch on the Segway).
constexpr int kPitchRow = 10;

const char* const kSegwayRowNames[3] = {"segway_slope_v_max", "segway_slope_a_max",
                                        "segway_slope_a_max"};

// The tables the path rows hold: the Segway's look-ups are this model's own rows
// (TranscriptionModelOptions::segway), with the platform pitch in the pitch rows.
SpeedTables pathTables(SpeedTables tables) {
  tables.segway = nullptr;
  return tables;
}

}  // namespace

TranscriptionModel::TranscriptionModel(const models::TerrainFollowingModel& vehicle,
                                       const BoundaryValueProblem& problem,
                                       const TranscriptionModelOptions& options)
    : kinematics_(vehicle),
      problem_(problem),
      options_(options),
      path_(problem.limits, pathTables(problem.tables)),
      path_rows_(path_.count() - kFirstPathRow),
      segway_rows_(options.segway ? 3 : 0),
      count_(path_rows_ + segway_rows_ + (options.clearance.map != nullptr ? 1 : 0)) {}

const char* TranscriptionModel::constraintName(int row) const {
  if (row < path_rows_) return path_.name(row + kFirstPathRow);
  if (row < path_rows_ + segway_rows_) return kSegwayRowNames[row - path_rows_];
  return "clearance";
}

PointEvaluation TranscriptionModel::makeEvaluation() const {
  PointEvaluation out;
  out.rate_jacobian.setZero();
  out.constraints = Eigen::VectorXd::Zero(count_);
  out.constraint_jacobian = ConstraintJacobian::Zero(count_, kPointSize);
  out.path_values = Eigen::VectorXd::Zero(path_.count());
  out.path_jacobian = ConstraintJacobian::Zero(path_.count(), kPointSize);
  return out;
}

models::AttitudeStatus TranscriptionModel::evaluate(const PointVector& w,
                                                    models::AttitudeWorkspace& workspace,
                                                    PointEvaluation& out) const {
  models::RoverStateSpaceRates rates;
  const models::AttitudeStatus status =
      kinematics_.stateSpaceRates(w.head<kStateSize>(), w.tail<kControlSize>(), workspace, rates);
  if (status != models::AttitudeStatus::kOk) return status;
  out.rate = rates.rate;
  out.rate_jacobian.leftCols<kStateSize>() = rates.d_state;
  out.rate_jacobian.rightCols<kControlSize>() = rates.d_control;

  PathPoint& p = out.point;
  p.state = w.head<3>();
  p.attitude = rates.attitude;
  p.v = w(kV);
  p.omega = w(kOmega);
  p.v_dot = w(kVDot);
  p.omega_dot = w(kOmegaDot);
  const double roll = rates.attitude.attitude.roll;
  const double pitch = rates.attitude.attitude.pitch;
  const Eigen::RowVector3d d_roll = rates.attitude.jacobian.row(1);
  const Eigen::RowVector3d d_pitch = rates.attitude.jacobian.row(2);
  out.slope = pitch;

  // The Segway's platform pitch, by the look-up of (acceleration, slope), in place of the
  // terrain pitch; its derivative by v' is added to the pitch rows below.
  double d_platform_da = 0.0;
  if (options_.segway) {
    // Its C1 version (the verdict judges by the grid's bilinear look-up).
    const models::SegwayPitchResponse& response = options_.segway->lookups.pitch_response;
    double d_platform_ds = 0.0;
    out.platform_pitch = response.smoothPitch(w(kVDot), pitch, &d_platform_da, &d_platform_ds);
    p.attitude.attitude.pitch = out.platform_pitch;
    p.attitude.jacobian.row(2) = d_platform_ds * d_pitch;
  }
  path_.evaluate(p, out.path_values.data(), &out.path_jacobian);
  out.constraints.head(path_rows_) = out.path_values.tail(path_rows_);
  out.constraint_jacobian.topRows(path_rows_) = out.path_jacobian.bottomRows(path_rows_);
  if (options_.segway) {
    out.constraint_jacobian(kPitchRow - kFirstPathRow, kVDot) += d_platform_da;
    out.constraint_jacobian(kPitchRow + 1 - kFirstPathRow, kVDot) -= d_platform_da;
    const models::SegwaySlopeBounds& bounds = options_.segway->lookups.bounds;
    const double scale = options_.segway->bound_scale;
    // C1, and continued below 0 on undrivable slopes: a direction back to drivable ground.
    double dv_ds = 0.0, da_ds = 0.0;
    const double v_limit = scale * bounds.optimiserSpeedLimit(pitch, &dv_ds);
    const double a_limit = scale * bounds.optimiserAccelerationLimit(pitch, &da_ds);
    dv_ds *= scale;
    da_ds *= scale;
    const int row = path_rows_;
    out.constraints(row) = w(kV) - v_limit;
    out.constraints(row + 1) = w(kVDot) - a_limit;
    out.constraints(row + 2) = -w(kVDot) - a_limit;
    out.constraint_jacobian.middleRows<3>(row).setZero();
    out.constraint_jacobian(row, kV) = 1.0;
    out.constraint_jacobian.block<1, 3>(row, 0) = -dv_ds * d_pitch;
    out.constraint_jacobian(row + 1, kVDot) = 1.0;
    out.constraint_jacobian.block<1, 3>(row + 1, 0) = -da_ds * d_pitch;
    out.constraint_jacobian(row + 2, kVDot) = -1.0;
    out.constraint_jacobian.block<1, 3>(row + 2, 0) = -da_ds * d_pitch;
  }
  if (options_.clearance.map != nullptr) {
    const int row = count_ - 1;
    const std::optional<terrain::Clearance> c = options_.clearance.map->at(w.head<2>());
    if (!c) return models::AttitudeStatus::kNoTerrain;
    out.clearance = c->distance;
    out.constraints(row) = options_.clearance.min_clearance - c->distance;
    out.constraint_jacobian.row(row).setZero();
    out.constraint_jacobian(row, kX) = -c->gradient.x();
    out.constraint_jacobian(row, kY) = -c->gradient.y();
  }

  // Running cost.
  out.running_cost = 0.0;
  out.running_cost_gradient.setZero();
  if (problem_.cost.kind == CostKind::kSlopeDwell && problem_.cost.alpha > 0.0) {
    const double alpha = problem_.cost.alpha;
    out.running_cost += alpha * (roll * roll + pitch * pitch);
    out.running_cost_gradient.head<3>() =
        (2.0 * alpha * (roll * d_roll + pitch * d_pitch)).transpose();
  }
  const double epsilon = options_.control_effort_weight;
  if (epsilon > 0.0) {
    out.running_cost += epsilon * (w(kVDot) * w(kVDot) + w(kOmegaDot) * w(kOmegaDot));
    out.running_cost_gradient(kVDot) += 2.0 * epsilon * w(kVDot);
    out.running_cost_gradient(kOmegaDot) += 2.0 * epsilon * w(kOmegaDot);
  }
  return models::AttitudeStatus::kOk;
}

void TranscriptionModel::accumulateViolation(const PointEvaluation& e,
                                             LimitViolation& worst) const {
  path_.accumulateViolation(e.point, worst);
  const auto consider = [&](double amount, const char* limit) {
    if (amount > worst.amount) worst = {amount, limit, e.point.t};
  };
  if (options_.segway) {
    const models::SegwaySlopeBounds& bounds = options_.segway->lookups.bounds;
    consider(e.point.v - bounds.speedLimit(e.slope), kSegwayRowNames[0]);
    consider(std::abs(e.point.v_dot) - bounds.accelerationLimit(e.slope), kSegwayRowNames[1]);
  }
  if (options_.clearance.map != nullptr) {
    consider(options_.clearance.min_clearance - e.clearance, "clearance");
  }
}

}  // namespace terratraj::ocp
