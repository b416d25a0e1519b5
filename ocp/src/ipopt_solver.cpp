#include "terratraj/ocp/ipopt_solver.hpp"

// Ipopt's headers need HAVE_CSTDDEF (set for this target in ocp/CMakeLists.txt).
#include <coin/IpDenseVector.hpp>
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpIpoptCalculatedQuantities.hpp>
#include <coin/IpIpoptData.hpp>
#include <coin/IpIteratesVector.hpp>
#include <coin/IpTNLP.hpp>

#include <Eigen/Dense>
#include <algorithm>
#include <cmath>
#include <deque>
#include <limits>
#include <sstream>
#include <string>
#include <vector>

#include "ipopt_common.hpp"
#include "solve_accounting.hpp"

namespace terratraj::ocp {
namespace {

using RowMajorMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

constexpr double kMinFinalTime = 1e-3;  // lower bound of t_f [s]
using detail::kIpoptInfinity;
constexpr std::size_t kRecentPoints = 32;  // evaluated points kept for the history records
// The rest ends' curvature rows aim this far inside kappa_max: the check reads the curvature at
// rest from the first moving sample, where the second-order terms of omega / v add to
// omega' / v'.
constexpr double kRestCurvatureMargin = 0.98;

// A point Ipopt asked about, for the per-iteration history.
struct RecentPoint {
  Eigen::VectorXd q;
  Eigen::Vector3d terminal_error;
  double cost;
};

// Ipopt's constr_viol_tol for the criteria: a tenth of the smaller end tolerance.
double constraintViolationTolerance(const ConvergenceCriteria& c) {
  return 0.1 * std::min(c.position_m, c.heading_rad);
}

// The NLP in Ipopt's terms. Every callback works on one cached evaluation keyed on x (Ipopt
// asks for f, grad f, g and its Jacobian at the same x): one integration per new x. No
// callback lets an exception escape; an integration failure returns false, which Ipopt treats
// as an evaluation error (it shortens the step, or stops at the starting point).
class TrajectoryNlp final : public Ipopt::TNLP {
 public:
  TrajectoryNlp(ParametricTrajectoryModel& model, const PathConstraints* constraints,
                const IpoptOptions& options, const Eigen::VectorXd& q0,
                const detail::SolveAccounting& accounting, std::vector<IterationRecord>& history)
      : model_(model),
        constraints_(constraints),
        options_(options),
        q0_(q0),
        accounting_(accounting),
        history_(history),
        n_(model.parameterCount()),
        rows_per_point_(constraints != nullptr ? constraints->count() : 0) {
    if (rows_per_point_ > 0) {
      const int points = options.path_points;
      tau_.resize(static_cast<std::size_t>(points));
      for (int i = 0; i < points; ++i) {
        tau_[static_cast<std::size_t>(i)] = static_cast<double>(i) / (points - 1);
      }
      // The last point at exactly t_f.
      tau_.back() = 1.0;
      // At an end at rest the curvature rows (|omega| <= kappa_max v) only hold omega at 0; the
      // curvature there is the limit omega' / v', held by two rows per rest end.
      const BoundaryValueProblem& problem = model.problem();
      const double kappa = problem.limits.kappa_max;
      if (std::isfinite(kappa) && kappa > 0.0) {
        rest_kappa_ = kRestCurvatureMargin * kappa;
        rest_start_ = standsStill(problem.start);
        rest_goal_ = standsStill(problem.goal);
      }
    }
    path_rows_ = rows_per_point_ * static_cast<int>(tau_.size());
    m_ = 3 + path_rows_ + 2 * (static_cast<int>(rest_start_) + static_cast<int>(rest_goal_));
    values_.resize(m_);
    jacobian_.resize(m_, n_);
  }

  // Evaluates everything at x (n_ values) unless cached. Returns false when the integration
  // fails or produces non-finite values; message() says why.
  bool update(const double* x) {
    const Eigen::Map<const Eigen::VectorXd> q(x, n_);
    if (has_cache_ && q == cache_q_) return cache_ok_;
    has_cache_ = true;
    cache_q_ = q;
    cache_ok_ = false;
    message_.clear();
    // Past the time limit, once Ipopt iterates, no new point is integrated (one integration can
    // take seconds where the dynamics are stiff): its line search fails at once and the solve
    // ends timed out. (The starting point is always evaluated: the first iteration's callback
    // stops a solve whose limit has passed.)
    if (!history_.empty() && accounting_.pastTimeLimit(options_.time_limit_s, options_.stop)) {
      timed_out_ = true;
      message_ = "time limit reached";
      return false;
    }
    bool ok;
    if (rows_per_point_ > 0) {
      ok = model_.evaluateWithPath(cache_q_, true, tau_, eval_, path_);
    } else {
      ok = model_.evaluate(cache_q_, DerivativeMode::kSensitivity, eval_);
    }
    if (!ok) {
      message_ = eval_.message;
      return false;
    }
    values_.head<3>() = eval_.terminal_error;
    jacobian_.topRows<3>() = eval_.jacobian;
    for (std::size_t i = 0; i < tau_.size(); ++i) {
      const Eigen::Index row = 3 + static_cast<Eigen::Index>(i) * rows_per_point_;
      constraints_->evaluate(path_.points[i], values_.data() + row, &point_jacobian_);
      jacobian_.middleRows(row, rows_per_point_) = point_jacobian_ * path_.derivatives[i];
    }
    Eigen::Index rest_row = 3 + path_rows_;
    if (rest_start_) addRestRows(0, +1.0, rest_row);
    if (rest_goal_) addRestRows(tau_.size() - 1, -1.0, rest_row);
    if (!std::isfinite(eval_.cost) || !eval_.gradient.allFinite() || !values_.allFinite() ||
        !jacobian_.allFinite()) {
      message_ = "non-finite cost, constraints or derivatives";
      return false;
    }
    recent_.push_back({cache_q_, eval_.terminal_error, eval_.cost});
    if (recent_.size() > kRecentPoints) recent_.pop_front();
    cache_ok_ = true;
    return true;
  }

  const std::string& message() const { return message_; }
  const ParametricEvaluation& evaluation() const { return eval_; }
  const Eigen::VectorXd& constraintValues() const { return values_; }
  int constraintCount() const { return m_; }
  int rowsPerPoint() const { return rows_per_point_; }
  int pathRows() const { return path_rows_; }
  bool restStart() const { return rest_start_; }
  bool finalized() const { return finalized_; }
  const Eigen::VectorXd& finalX() const { return final_x_; }
  const Eigen::VectorXd& finalLambda() const { return final_lambda_; }
  bool timedOut() const { return timed_out_; }
  int lastIteration() const { return last_iteration_; }

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac_g,
                    Ipopt::Index& nnz_h_lag, IndexStyleEnum& index_style) override {
    n = n_;
    m = m_;
    nnz_jac_g = n_ * m_;  // dense
    nnz_h_lag = 0;        // limited-memory quasi-Newton
    index_style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override {
    for (Ipopt::Index k = 0; k < n; ++k) {
      x_l[k] = -kIpoptInfinity;
      x_u[k] = kIpoptInfinity;
    }
    x_l[model_.finalTimeIndex()] = kMinFinalTime;
    if (options_.max_final_time_s) x_u[model_.finalTimeIndex()] = *options_.max_final_time_s;
    for (Ipopt::Index i = 0; i < m; ++i) {
      g_l[i] = i < 3 ? 0.0 : -kIpoptInfinity;
      g_u[i] = 0.0;
    }
    freeDegenerateRestRows(g_u);
    return true;
  }

  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                          Ipopt::Number* /*z_L*/, Ipopt::Number* /*z_U*/, Ipopt::Index /*m*/,
                          bool init_lambda, Ipopt::Number* /*lambda*/) override {
    if (init_z || init_lambda) return false;  // only x is supplied
    if (init_x) std::copy(q0_.data(), q0_.data() + n, x);
    return true;
  }

  bool eval_f(Ipopt::Index /*n*/, const Ipopt::Number* x, bool /*new_x*/,
              Ipopt::Number& obj_value) override {
    return detail::guardedCallback([&] {
      if (!update(x)) return false;
      obj_value = eval_.cost;
      return true;
    });
  }

  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool /*new_x*/,
                   Ipopt::Number* grad_f) override {
    return detail::guardedCallback([&] {
      if (!update(x)) return false;
      std::copy(eval_.gradient.data(), eval_.gradient.data() + n, grad_f);
      return true;
    });
  }

  bool eval_g(Ipopt::Index /*n*/, const Ipopt::Number* x, bool /*new_x*/, Ipopt::Index m,
              Ipopt::Number* g) override {
    return detail::guardedCallback([&] {
      if (!update(x)) return false;
      std::copy(values_.data(), values_.data() + m, g);
      return true;
    });
  }

  bool eval_jac_g(Ipopt::Index /*n*/, const Ipopt::Number* x, bool /*new_x*/, Ipopt::Index /*m*/,
                  Ipopt::Index nele_jac, Ipopt::Index* iRow, Ipopt::Index* jCol,
                  Ipopt::Number* values) override {
    return detail::guardedCallback([&] {
      if (values == nullptr) {
        // Structure: dense, row-major.
        for (Ipopt::Index k = 0; k < nele_jac; ++k) {
          iRow[k] = k / n_;
          jCol[k] = k % n_;
        }
        return true;
      }
      if (!update(x)) return false;
      std::copy(jacobian_.data(), jacobian_.data() + nele_jac, values);
      return true;
    });
  }

  void finalize_solution(Ipopt::SolverReturn /*status*/, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number* /*z_L*/, const Ipopt::Number* /*z_U*/, Ipopt::Index m,
                         const Ipopt::Number* /*g*/, const Ipopt::Number* lambda,
                         Ipopt::Number /*obj_value*/, const Ipopt::IpoptData* /*ip_data*/,
                         Ipopt::IpoptCalculatedQuantities* /*ip_cq*/) override {
    if (x == nullptr || lambda == nullptr) return;
    finalized_ = detail::guardedCallback([&] {
      final_x_ = Eigen::Map<const Eigen::VectorXd>(x, n);
      final_lambda_ = Eigen::Map<const Eigen::VectorXd>(lambda, m);
      return true;
    });
  }

  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter,
                             Ipopt::Number /*obj_value*/, Ipopt::Number inf_pr,
                             Ipopt::Number inf_du, Ipopt::Number /*mu*/, Ipopt::Number /*d_norm*/,
                             Ipopt::Number /*regularization_size*/, Ipopt::Number /*alpha_du*/,
                             Ipopt::Number alpha_pr, Ipopt::Index /*ls_trials*/,
                             const Ipopt::IpoptData* ip_data,
                             Ipopt::IpoptCalculatedQuantities* ip_cq) override {
    return detail::guardedCallback([&] {
      last_iteration_ = iter;
      IterationRecord record;
      record.iteration = iter;
      record.lagrangian_gradient = inf_du;
      record.step = alpha_pr;
      const RecentPoint* point = currentPoint(mode, ip_data);
      if (point != nullptr) {
        record.terminal_error = point->terminal_error.head<2>().norm();
        record.heading_error = std::abs(point->terminal_error.z());
        record.cost = point->cost;
      } else {
        record.terminal_error = record.heading_error = record.cost =
            std::numeric_limits<double>::quiet_NaN();
      }
      history_.push_back(record);
      if (accounting_.pastTimeLimit(options_.time_limit_s, options_.stop)) {
        timed_out_ = true;
        return false;  // User_Requested_Stop
      }
      if (point != nullptr && meetsCriteria(*point, inf_pr, inf_du, ip_cq)) {
        if (!accepted_ || point->cost < accepted_->cost) accepted_ = *point;
        // Wandering: Ipopt has not met its own test long after the criteria were met.
        if (iter >= options_.wandering_iterations) return false;  // User_Requested_Stop
      }
      return true;
    });
  }

  /// The iterate of lowest cost that met the criteria (Ipopt's own termination test is much
  /// tighter); nothing when none did. The solve's answer when Ipopt ends without success.
  const std::optional<RecentPoint>& accepted() const { return accepted_; }

 private:
  // The rows of a fixed end at rest that vanish there (detail::degenerateAtRestEnd) are freed.
  void freeDegenerateRestRows(Ipopt::Number* g_u) const {
    if (rows_per_point_ == 0) return;
    const BoundaryValueProblem& problem = model_.problem();
    const int last = static_cast<int>(tau_.size()) - 1;
    for (const int point : {0, last}) {
      const VehicleState& end = point == 0 ? problem.start : problem.goal;
      for (int r = 0; r < rows_per_point_; ++r) {
        if (detail::degenerateAtRestEnd(end, constraints_->name(r))) {
          g_u[3 + point * rows_per_point_ + r] = kIpoptInfinity;
        }
      }
    }
  }

  // The rows +-omega' - direction kappa v' <= 0 at path point `point` (an end at rest; direction
  // +1 at the start, where v' >= 0, -1 at the goal), from row `row` on (advanced by 2).
  void addRestRows(std::size_t point, double direction, Eigen::Index& row) {
    constexpr int kVDot = 5, kOmegaDot = 6;  // PathPoint variables (path_constraints.hpp)
    const PathPoint& p = path_.points[point];
    const auto& d = path_.derivatives[point];
    for (const double sign : {1.0, -1.0}) {
      values_(row) = sign * p.omega_dot - direction * rest_kappa_ * p.v_dot;
      jacobian_.row(row) = sign * d.row(kOmegaDot) - direction * rest_kappa_ * d.row(kVDot);
      ++row;
    }
  }

  // The iterate of this iteration among the recently evaluated points (Ipopt evaluated it
  // before the callback); in the restoration phase (whose iterate is not q) the last point
  // evaluated. Null when none is known.
  // The solve's criteria at an iterate: the terminal error within them, the path rows within
  // the constraint tolerance, and stationarity (Ipopt's scaled dual infeasibility, and its
  // whole optimality error: dual, primal and complementarity) within the Lagrangian gradient
  // criterion. Ipopt's own `tol` is 100 times tighter; on rough terrain its iterates can wander
  // for hundreds of iterations at a point these criteria already accept (the robustness set's
  // davosdorf problems: 300 iterations, the criteria met from the 30th on).
  bool meetsCriteria(const RecentPoint& point, double inf_pr, double inf_du,
                     Ipopt::IpoptCalculatedQuantities* ip_cq) const {
    const ConvergenceCriteria& c = options_.criteria;
    if (!(point.terminal_error.head<2>().norm() <= c.position_m) ||
        !(std::abs(point.terminal_error.z()) <= c.heading_rad) ||
        !(inf_pr <= constraintViolationTolerance(c)) || !(inf_du <= c.lagrangian_gradient) ||
        ip_cq == nullptr) {
      return false;
    }
    return ip_cq->curr_nlp_error() <= c.lagrangian_gradient;
  }

  const RecentPoint* currentPoint(Ipopt::AlgorithmMode mode, const Ipopt::IpoptData* ip_data) {
    if (mode == Ipopt::RegularMode && ip_data != nullptr && Ipopt::IsValid(ip_data->curr())) {
      const auto* x =
          dynamic_cast<const Ipopt::DenseVector*>(Ipopt::GetRawPtr(ip_data->curr()->x()));
      if (x != nullptr && x->Dim() == n_) {
        const Eigen::Map<const Eigen::VectorXd> q(x->ExpandedValues(), n_);
        for (auto it = recent_.rbegin(); it != recent_.rend(); ++it) {
          if (it->q == q) return &*it;
        }
        // Not evaluated by a callback (should not happen): one integration without derivatives.
        if (model_.evaluate(q, DerivativeMode::kNone, scratch_)) {
          recent_.push_back({q, scratch_.terminal_error, scratch_.cost});
          if (recent_.size() > kRecentPoints) recent_.pop_front();
          return &recent_.back();
        }
        return nullptr;
      }
    }
    return recent_.empty() ? nullptr : &recent_.back();
  }

  ParametricTrajectoryModel& model_;
  const PathConstraints* constraints_;  // null or no rows: terminal equalities only
  const IpoptOptions& options_;
  Eigen::VectorXd q0_;
  const detail::SolveAccounting& accounting_;
  std::vector<IterationRecord>& history_;
  int n_;
  int rows_per_point_;
  int path_rows_ = 0;  // rows_per_point_ per path point
  int m_ = 3;
  std::vector<double> tau_;
  bool rest_start_ = false, rest_goal_ = false;  // ends at rest: their curvature rows
  double rest_kappa_ = 0.0;                      // [1/m]

  // The cached evaluation.
  bool has_cache_ = false;
  bool cache_ok_ = false;
  Eigen::VectorXd cache_q_;
  ParametricEvaluation eval_, scratch_;
  PathEvaluation path_;
  Eigen::VectorXd values_;   // m_: c, then the path rows point by point
  RowMajorMatrix jacobian_;  // m_ x n_
  Eigen::Matrix<double, Eigen::Dynamic, kPathVariables> point_jacobian_;
  std::string message_;
  std::deque<RecentPoint> recent_;

  // The outcome.
  bool finalized_ = false;
  Eigen::VectorXd final_x_, final_lambda_;
  bool timed_out_ = false;
  std::optional<RecentPoint> accepted_;
  int last_iteration_ = 0;
};

// The worst violated row of the constraint values `values` (terminal rows by their absolute
// value), for reasons.
std::string worstConstraint(const TrajectoryNlp& nlp, const PathConstraints* constraints) {
  const Eigen::VectorXd& values = nlp.constraintValues();
  static const char* const kTerminal[] = {"terminal x", "terminal y", "terminal heading"};
  int worst = 0;
  double amount = 0.0;
  for (int i = 0; i < nlp.constraintCount(); ++i) {
    const double violation = i < 3 ? std::abs(values(i)) : values(i);
    if (violation > amount) {
      amount = violation;
      worst = i;
    }
  }
  std::ostringstream text;
  if (amount <= 0.0) return "no constraint violated at the final point";
  if (worst < 3) {
    text << kTerminal[worst];
  } else if (worst >= 3 + nlp.pathRows()) {
    const bool at_start = nlp.restStart() && worst < 3 + nlp.pathRows() + 2;
    text << "kappa_max at the " << (at_start ? "start" : "goal") << " (at rest: omega' / v')";
  } else {
    const int row = (worst - 3) % nlp.rowsPerPoint();
    const int point = (worst - 3) / nlp.rowsPerPoint();
    text << constraints->name(row) << " at path point " << point;
  }
  text << " violated by " << amount;
  return text.str();
}

SolveResult runIpopt(ParametricTrajectoryModel& model, const PathConstraints* constraints,
                     const Eigen::VectorXd& q0, const IpoptOptions& options, SolveResult& result,
                     const detail::SolveAccounting& accounting) {
  const auto finish = [&](SolveStatus status, std::string reason) {
    return accounting.finish(status, std::move(reason));
  };
  const int n = model.parameterCount();
  const bool with_path =
      constraints != nullptr && options.path_constraints && constraints->count() > 0;
  if (q0.size() != n) return finish(SolveStatus::kError, "initial guess has the wrong size");
  if (with_path && options.path_points < 2) {
    return finish(SolveStatus::kError, "path_points must be >= 2");
  }
  if (options.max_iterations < 0) return finish(SolveStatus::kError, "max_iterations < 0");
  if (options.wandering_iterations < 0) {
    return finish(SolveStatus::kError, "wandering_iterations < 0");
  }
  if (options.max_final_time_s && !(*options.max_final_time_s > kMinFinalTime &&
                                    *options.max_final_time_s >= q0(model.finalTimeIndex()))) {
    return finish(SolveStatus::kError, "max_final_time_s must be above 1e-3 s and the guess's t_f");
  }
  if (options.time_limit_s && !(*options.time_limit_s >= 0.0)) {
    return finish(SolveStatus::kError, "time_limit_s must be >= 0");
  }

  Ipopt::SmartPtr<TrajectoryNlp> nlp = new TrajectoryNlp(model, with_path ? constraints : nullptr,
                                                         options, q0, accounting, result.history);
  if (!nlp->update(q0.data())) {
    return finish(SolveStatus::kDiverged, "initial guess: " + nlp->message());
  }
  result.cost = nlp->evaluation().cost;
  result.terminal_error = nlp->evaluation().terminal_error;

  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& ipopt = *app->Options();
  const ConvergenceCriteria& criteria = options.criteria;
  const double constr_viol_tol = constraintViolationTolerance(criteria);
  detail::IpoptBaseSettings base;
  base.print_level = options.print_level;
  base.max_iterations = options.max_iterations;
  base.max_cpu_time_s = options.time_limit_s;
  const bool options_ok =
      detail::setBaseOptions(ipopt, base) &&
      ipopt.SetStringValue("hessian_approximation", "limited-memory") &&
      ipopt.SetNumericValue("tol",
                            std::min(constr_viol_tol, 0.01 * criteria.lagrangian_gradient)) &&
      ipopt.SetNumericValue("constr_viol_tol", constr_viol_tol) &&
      ipopt.SetNumericValue("dual_inf_tol", criteria.lagrangian_gradient) &&
      ipopt.SetNumericValue("acceptable_constr_viol_tol", constr_viol_tol) &&
      ipopt.SetNumericValue("acceptable_dual_inf_tol", criteria.lagrangian_gradient);
  if (!options_ok) {
    return finish(SolveStatus::kError,
                  "Ipopt rejected an option (check the criteria, print_level in [0, 12])");
  }
  if (!detail::initializeIpopt(*app)) {
    return finish(SolveStatus::kError, "Ipopt could not be initialised");
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(Ipopt::GetRawPtr(nlp));

  result.iterations = result.history.empty() ? 0 : nlp->lastIteration();
  Eigen::VectorXd q = nlp->finalized() ? nlp->finalX() : q0;
  if (q.size() != n || !q.allFinite()) q = q0;
  detail::IpoptOutcome outcome =
      detail::ipoptOutcome(status, nlp->timedOut(), options.max_iterations, options.time_limit_s,
                           options.stop != nullptr && options.stop->load());
  // Ended without success (wandering, the iteration or time limit, a failed restoration) after
  // an iterate met the criteria: that iterate is the answer (re-simulated and checked after).
  if (outcome.status != SolveStatus::kConverged && nlp->accepted()) {
    q = nlp->accepted()->q;
    outcome = {SolveStatus::kConverged, ""};
  }
  result.q = q;
  result.time_limit_reached = outcome.status != SolveStatus::kConverged &&
                              (nlp->timedOut() || status == Ipopt::Maximum_CpuTime_Exceeded);
  if (nlp->finalized() && nlp->finalLambda().size() >= 3) {
    result.lambda = nlp->finalLambda().head<3>();
  }
  const bool final_ok = nlp->update(q.data());
  if (final_ok) {
    result.cost = nlp->evaluation().cost;
    result.terminal_error = nlp->evaluation().terminal_error;
  }
  const std::string name = detail::ipoptStatusName(status);
  switch (outcome.status) {
    case SolveStatus::kConverged: {
      if (!final_ok) {
        return finish(SolveStatus::kDiverged,
                      "Ipopt reported " + name + " but the final point fails: " + nlp->message());
      }
      const double position = result.terminal_error.head<2>().norm();
      const double heading = std::abs(result.terminal_error.z());
      if (position <= criteria.position_m && heading <= criteria.heading_rad) {
        return finish(SolveStatus::kConverged, "");
      }
      std::ostringstream text;
      text << "Ipopt reported " << name << " but the terminal error is " << position << " m, "
           << heading << " rad (criteria " << criteria.position_m << " m, " << criteria.heading_rad
           << " rad)";
      return finish(SolveStatus::kDiverged, text.str());
    }
    case SolveStatus::kInfeasible:
      return finish(
          SolveStatus::kInfeasible,
          outcome.reason + ": " + (final_ok ? worstConstraint(*nlp, constraints) : nlp->message()));
    case SolveStatus::kMaxIterations:
      return finish(outcome.status, outcome.reason);
    default: {
      std::string reason = outcome.reason;
      if (!nlp->message().empty()) reason += " (last evaluation: " + nlp->message() + ")";
      return finish(outcome.status, reason);
    }
  }
}

}  // namespace

SolveResult solveIpopt(ParametricTrajectoryModel& model, const PathConstraints* constraints,
                       const Eigen::VectorXd& q0, const IpoptOptions& options) {
  SolveResult result;
  result.q = q0;
  const detail::SolveAccounting accounting(model, result, "ipopt");
  return detail::guardThirdParty("Ipopt", accounting, [&] {
    return runIpopt(model, constraints, q0, options, result, accounting);
  });
}

}  // namespace terratraj::ocp
