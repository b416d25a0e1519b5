#include "terratraj/ocp/transcription_nlp.hpp"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "shooting_interval.hpp"

namespace terratraj::ocp {
namespace {

constexpr int kBlockEntries = kStateSize * kPointSize;  // one term of a defect block
// Relative step of the central differences of the point gradients (exact Hessian).
constexpr double kHessianStep = 1e-5;

}  // namespace

const char* transcriptionSchemeName(TranscriptionScheme scheme) {
  switch (scheme) {
    case TranscriptionScheme::kTrapezoidal:
      return "trapezoidal";
    case TranscriptionScheme::kHermiteSimpson:
      return "hermite_simpson";
    case TranscriptionScheme::kMultipleShooting:
      return "multiple_shooting";
  }
  return "unknown";
}

std::vector<double> uniformMesh(int intervals) {
  std::vector<double> mesh(static_cast<std::size_t>(std::max(intervals, 1)) + 1);
  for (std::size_t k = 0; k < mesh.size(); ++k) {
    mesh[k] = static_cast<double>(k) / static_cast<double>(mesh.size() - 1);
  }
  mesh.back() = 1.0;
  return mesh;
}

struct TranscriptionNlp::Shooting {
  detail::ShootingInterval integrator;
  detail::IntervalResult result;
  Shooting(const TranscriptionModel& model, const TranscriptionLayout& layout)
      : integrator(model, layout.shooting_controls == ShootingControls::kPiecewiseLinear,
                   layout.shooting_relative_tolerance, layout.shooting_absolute_tolerance) {}
};

template <typename Visit>
void TranscriptionNlp::forEachEntry(TermPattern pattern, Visit&& visit) {
  for (int i = 0; i < kStateSize; ++i) {
    switch (pattern) {
      case TermPattern::kDense:
        for (int j = 0; j < kPointSize; ++j) visit(i, j);
        break;
      case TermPattern::kDynamics:
        if (i < 3) {
          for (int j = 0; j < kStateSize; ++j) visit(i, j);
        } else {
          visit(i, i);
          visit(i, i + kControlSize);  // v' for v, omega' for omega
        }
        break;
      case TermPattern::kIdentity:
        visit(i, i);
        break;
    }
  }
}

TranscriptionNlp::TranscriptionNlp(const TranscriptionModel& model, TranscriptionLayout layout)
    : model_(&model), layout_(std::move(layout)) {
  const std::vector<double>& mesh = layout_.mesh;
  if (mesh.size() < 2 || mesh.front() != 0.0 || mesh.back() != 1.0) {
    throw std::invalid_argument("transcription mesh must run from 0 to 1 with >= 1 interval");
  }
  for (std::size_t k = 1; k < mesh.size(); ++k) {
    if (!(mesh[k] > mesh[k - 1])) {
      throw std::invalid_argument("transcription mesh must be strictly increasing");
    }
  }
  buildStructure();
  evals_.assign(static_cast<std::size_t>(points()), model.makeEvaluation());
  workspaces_.assign(static_cast<std::size_t>(points()), models::AttitudeWorkspace{});
  scratch_ = model.makeEvaluation();
  nu_.assign(static_cast<std::size_t>(points()), StateVector::Zero());
  last_x_.resize(variableCount());
  gradient_ = Eigen::VectorXd::Zero(variableCount());
  constraints_ = Eigen::VectorXd::Zero(constraintCount());
  jac_values_ = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(jac_rows_.size()));
  if (layout_.scheme == TranscriptionScheme::kMultipleShooting) {
    shooting_ = std::make_unique<Shooting>(model, layout_);
  }
}

TranscriptionNlp::~TranscriptionNlp() = default;

bool TranscriptionNlp::isNode(int point) const {
  return layout_.scheme != TranscriptionScheme::kHermiteSimpson || point % 2 == 0;
}

int TranscriptionNlp::nodePoint(int node) const {
  return layout_.scheme == TranscriptionScheme::kHermiteSimpson ? 2 * node : node;
}

ConstraintRow TranscriptionNlp::row(int row) const {
  if (row >= control_row_start_ && row < defect_rows_) {
    return {true, (row - control_row_start_) / kControlSize, "control_linearity"};
  }
  if (row < defect_rows_) {
    const int block = row / kStateSize;
    const int interval = layout_.scheme == TranscriptionScheme::kHermiteSimpson ? block / 2 : block;
    return {true, interval, "defect"};
  }
  if (row >= defect_rows_ + path_rows_ + rest_rows_) {
    const int bound = row - defect_rows_ - path_rows_ - rest_rows_;
    return {false, bounds_.point(bound), bounds_.name(bound)};
  }
  if (row >= defect_rows_ + path_rows_) {
    return {false, rest_[static_cast<std::size_t>(row - defect_rows_ - path_rows_)].point,
            "kappa_max_at_rest"};
  }
  const int count = model_->constraintCount();
  const int local = row - defect_rows_;
  return {false, local / count, model_->constraintName(local % count)};
}

void TranscriptionNlp::buildStructure() {
  const std::vector<double>& mesh = layout_.mesh;
  const int n = intervals();
  const bool hs = layout_.scheme == TranscriptionScheme::kHermiteSimpson;
  tau_.clear();
  for (int k = 0; k < n; ++k) {
    tau_.push_back(mesh[static_cast<std::size_t>(k)]);
    if (hs)
      tau_.push_back(0.5 *
                     (mesh[static_cast<std::size_t>(k)] + mesh[static_cast<std::size_t>(k) + 1]));
  }
  tau_.push_back(1.0);
  weights_.assign(tau_.size(), 0.0);
  blocks_.clear();
  for (int k = 0; k < n; ++k) {
    const double d = mesh[static_cast<std::size_t>(k) + 1] - mesh[static_cast<std::size_t>(k)];
    if (hs) {
      const int a = 2 * k, m = 2 * k + 1, b = 2 * k + 2;
      weights_[static_cast<std::size_t>(a)] += d / 6.0;
      weights_[static_cast<std::size_t>(m)] += 4.0 * d / 6.0;
      weights_[static_cast<std::size_t>(b)] += d / 6.0;
      blocks_.push_back({{{a, -0.5, d / 8.0}, {m, 1.0, 0.0}, {b, -0.5, -d / 8.0}}, 0, 0});
      blocks_.push_back({{{a, -1.0, d / 6.0}, {m, 0.0, 4.0 * d / 6.0}, {b, 1.0, d / 6.0}}, 0, 0});
    } else {
      weights_[static_cast<std::size_t>(k)] += d / 2.0;
      weights_[static_cast<std::size_t>(k) + 1] += d / 2.0;
      blocks_.push_back({{{k, -1.0, d / 2.0}, {k + 1, 1.0, d / 2.0}}, 0, 0});
    }
  }
  for (DefectBlock& block : blocks_) {
    for (Term& term : block.terms) {
      term.pattern = layout_.scheme == TranscriptionScheme::kMultipleShooting ? TermPattern::kDense
                     : term.beta == 0.0 ? TermPattern::kIdentity
                                        : TermPattern::kDynamics;
    }
  }
  const int tf = finalTimeIndex();
  jac_rows_.clear();
  jac_cols_.clear();
  int row = 0;
  for (DefectBlock& block : blocks_) {
    block.row = row;
    block.jac_start = static_cast<int>(jac_rows_.size());
    for (const Term& term : block.terms) {
      forEachEntry(term.pattern, [&](int i, int j) {
        jac_rows_.push_back(row + i);
        jac_cols_.push_back(kPointSize * term.point + j);
      });
    }
    for (int i = 0; i < kStateSize; ++i) {
      jac_rows_.push_back(row + i);
      jac_cols_.push_back(tf);
    }
    row += kStateSize;
  }
  control_row_start_ = row;
  control_jac_start_ = static_cast<int>(jac_rows_.size());
  if (hs && layout_.linear_controls) {
    for (int k = 0; k < n; ++k) {
      for (int j = kStateSize; j < kPointSize; ++j) {
        for (int p : {2 * k, 2 * k + 1, 2 * k + 2}) {
          jac_rows_.push_back(row);
          jac_cols_.push_back(kPointSize * p + j);
        }
        ++row;
      }
    }
  }
  defect_rows_ = row;
  const int count = model_->constraintCount();
  path_rows_ = count * points();
  path_jac_start_ = static_cast<int>(jac_rows_.size());
  for (int p = 0; p < points(); ++p) {
    for (int r = 0; r < count; ++r) {
      for (int j = 0; j < kPointSize; ++j) {
        jac_rows_.push_back(row);
        jac_cols_.push_back(kPointSize * p + j);
      }
      ++row;
    }
  }
  rest_.clear();
  const BoundaryValueProblem& problem = model_->problem();
  const double kappa = problem.limits.kappa_max;
  if (layout_.rest_curvature && standsStill(problem.start)) {
    rest_.push_back({0, 1.0, -kappa});
    rest_.push_back({0, -1.0, -kappa});
  }
  if (layout_.rest_curvature && standsStill(problem.goal)) {
    rest_.push_back({points() - 1, 1.0, kappa});
    rest_.push_back({points() - 1, -1.0, kappa});
  }
  rest_rows_ = static_cast<int>(rest_.size());
  rest_jac_start_ = static_cast<int>(jac_rows_.size());
  for (const RestRow& r : rest_) {
    jac_rows_.push_back(row);
    jac_cols_.push_back(kPointSize * r.point + kStateSize + 1);  // omega'
    jac_rows_.push_back(row);
    jac_cols_.push_back(kPointSize * r.point + kStateSize);  // v'
    ++row;
  }
  bounds_ =
      IntervalBoundRows(layout_.scheme, mesh, problem.limits, layout_.interval_bounds_final_time);
  bound_jac_start_ = static_cast<int>(jac_rows_.size());
  bounds_.appendStructure(row, jac_rows_, jac_cols_);
  buildHessianStructure();
}

void TranscriptionNlp::buildHessianStructure() {
  const int tf = finalTimeIndex();
  hess_rows_.clear();
  hess_cols_.clear();
  for (int p = 0; p < points(); ++p) {
    for (int i = 0; i < kPointSize; ++i) {
      for (int j = 0; j <= i; ++j) {
        hess_rows_.push_back(kPointSize * p + i);
        hess_cols_.push_back(kPointSize * p + j);
      }
    }
    for (int j = 0; j < kPointSize; ++j) {
      hess_rows_.push_back(tf);
      hess_cols_.push_back(kPointSize * p + j);
    }
  }
  hess_rows_.push_back(tf);
  hess_cols_.push_back(tf);
}

bool TranscriptionNlp::evaluatePoints(const Eigen::Map<const Eigen::VectorXd>& x) {
  const double tf = x(finalTimeIndex());
  for (int p = 0; p < points(); ++p) {
    const PointVector w = x.segment<kPointSize>(kPointSize * p);
    PointEvaluation& e = evals_[static_cast<std::size_t>(p)];
    const models::AttitudeStatus status =
        model_->evaluate(w, workspaces_[static_cast<std::size_t>(p)], e);
    e.point.t = tf * tau_[static_cast<std::size_t>(p)];
    if (status != models::AttitudeStatus::kOk) {
      std::ostringstream text;
      text << "the rover cannot be placed at (" << w(0) << ", " << w(1) << ") at t = " << e.point.t
           << " s: " << models::attitudeStatusName(status);
      message_ = text.str();
      return false;
    }
  }
  return true;
}

bool TranscriptionNlp::evaluateCollocation(const Eigen::Map<const Eigen::VectorXd>& x) {
  const double tf = x(finalTimeIndex());
  for (const DefectBlock& block : blocks_) {
    StateVector defect = StateVector::Zero();
    StateVector d_tf = StateVector::Zero();
    int entry = block.jac_start;
    for (const Term& term : block.terms) {
      const PointEvaluation& e = evals_[static_cast<std::size_t>(term.point)];
      defect +=
          term.alpha * x.segment<kStateSize>(kPointSize * term.point) - tf * term.beta * e.rate;
      d_tf -= term.beta * e.rate;
      Eigen::Matrix<double, kStateSize, kPointSize> jac = -tf * term.beta * e.rate_jacobian;
      jac.leftCols<kStateSize>().diagonal().array() += term.alpha;
      forEachEntry(term.pattern, [&](int i, int j) { jac_values_(entry++) = jac(i, j); });
    }
    for (int i = 0; i < kStateSize; ++i) jac_values_(entry++) = d_tf(i);
    constraints_.segment<kStateSize>(block.row) = defect;
  }
  // Control linearity: u_m - (u_a + u_b) / 2 = 0 (constant Jacobian, no curvature).
  int entry = control_jac_start_;
  for (int row = control_row_start_; row < defect_rows_; ++row) {
    const int k = (row - control_row_start_) / kControlSize;
    const int j = kStateSize + (row - control_row_start_) % kControlSize;
    const double ua = x(kPointSize * (2 * k) + j), um = x(kPointSize * (2 * k + 1) + j),
                 ub = x(kPointSize * (2 * k + 2) + j);
    constraints_(row) = um - 0.5 * (ua + ub);
    jac_values_(entry++) = -0.5;
    jac_values_(entry++) = 1.0;
    jac_values_(entry++) = -0.5;
  }
  return true;
}

bool TranscriptionNlp::evaluateShooting(const Eigen::Map<const Eigen::VectorXd>& x) {
  const double tf = x(finalTimeIndex());
  const bool linear = layout_.shooting_controls == ShootingControls::kPiecewiseLinear;
  detail::IntervalResult& r = shooting_->result;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const DefectBlock& block = blocks_[k];
    const int a = block.terms[0].point, b = block.terms[1].point;
    const PointVector wa = x.segment<kPointSize>(kPointSize * a);
    const PointVector wb = x.segment<kPointSize>(kPointSize * b);
    const double delta = layout_.mesh[k + 1] - layout_.mesh[k];
    if (!shooting_->integrator.integrate(wa.head<kStateSize>(), wa.tail<kControlSize>(),
                                         wb.tail<kControlSize>(), tf, delta, true, r)) {
      std::ostringstream text;
      text << "shooting interval " << k << " (from (" << wa(0) << ", " << wa(1)
           << ")): " << r.message;
      message_ = text.str();
      return false;
    }
    constraints_.segment<kStateSize>(block.row) = wb.head<kStateSize>() - r.end;
    Eigen::Matrix<double, kStateSize, kPointSize> ja, jb;
    ja.leftCols<kStateSize>() = -r.sensitivity.leftCols<kStateSize>();
    ja.rightCols<kControlSize>() = -r.sensitivity.middleCols<kControlSize>(kStateSize);
    jb.setZero();
    jb.leftCols<kStateSize>().setIdentity();
    if (linear) {
      jb.rightCols<kControlSize>() =
          -r.sensitivity.middleCols<kControlSize>(kStateSize + kControlSize);
    }
    int entry = block.jac_start;
    for (const auto* jac : {&ja, &jb}) {
      for (int i = 0; i < kStateSize; ++i) {
        for (int j = 0; j < kPointSize; ++j) jac_values_(entry++) = (*jac)(i, j);
      }
    }
    const Eigen::Index tf_column = r.sensitivity.cols() - 1;
    for (int i = 0; i < kStateSize; ++i) jac_values_(entry++) = -r.sensitivity(i, tf_column);
  }
  return true;
}

void TranscriptionNlp::evaluatePathAndCost(const Eigen::Map<const Eigen::VectorXd>& x) {
  const double tf = x(finalTimeIndex());
  const int count = model_->constraintCount();
  int entry = path_jac_start_;
  double mean_running = 0.0;
  gradient_.setZero();
  for (int p = 0; p < points(); ++p) {
    const PointEvaluation& e = evals_[static_cast<std::size_t>(p)];
    constraints_.segment(defect_rows_ + count * p, count) = e.constraints;
    for (int r = 0; r < count; ++r) {
      for (int j = 0; j < kPointSize; ++j) jac_values_(entry++) = e.constraint_jacobian(r, j);
    }
    const double weight = weights_[static_cast<std::size_t>(p)];
    mean_running += weight * e.running_cost;
    gradient_.segment<kPointSize>(kPointSize * p) = tf * weight * e.running_cost_gradient;
  }
  objective_ = tf * (1.0 + mean_running);
  gradient_(finalTimeIndex()) = 1.0 + mean_running;
  entry = rest_jac_start_;
  for (std::size_t k = 0; k < rest_.size(); ++k) {
    const RestRow& r = rest_[k];
    const int base = kPointSize * r.point + kStateSize;
    constraints_(defect_rows_ + path_rows_ + static_cast<int>(k)) =
        r.omega_dot * x(base + 1) + r.v_dot * x(base);
    jac_values_(entry++) = r.omega_dot;
    jac_values_(entry++) = r.v_dot;
  }
  bounds_.evaluate(x, constraints_.data() + defect_rows_ + path_rows_ + rest_rows_);
  bounds_.jacobian(jac_values_.data() + bound_jac_start_);
}

bool TranscriptionNlp::evaluate(const double* x_data) {
  const Eigen::Map<const Eigen::VectorXd> x(x_data, variableCount());
  if (has_last_ && x == last_x_) return last_ok_;
  has_last_ = true;
  last_x_ = x;
  message_.clear();
  last_ok_ = false;
  if (!x.allFinite()) {
    message_ = "non-finite variables";
    return false;
  }
  if (!evaluatePoints(x)) return false;
  const bool ok = layout_.scheme == TranscriptionScheme::kMultipleShooting ? evaluateShooting(x)
                                                                           : evaluateCollocation(x);
  if (!ok) return false;
  evaluatePathAndCost(x);
  if (!std::isfinite(objective_) || !gradient_.allFinite() || !constraints_.allFinite() ||
      !jac_values_.allFinite()) {
    message_ = "non-finite cost, constraints or derivatives";
    return false;
  }
  last_ok_ = true;
  return true;
}

bool TranscriptionNlp::pointLagrangianGradient(const PointVector& w, const StateVector& nu,
                                               const double* mu, double c,
                                               models::AttitudeWorkspace& workspace,
                                               PointVector& out) {
  if (model_->evaluate(w, workspace, scratch_) != models::AttitudeStatus::kOk) return false;
  out = scratch_.rate_jacobian.transpose() * nu + c * scratch_.running_cost_gradient;
  const int count = model_->constraintCount();
  for (int r = 0; r < count; ++r) {
    if (mu[r] != 0.0) out += mu[r] * scratch_.constraint_jacobian.row(r).transpose();
  }
  return true;
}

bool TranscriptionNlp::hessian(const double* x_data, double sigma, const double* lambda,
                               double* values) {
  if (!hasExactHessian() || !evaluate(x_data)) return false;
  const Eigen::Map<const Eigen::VectorXd> x(x_data, variableCount());
  const double tf = x(finalTimeIndex());
  // nu_p = sum over defect terms at p of beta lambda_block.
  std::vector<StateVector>& nu = nu_;
  for (StateVector& v : nu) v.setZero();
  for (const DefectBlock& block : blocks_) {
    const Eigen::Map<const StateVector> l(lambda + block.row);
    for (const Term& term : block.terms) nu[static_cast<std::size_t>(term.point)] += term.beta * l;
  }
  const int count = model_->constraintCount();
  int entry = 0;
  for (int p = 0; p < points(); ++p) {
    const std::size_t ps = static_cast<std::size_t>(p);
    const PointVector w = x.segment<kPointSize>(kPointSize * p);
    const StateVector scaled_nu = -tf * nu[ps];
    const double* mu = lambda + defect_rows_ + count * p;
    const double c = sigma * tf * weights_[ps];
    Eigen::Matrix<double, kPointSize, kPointSize> h;
    for (int i = 0; i < kPointSize; ++i) {
      const double step = i < 2 && layout_.hessian_position_step > 0.0
                              ? layout_.hessian_position_step
                              : kHessianStep * (1.0 + std::abs(w(i)));
      PointVector plus = w, minus = w, g_plus, g_minus;
      plus(i) += step;
      minus(i) -= step;
      models::AttitudeWorkspace workspace = workspaces_[ps];
      const bool has_plus = pointLagrangianGradient(plus, scaled_nu, mu, c, workspace, g_plus);
      workspace = workspaces_[ps];
      const bool has_minus = pointLagrangianGradient(minus, scaled_nu, mu, c, workspace, g_minus);
      if (has_plus && has_minus) {
        h.col(i) = (g_plus - g_minus) / (2.0 * step);
        continue;
      }
      // One side undefined (the point lies beside no data, where the surface ends): a
      // one-sided difference from the point itself.
      PointVector g_here;
      workspace = workspaces_[ps];
      if ((!has_plus && !has_minus) ||
          !pointLagrangianGradient(w, scaled_nu, mu, c, workspace, g_here)) {
        return false;
      }
      h.col(i) = has_plus ? (g_plus - g_here) / step : (g_here - g_minus) / step;
    }
    h = 0.5 * (h + h.transpose()).eval();
    for (int i = 0; i < kPointSize; ++i) {
      for (int j = 0; j <= i; ++j) values[entry++] = h(i, j);
    }
    // d^2 L / d t_f d w_p = -nu' df/dw + sigma omega_p dl/dw.
    const PointEvaluation& e = evals_[ps];
    const PointVector cross =
        -(e.rate_jacobian.transpose() * nu[ps]) + sigma * weights_[ps] * e.running_cost_gradient;
    for (int j = 0; j < kPointSize; ++j) values[entry++] = cross(j);
  }
  values[entry] = 0.0;  // L is linear in t_f
  const Eigen::Map<const Eigen::VectorXd> all(values, entry + 1);
  if (!all.allFinite()) {
    message_ = "non-finite Hessian";
    return false;
  }
  return true;
}

Eigen::VectorXd initialVariables(const TranscriptionNlp& nlp, const BoundaryValueProblem& problem,
                                 const TranscriptionGuess& guess) {
  Eigen::VectorXd x(nlp.variableCount());
  const double tf = guess.finalTime();
  for (int p = 0; p < nlp.points(); ++p) {
    x.segment<kPointSize>(kPointSize * p) =
        guess.at(tf * nlp.pointTimes()[static_cast<std::size_t>(p)]);
  }
  x(nlp.finalTimeIndex()) = tf;
  const VehicleState& s = problem.start;
  const VehicleState& g = problem.goal;
  const double first_heading = x(2);
  x.head<kStateSize>() << s.x, s.y, first_heading + wrapAngle(s.heading - first_heading), s.v,
      s.omega;
  const int last = kPointSize * (nlp.points() - 1);
  const double last_heading = x(last + 2);
  x.segment<kStateSize>(last) << g.x, g.y, last_heading + wrapAngle(g.heading - last_heading), g.v,
      g.omega;
  return x;
}

}  // namespace terratraj::ocp
