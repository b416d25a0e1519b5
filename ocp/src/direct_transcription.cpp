#include "terratraj/ocp/direct_transcription.hpp"

// Ipopt's headers need HAVE_CSTDDEF (set for this target in ocp/CMakeLists.txt).
#include <coin/IpIpoptApplication.hpp>
#include <coin/IpIpoptCalculatedQuantities.hpp>
#include <coin/IpTNLP.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <sstream>
#include <string>

#include "ipopt_common.hpp"

namespace terratraj::ocp {
namespace {

using detail::kIpoptInfinity;
// A path constraint is reported active when g > -kActiveTolerance.
constexpr double kActiveTolerance = 1e-6;
// Sub-steps of RK4 per interval when estimating an interval's local error.
constexpr int kErrorSubsteps = 32;

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// The adapter between TranscriptionNlp and Ipopt. No callback lets an exception escape; an
// evaluation failure returns false (Ipopt shortens the step).
class IpoptTranscription final : public Ipopt::TNLP {
 public:
  IpoptTranscription(TranscriptionNlp& nlp, const BoundaryValueProblem& problem,
                     const Eigen::VectorXd& x0, const DirectTranscriptionOptions& options,
                     Clock::time_point started, std::vector<IterationRecord>& history)
      : nlp_(nlp),
        problem_(problem),
        x0_(x0),
        options_(options),
        started_(started),
        history_(history),
        stall_(options.stall),
        divergence_(options.divergence),
        // A later solve of a call (mesh round, retry) times its first step from now.
        previous_elapsed_(secondsSince(started)) {}

  bool get_nlp_info(Ipopt::Index& n, Ipopt::Index& m, Ipopt::Index& nnz_jac, Ipopt::Index& nnz_h,
                    IndexStyleEnum& style) override {
    n = nlp_.variableCount();
    m = nlp_.constraintCount();
    nnz_jac = static_cast<Ipopt::Index>(nlp_.jacobianRows().size());
    nnz_h = static_cast<Ipopt::Index>(nlp_.hessianRows().size());
    style = C_STYLE;
    return true;
  }

  bool get_bounds_info(Ipopt::Index n, Ipopt::Number* x_l, Ipopt::Number* x_u, Ipopt::Index m,
                       Ipopt::Number* g_l, Ipopt::Number* g_u) override {
    const models::VehicleLimits& l = problem_.limits;
    std::fill(x_l, x_l + n, -kIpoptInfinity);
    std::fill(x_u, x_u + n, kIpoptInfinity);
    for (int p = 0; p < nlp_.points(); ++p) {
      Ipopt::Number* lo = x_l + kPointSize * p;
      Ipopt::Number* hi = x_u + kPointSize * p;
      lo[3] = 0.0;
      hi[3] = l.v_max;
      lo[4] = -l.omega_max;
      hi[4] = l.omega_max;
      lo[5] = -l.a_max;
      hi[5] = l.a_max;
    }
    // The map's extent, inset by the margin (unless the boundary states are closer to its edge).
    const terrain::GridGeometry& map = nlp_.model().kinematics().model().surface().map().geometry();
    const double margin = options_.map_margin;
    const double x_lo = std::min({margin, problem_.start.x, problem_.goal.x});
    const double y_lo = std::min({margin, problem_.start.y, problem_.goal.y});
    const double x_hi = std::max({map.width() - margin, problem_.start.x, problem_.goal.x});
    const double y_hi = std::max({map.height() - margin, problem_.start.y, problem_.goal.y});
    for (int p = 0; p < nlp_.points(); ++p) {
      x_l[kPointSize * p] = x_lo;
      x_u[kPointSize * p] = x_hi;
      x_l[kPointSize * p + 1] = y_lo;
      x_u[kPointSize * p + 1] = y_hi;
    }
    // Boundary states fixed (the goal heading unwrapped next to the guess's, in x0).
    const int last = kPointSize * (nlp_.points() - 1);
    for (int i = 0; i < kStateSize; ++i) {
      x_l[i] = x_u[i] = x0_(i);
      x_l[last + i] = x_u[last + i] = x0_(last + i);
    }
    x_l[nlp_.finalTimeIndex()] = options_.min_final_time;
    x_u[nlp_.finalTimeIndex()] = options_.max_final_time;
    std::fill(g_l, g_l + nlp_.defectRowCount(), 0.0);
    std::fill(g_u, g_u + nlp_.defectRowCount(), 0.0);
    std::fill(g_l + nlp_.defectRowCount(), g_l + m, -kIpoptInfinity);
    std::fill(g_u + nlp_.defectRowCount(), g_u + m, 0.0);
    freeDegenerateRestRows(m, g_u);
    return true;
  }

  // The rows of a fixed end at rest that vanish there (detail::degenerateAtRestEnd) are freed.
  void freeDegenerateRestRows(Ipopt::Index m, Ipopt::Number* g_u) const {
    const int last = nlp_.points() - 1;
    for (Ipopt::Index r = nlp_.defectRowCount(); r < m; ++r) {
      const ConstraintRow row = nlp_.row(r);
      if (row.defect || (row.point != 0 && row.point != last)) continue;
      if (detail::degenerateAtRestEnd(row.point == 0 ? problem_.start : problem_.goal, row.name)) {
        g_u[r] = detail::kIpoptInfinity;
      }
    }
  }

  bool get_scaling_parameters(Ipopt::Number& obj_scaling, bool& use_x_scaling, Ipopt::Index n,
                              Ipopt::Number* x_scaling, bool& use_g_scaling, Ipopt::Index m,
                              Ipopt::Number* g_scaling) override {
    const models::VehicleLimits& l = problem_.limits;
    const double state_scale[kStateSize] = {1.0, 1.0, 1.0, 1.0 / std::max(l.v_max, 1e-3),
                                            1.0 / std::max(l.omega_max, 1e-3)};
    obj_scaling = 1.0 / std::max(x0_(nlp_.finalTimeIndex()), 1e-3);
    use_x_scaling = true;
    std::fill(x_scaling, x_scaling + n, 1.0);
    for (int p = 0; p < nlp_.points(); ++p) {
      for (int i = 0; i < kStateSize; ++i) x_scaling[kPointSize * p + i] = state_scale[i];
      x_scaling[kPointSize * p + 5] = 1.0 / std::max(l.a_max, 1e-3);
    }
    x_scaling[nlp_.finalTimeIndex()] = obj_scaling;
    use_g_scaling = true;
    std::fill(g_scaling, g_scaling + m, 1.0);
    for (int r = 0; r < nlp_.controlRowStart(); ++r) g_scaling[r] = state_scale[r % kStateSize];
    for (int r = nlp_.controlRowStart(); r < nlp_.defectRowCount(); ++r) {
      g_scaling[r] =
          (r - nlp_.controlRowStart()) % kControlSize == 0 ? 1.0 / std::max(l.a_max, 1e-3) : 1.0;
    }
    return true;
  }

  bool get_starting_point(Ipopt::Index n, bool init_x, Ipopt::Number* x, bool init_z,
                          Ipopt::Number*, Ipopt::Number*, Ipopt::Index, bool init_lambda,
                          Ipopt::Number*) override {
    if (init_z || init_lambda) return false;
    if (init_x) std::copy(x0_.data(), x0_.data() + n, x);
    return true;
  }

  bool eval_f(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number& obj) override {
    return detail::guardedCallback([&] {
      if (!nlp_.evaluate(x)) return false;
      obj = nlp_.objective();
      return true;
    });
  }
  bool eval_grad_f(Ipopt::Index n, const Ipopt::Number* x, bool, Ipopt::Number* grad) override {
    return detail::guardedCallback([&] {
      if (!nlp_.evaluate(x)) return false;
      std::copy(nlp_.gradient().data(), nlp_.gradient().data() + n, grad);
      return true;
    });
  }
  bool eval_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index m,
              Ipopt::Number* g) override {
    return detail::guardedCallback([&] {
      if (!nlp_.evaluate(x)) return false;
      std::copy(nlp_.constraints().data(), nlp_.constraints().data() + m, g);
      return true;
    });
  }
  bool eval_jac_g(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Index, Ipopt::Index nele,
                  Ipopt::Index* rows, Ipopt::Index* cols, Ipopt::Number* values) override {
    return detail::guardedCallback([&] {
      if (values == nullptr) {
        std::copy(nlp_.jacobianRows().begin(), nlp_.jacobianRows().end(), rows);
        std::copy(nlp_.jacobianCols().begin(), nlp_.jacobianCols().end(), cols);
        return true;
      }
      if (!nlp_.evaluate(x)) return false;
      std::copy(nlp_.jacobianValues().data(), nlp_.jacobianValues().data() + nele, values);
      return true;
    });
  }
  bool eval_h(Ipopt::Index, const Ipopt::Number* x, bool, Ipopt::Number sigma, Ipopt::Index,
              const Ipopt::Number* lambda, bool, Ipopt::Index, Ipopt::Index* rows,
              Ipopt::Index* cols, Ipopt::Number* values) override {
    return detail::guardedCallback([&] {
      if (values == nullptr) {
        std::copy(nlp_.hessianRows().begin(), nlp_.hessianRows().end(), rows);
        std::copy(nlp_.hessianCols().begin(), nlp_.hessianCols().end(), cols);
        return true;
      }
      return nlp_.hessian(x, sigma, lambda, values);
    });
  }

  bool intermediate_callback(Ipopt::AlgorithmMode mode, Ipopt::Index iter, Ipopt::Number obj_value,
                             Ipopt::Number inf_pr, Ipopt::Number inf_du, Ipopt::Number mu,
                             Ipopt::Number, Ipopt::Number, Ipopt::Number, Ipopt::Number alpha_pr,
                             Ipopt::Index, const Ipopt::IpoptData*,
                             Ipopt::IpoptCalculatedQuantities* quantities) override {
    return detail::guardedCallback([&] {
      // Ipopt 3.11 passes its internal primal infeasibility: scaled, and with the slacks of the
      // inequality rows (d(x) - s), which stays large on a cycle at a kink while every row
      // holds. The stall test and the history want the original rows' violation, unscaled (the
      // quantity constr_viol_tol bounds; cached by Ipopt's own convergence test).
      const double violation =
          mode == Ipopt::RegularMode && quantities != nullptr
              ? quantities->unscaled_curr_nlp_constraint_violation(Ipopt::NORM_MAX)
              : inf_pr;
      IterationRecord record;
      record.iteration = static_cast<int>(history_.size());
      record.terminal_error = violation;  // the defects: terminal states are bounds
      record.cost = obj_value;
      record.lagrangian_gradient = inf_du;
      record.step = alpha_pr;
      history_.push_back(record);
      last_iteration_ = iter;
      if (mode == Ipopt::RegularMode && stall_.accept(obj_value, violation, inf_du, mu)) {
        stalled_ = true;  // cycling at a kink of the terrain, at a feasible iterate
        return false;
      }
      last_inf_pr_ = violation;
      if (mode == Ipopt::RegularMode && divergence_.diverged(inf_du)) {
        diverged_ = true;  // blown up: its factorisations slow to seconds
        return false;
      }
      if (options_.stop != nullptr && options_.stop->load()) {
        timed_out_ = true;  // stopped on request: as at the time limit
        return false;
      }
      if (options_.time_limit_s) {
        // Stop when the next iteration (as long as the last one) would end past the limit.
        const double elapsed = secondsSince(started_);
        const double step = elapsed - previous_elapsed_;
        previous_elapsed_ = elapsed;
        if (elapsed + step > *options_.time_limit_s) {
          timed_out_ = true;
          return false;
        }
      }
      return true;
    });
  }

  void finalize_solution(Ipopt::SolverReturn, Ipopt::Index n, const Ipopt::Number* x,
                         const Ipopt::Number*, const Ipopt::Number*, Ipopt::Index m,
                         const Ipopt::Number*, const Ipopt::Number* lambda, Ipopt::Number,
                         const Ipopt::IpoptData*, Ipopt::IpoptCalculatedQuantities*) override {
    if (x == nullptr || lambda == nullptr) return;
    finalized_ = detail::guardedCallback([&] {
      final_x_ = Eigen::Map<const Eigen::VectorXd>(x, n);
      final_lambda_ = Eigen::Map<const Eigen::VectorXd>(lambda, m);
      return true;
    });
  }

  bool finalized() const { return finalized_; }
  bool timedOut() const { return timed_out_; }
  bool stalled() const { return stalled_; }
  bool diverged() const { return diverged_; }
  double lastConstraintViolation() const { return last_inf_pr_; }
  int iterations() const { return last_iteration_; }
  const Eigen::VectorXd& finalX() const { return final_x_; }
  const Eigen::VectorXd& finalLambda() const { return final_lambda_; }

 private:
  TranscriptionNlp& nlp_;
  const BoundaryValueProblem& problem_;
  const Eigen::VectorXd& x0_;
  const DirectTranscriptionOptions& options_;
  Clock::time_point started_;
  std::vector<IterationRecord>& history_;
  IterationStall stall_;
  IterationDivergence divergence_;
  double last_inf_pr_ = 0.0;
  Eigen::VectorXd final_x_, final_lambda_;
  bool finalized_ = false, timed_out_ = false, stalled_ = false, diverged_ = false;
  int last_iteration_ = 0;
  double previous_elapsed_ = 0.0;  // [s] at the previous iteration
};

// Ipopt's barrier strategy (TranscriptionBarrier).
bool setBarrier(Ipopt::OptionsList& ipopt, const DirectTranscriptionOptions& options) {
  if (options.barrier == TranscriptionBarrier::kAdaptive) {
    return ipopt.SetStringValue("mu_strategy", "adaptive");
  }
  return ipopt.SetStringValue("mu_strategy", "monotone") &&
         ipopt.SetNumericValue("mu_init", options.warm_mu_init);
}

// Exact for collocation (the Segway's look-ups included: the model takes their C1 versions,
// SegwayPitchResponse::smoothPitch and SegwaySlopeBounds::optimiserSpeedLimit), limited-memory
// for shooting.
TranscriptionHessian defaultHessian(const TranscriptionNlp& nlp) {
  return nlp.hasExactHessian() ? TranscriptionHessian::kExact
                               : TranscriptionHessian::kLimitedMemory;
}

struct SingleSolve {
  SolveStatus status = SolveStatus::kError;
  std::string reason;
  std::string ipopt_status;
  Eigen::VectorXd x, lambda;
  int iterations = 0;
  bool time_limit_reached = false;
};

SingleSolve solveOnce(TranscriptionNlp& nlp, const BoundaryValueProblem& problem,
                      const Eigen::VectorXd& x0, const DirectTranscriptionOptions& options,
                      Clock::time_point started, std::vector<IterationRecord>& history) {
  SingleSolve out;
  out.x = x0;
  if (!nlp.evaluate(x0.data())) {
    out.status = SolveStatus::kDiverged;
    out.reason = "initial guess: " + nlp.message();
    return out;
  }
  Ipopt::SmartPtr<IpoptTranscription> adapter =
      new IpoptTranscription(nlp, problem, x0, options, started, history);
  Ipopt::SmartPtr<Ipopt::IpoptApplication> app = IpoptApplicationFactory();
  Ipopt::OptionsList& ipopt = *app->Options();
  const TranscriptionHessian hessian = options.hessian.value_or(defaultHessian(nlp));
  const char* scaling = options.scaling == TranscriptionScaling::kUser            ? "user-scaling"
                        : options.scaling == TranscriptionScaling::kGradientBased ? "gradient-based"
                                                                                  : "none";
  detail::IpoptBaseSettings base;
  base.print_level = options.print_level;
  base.max_iterations = options.max_iterations;
  if (options.time_limit_s) base.max_cpu_time_s = *options.time_limit_s - secondsSince(started);
  const bool ok =
      detail::setBaseOptions(ipopt, base) &&
      ipopt.SetStringValue("hessian_approximation",
                           hessian == TranscriptionHessian::kExact ? "exact" : "limited-memory") &&
      ipopt.SetStringValue("nlp_scaling_method", scaling) && setBarrier(ipopt, options) &&
      ipopt.SetStringValue("print_timing_statistics", options.print_level > 0 ? "yes" : "no") &&
      ipopt.SetNumericValue("tol", options.tolerance) &&
      // Near a kink of the terrain (bicubic is C1) the dual infeasibility can stall just
      // above tol: accept 100 x tol held for 10 iterations, with the constraints within
      // 100 x constraint_tolerance (Solved_To_Acceptable_Level, reported as such).
      ipopt.SetNumericValue("acceptable_tol", 100.0 * options.tolerance) &&
      ipopt.SetIntegerValue("acceptable_iter", 10) &&
      ipopt.SetNumericValue("constr_viol_tol", options.constraint_tolerance) &&
      ipopt.SetNumericValue("acceptable_constr_viol_tol", 100.0 * options.constraint_tolerance) &&
      ipopt.SetNumericValue("bound_relax_factor", 0.0);
  if (!ok || !detail::initializeIpopt(*app)) {
    out.reason = "Ipopt could not be set up";
    return out;
  }
  const Ipopt::ApplicationReturnStatus status = app->OptimizeTNLP(Ipopt::GetRawPtr(adapter));
  out.ipopt_status = detail::ipoptStatusName(status);
  out.iterations = adapter->iterations();
  if (adapter->finalized() && adapter->finalX().allFinite()) {
    out.x = adapter->finalX();
    out.lambda = adapter->finalLambda();
  } else {
    out.lambda = Eigen::VectorXd::Zero(nlp.constraintCount());
  }
  detail::IpoptOutcome outcome =
      detail::ipoptOutcome(status, adapter->timedOut(), options.max_iterations,
                           options.time_limit_s, options.stop != nullptr && options.stop->load());
  if (status == Ipopt::User_Requested_Stop && adapter->stalled()) {
    outcome = {SolveStatus::kConverged, ""};
    out.ipopt_status += " (stalled at a feasible, nearly stationary point: accepted)";
  }
  if (status == Ipopt::User_Requested_Stop && adapter->diverged()) {
    // Multipliers diverging while the constraint violation stays: Ipopt heading for a point
    // of local infeasibility, which its restoration phase would take long to prove.
    std::ostringstream why;
    why << "locally infeasible: Ipopt's dual infeasibility stayed above "
        << options.divergence.dual_infeasibility << " for " << options.divergence.window
        << " iterations or rose above " << options.divergence.blow_up
        << " (diverging multipliers) with the constraint violation at "
        << adapter->lastConstraintViolation();
    outcome = {SolveStatus::kInfeasible, why.str()};
  }
  out.status = outcome.status;
  out.reason = std::move(outcome.reason);
  out.time_limit_reached = out.status != SolveStatus::kConverged &&
                           (adapter->timedOut() || status == Ipopt::Maximum_CpuTime_Exceeded);
  if (out.status != SolveStatus::kConverged && !nlp.message().empty()) {
    out.reason += " (last evaluation: " + nlp.message() + ")";
  }
  return out;
}

// Whether a solve with the default exact Hessian on the Segway ended locally infeasible (blown
// up by options.divergence included) or at its iteration limit with half its time limit left
// (`elapsed_s` spent): then L-BFGS is tried once. Later, a retry would take the time of the
// caller's other seeds (docs/benchmarks.md).
bool retriesWithLimitedMemory(const TranscriptionNlp& nlp,
                              const DirectTranscriptionOptions& options, const SingleSolve& solve,
                              double elapsed_s) {
  return !options.hessian && nlp.model().options().segway &&
         defaultHessian(nlp) == TranscriptionHessian::kExact && !solve.time_limit_reached &&
         (!options.time_limit_s || elapsed_s < 0.5 * *options.time_limit_s) &&
         (solve.status == SolveStatus::kInfeasible || solve.status == SolveStatus::kMaxIterations);
}

void fillSolution(TranscriptionNlp& nlp, const SingleSolve& solve, TranscriptionSolution& out) {
  out.scheme = nlp.layout().scheme;
  out.shooting_controls = nlp.layout().shooting_controls;
  out.mesh = nlp.layout().mesh;
  out.final_time = solve.x(nlp.finalTimeIndex());
  out.times.resize(static_cast<std::size_t>(nlp.points()));
  out.points.resize(static_cast<std::size_t>(nlp.points()));
  for (int p = 0; p < nlp.points(); ++p) {
    out.times[static_cast<std::size_t>(p)] =
        out.final_time * nlp.pointTimes()[static_cast<std::size_t>(p)];
    out.points[static_cast<std::size_t>(p)] = solve.x.segment<kPointSize>(kPointSize * p);
  }
  out.multipliers = solve.lambda;
  out.active.clear();
  out.max_defect = 0.0;
  if (!nlp.evaluate(solve.x.data())) return;
  out.result.cost = nlp.objective();
  out.max_defect = nlp.constraints().head(nlp.defectRowCount()).cwiseAbs().maxCoeff();
  for (int r = nlp.defectRowCount(); r < nlp.constraintCount(); ++r) {
    const double value = nlp.constraints()(r);
    const double multiplier = r < solve.lambda.size() ? solve.lambda(r) : 0.0;
    if (value > -kActiveTolerance && multiplier > 0.0) {
      const ConstraintRow row = nlp.row(r);
      out.active.push_back(
          {row.point, out.times[static_cast<std::size_t>(row.point)], row.name, value, multiplier});
    }
  }
}

// Quadratic Lagrange interpolation through s = 0, 1/2, 1.
Eigen::Vector2d quadratic(const Eigen::Vector2d& a, const Eigen::Vector2d& m,
                          const Eigen::Vector2d& b, double s) {
  return 2.0 * (s - 0.5) * (s - 1.0) * a - 4.0 * s * (s - 1.0) * m + 2.0 * s * (s - 0.5) * b;
}

}  // namespace

Eigen::Vector2d TranscriptionSolution::controlsAt(double t) const {
  if (points.empty()) return Eigen::Vector2d::Zero();
  const int intervals = static_cast<int>(mesh.size()) - 1;
  const double tau = final_time > 0.0 ? std::clamp(t / final_time, 0.0, 1.0) : 0.0;
  const int k = std::clamp(
      static_cast<int>(std::upper_bound(mesh.begin(), mesh.end(), tau) - mesh.begin()) - 1, 0,
      intervals - 1);
  const double s = (tau - mesh[static_cast<std::size_t>(k)]) /
                   (mesh[static_cast<std::size_t>(k) + 1] - mesh[static_cast<std::size_t>(k)]);
  if (scheme == TranscriptionScheme::kHermiteSimpson) {
    const std::size_t a = 2 * static_cast<std::size_t>(k);
    return quadratic(points[a].tail<2>(), points[a + 1].tail<2>(), points[a + 2].tail<2>(), s);
  }
  const std::size_t a = static_cast<std::size_t>(k);
  if (scheme == TranscriptionScheme::kMultipleShooting &&
      shooting_controls == ShootingControls::kPiecewiseConstant) {
    return points[a].tail<2>();
  }
  return (1.0 - s) * points[a].tail<2>() + s * points[a + 1].tail<2>();
}

TranscriptionGuess TranscriptionSolution::asGuess() const {
  TranscriptionGuess guess;
  guess.t = times;
  guess.points = points;
  return guess;
}

std::optional<std::string> validateTranscriptionOptions(const DirectTranscriptionOptions& o) {
  if (o.intervals < 1) return "intervals must be >= 1";
  if (o.intervals > 100000) return "intervals must be <= 100000";
  if (!o.mesh.empty()) {
    if (static_cast<int>(o.mesh.size()) != o.intervals + 1) {
      return "mesh must have intervals + 1 (" + std::to_string(o.intervals + 1) + ") node times";
    }
    if (o.mesh.front() != 0.0 || o.mesh.back() != 1.0) return "mesh must run from 0 to 1";
    for (std::size_t k = 0; k + 1 < o.mesh.size(); ++k) {
      if (!(o.mesh[k + 1] > o.mesh[k])) return "mesh node times must increase strictly";
    }
  }
  if (!(o.min_final_time > 0.0) || !(o.max_final_time > o.min_final_time)) {
    return "final-time bounds must satisfy 0 < min_final_time < max_final_time";
  }
  if (o.max_iterations < 1) return "max_iterations must be >= 1";
  if (!(o.map_margin >= 0.0)) return "map_margin must be >= 0";
  if (o.time_limit_s && !(*o.time_limit_s >= 0.0)) return "time_limit_s must be >= 0";
  if (!(o.tolerance > 0.0) || !(o.constraint_tolerance > 0.0)) return "tolerances must be > 0";
  if (!(o.warm_mu_init > 0.0) || !std::isfinite(o.warm_mu_init)) {
    return "warm_mu_init must be > 0";
  }
  if (o.scheme == TranscriptionScheme::kMultipleShooting &&
      o.hessian == TranscriptionHessian::kExact) {
    return "the exact Hessian is available for collocation only; multiple shooting uses "
           "limited_memory";
  }
  if (o.refinement.max_rounds < 0 || !(o.refinement.tolerance > 0.0)) {
    return "mesh refinement needs max_rounds >= 0 and tolerance > 0";
  }
  if (!(o.model.control_effort_weight >= 0.0)) return "control_effort_weight must be >= 0";
  if (o.model.clearance.map != nullptr && !std::isfinite(o.model.clearance.min_clearance)) {
    return "min_clearance must be finite";
  }
  if (o.divergence.window < 0 || !(o.divergence.dual_infeasibility > 0.0) ||
      !(o.divergence.blow_up >= o.divergence.dual_infeasibility)) {
    return "divergence needs window >= 0, dual_infeasibility > 0 and blow_up >= "
           "dual_infeasibility";
  }
  return std::nullopt;
}

std::optional<std::vector<double>> intervalErrors(const TranscriptionModel& model,
                                                  const TranscriptionSolution& solution) {
  const int intervals = static_cast<int>(solution.mesh.size()) - 1;
  std::vector<double> errors(static_cast<std::size_t>(std::max(intervals, 0)), 0.0);
  const bool hs = solution.scheme == TranscriptionScheme::kHermiteSimpson;
  models::AttitudeWorkspace workspace;
  models::RoverStateSpaceRates rates;
  const auto f = [&](const StateVector& z, double t, StateVector& out) {
    if (model.kinematics().stateSpaceRates(z, solution.controlsAt(t), workspace, rates) !=
        models::AttitudeStatus::kOk) {
      return false;
    }
    out = rates.rate;
    return true;
  };
  for (int k = 0; k < intervals; ++k) {
    const std::size_t a = hs ? 2 * static_cast<std::size_t>(k) : static_cast<std::size_t>(k);
    const std::size_t b = hs ? a + 2 : a + 1;
    const double t0 = solution.times[a], t1 = solution.times[b];
    const double h = (t1 - t0) / kErrorSubsteps;
    StateVector z = solution.points[a].head<kStateSize>();
    for (int i = 0; i < kErrorSubsteps; ++i) {
      const double t = t0 + i * h;
      StateVector k1, k2, k3, k4;
      if (!f(z, t, k1) || !f(z + 0.5 * h * k1, t + 0.5 * h, k2) ||
          !f(z + 0.5 * h * k2, t + 0.5 * h, k3) || !f(z + h * k3, t + h, k4)) {
        return std::nullopt;
      }
      z += h / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4);
    }
    const StateVector error = z - solution.points[b].head<kStateSize>();
    errors[static_cast<std::size_t>(k)] = error.head<3>().cwiseAbs().maxCoeff();
  }
  return errors;
}

TranscriptionSolution solveDirectTranscription(const models::TerrainFollowingModel& vehicle,
                                               const BoundaryValueProblem& problem,
                                               const TranscriptionGuess& guess,
                                               const DirectTranscriptionOptions& options) {
  const Clock::time_point started = Clock::now();
  TranscriptionSolution out;
  out.result.method =
      options.scheme == TranscriptionScheme::kMultipleShooting ? "shooting" : "collocation";
  out.scheme = options.scheme;
  const auto finish = [&](SolveStatus status, std::string reason) {
    out.result.status = status;
    out.result.reason = std::move(reason);
    out.result.solve_time_ms = 1e3 * secondsSince(started);
    return out;
  };
  if (std::optional<std::string> why = validateTranscriptionOptions(options)) {
    return finish(SolveStatus::kError, *why);
  }
  if (std::optional<std::string> why = validateBoundaryStates(problem)) {
    return finish(SolveStatus::kError, *why);
  }
  if (guess.t.size() < 2 || guess.t.size() != guess.points.size() || !(guess.finalTime() > 0.0)) {
    return finish(SolveStatus::kError, "the initial guess needs >= 2 points and a final time > 0");
  }
  for (const PointVector& w : guess.points) {
    if (!w.allFinite())
      return finish(SolveStatus::kError, "the initial guess has non-finite values");
  }
  try {
    const TranscriptionModel model(vehicle, problem, options.model);
    TranscriptionLayout layout;
    layout.scheme = options.scheme;
    layout.shooting_controls = options.shooting_controls;
    layout.linear_controls = options.linear_controls;
    layout.rest_curvature = options.rest_curvature;
    layout.mesh = options.mesh.empty() ? uniformMesh(options.intervals) : options.mesh;
    // A twentieth of a cell: see TranscriptionLayout::hessian_position_step.
    layout.hessian_position_step = 0.05 * vehicle.surface().map().geometry().cell;
    // The iteration records are appended inside Ipopt's callback: no allocation there.
    // (A round may take two solves: retriesWithLimitedMemory.)
    out.result.history.reserve(static_cast<std::size_t>(options.max_iterations + 1) *
                               static_cast<std::size_t>(options.refinement.max_rounds + 2));
    TranscriptionGuess current = guess;
    int total_iterations = 0;
    for (int round = 0;; ++round) {
      layout.interval_bounds_final_time =
          options.interval_bounds ? intervalBoundsFinalTime(problem, current.finalTime()) : 0.0;
      TranscriptionNlp nlp(model, layout);
      const Eigen::VectorXd x0 = initialVariables(nlp, problem, current);
      SingleSolve solve = solveOnce(nlp, problem, x0, options, started, out.result.history);
      if (retriesWithLimitedMemory(nlp, options, solve, secondsSince(started))) {
        // The Segway's look-ups are only C1: where the exact Hessian's steps end locally
        // infeasible or stall, L-BFGS from the same start often gets through.
        total_iterations += solve.iterations;
        DirectTranscriptionOptions limited_memory = options;
        limited_memory.hessian = TranscriptionHessian::kLimitedMemory;
        const std::string first = solve.reason;
        solve = solveOnce(nlp, problem, x0, limited_memory, started, out.result.history);
        if (solve.status != SolveStatus::kConverged) {
          solve.reason += " (L-BFGS, after the exact Hessian's " + first + ")";
        }
      }
      total_iterations += solve.iterations;
      out.ipopt_status = solve.ipopt_status;
      fillSolution(nlp, solve, out);
      out.result.iterations = total_iterations;
      out.result.time_limit_reached = solve.time_limit_reached;
      if (solve.status != SolveStatus::kConverged) return finish(solve.status, solve.reason);
      if (options.refinement.max_rounds == 0) break;
      const std::optional<std::vector<double>> errors = intervalErrors(model, out);
      if (!errors) break;
      const double worst = *std::max_element(errors->begin(), errors->end());
      out.refinement.push_back({nlp.intervals(), worst, solve.iterations});
      if (worst <= options.refinement.tolerance || round >= options.refinement.max_rounds) break;
      // Split every interval whose local error exceeds the tolerance, up to max_intervals.
      std::vector<double> mesh;
      int count = nlp.intervals();
      for (std::size_t k = 0; k + 1 < layout.mesh.size(); ++k) {
        mesh.push_back(layout.mesh[k]);
        if ((*errors)[k] > options.refinement.tolerance &&
            count < options.refinement.max_intervals) {
          mesh.push_back(0.5 * (layout.mesh[k] + layout.mesh[k + 1]));
          ++count;
        }
      }
      mesh.push_back(1.0);
      if (mesh.size() == layout.mesh.size()) break;  // at max_intervals
      layout.mesh = std::move(mesh);
      current = out.asGuess();
    }
    return finish(SolveStatus::kConverged, "");
  } catch (const std::exception& error) {
    return finish(SolveStatus::kError, std::string("direct transcription: ") + error.what());
  } catch (...) {
    return finish(SolveStatus::kError, "direct transcription: unexpected exception");
  }
}

}  // namespace terratraj::ocp
