#pragma once
// TranscriptionNlp: a trajectory-optimisation problem transcribed into a sparse nonlinear
// programme (the functions, their sparse derivatives and the bounds; no solver in here; the
// Ipopt adapter in direct_transcription.cpp drives it).
//
// Variables x = (w_0, ..., w_{P-1}, t_f): the variables w_p of P points (TranscriptionModel's
// 7 per point) and the final time. The points sit at normalised times tau_p in [0, 1] of a
// mesh of N intervals (nodes tau_0 = 0 < ... < tau_N = 1; Hermite-Simpson adds the interval
// midpoints, so P = 2N + 1 there and P = N + 1 otherwise).
// Constraints, in this order:
//   defects (5 rows per block): trapezoidal z_{k+1} - z_k - t_f d_k/2 (f_k + f_{k+1});
//     Hermite-Simpson (separated) z_m - (z_k + z_{k+1})/2 - t_f d_k/8 (f_k - f_{k+1}) and
//     z_{k+1} - z_k - t_f d_k/6 (f_k + 4 f_m + f_{k+1}); multiple shooting
//     z_{k+1} - Phi_k(z_k, u_k, [u_{k+1}], t_f) with Phi_k from CVODES and its Jacobian blocks
//     from CVODES forward sensitivities (d_k = tau_{k+1} - tau_k);
//   path constraints g(w_p) <= 0 at every point (TranscriptionModel);
//   the curvature rows at rest (TranscriptionLayout::rest_curvature) and the limits between the
//   points (TranscriptionLayout::interval_bounds_final_time), when asked for.
// Objective J = t_f (1 + sum_p omega_p l(w_p)), omega_p the quadrature weights (trapezoid, or
// Simpson for Hermite-Simpson; trapezoid on the nodes for shooting).
// The exact Hessian of the Lagrangian (collocation only) is block-diagonal per point plus the
// t_f row; each block is the central difference of the analytic point gradients (the models
// give no second derivatives), which the tests compare with differences of the whole gradient.

#include <Eigen/Core>
#include <memory>
#include <string>
#include <vector>

#include "terratraj/ocp/interval_bound_rows.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_model.hpp"

namespace terratraj::ocp {

/// How the dynamics are enforced between nodes.
enum class TranscriptionScheme {
  kTrapezoidal,       ///< collocation, trapezoidal rule
  kHermiteSimpson,    ///< collocation, separated Hermite-Simpson
  kMultipleShooting,  ///< CVODES over each interval
};
/// The scheme's name ("trapezoidal", "hermite_simpson", "multiple_shooting").
const char* transcriptionSchemeName(TranscriptionScheme scheme);

/// Shooting controls within an interval.
enum class ShootingControls { kPiecewiseConstant, kPiecewiseLinear };

/// The structure of one transcription.
struct TranscriptionLayout {
  TranscriptionScheme scheme = TranscriptionScheme::kHermiteSimpson;
  ShootingControls shooting_controls = ShootingControls::kPiecewiseLinear;
  std::vector<double> mesh;                    ///< node times tau_0 = 0 < ... < tau_N = 1
  double shooting_relative_tolerance = 1e-8;   ///< CVODES (shooting only)
  double shooting_absolute_tolerance = 1e-10;  ///< CVODES (shooting only)
  /// Step of the Hessian's differences in x and y [m]; 0: 1e-5 (1 + |x|). A step of a fraction
  /// of the cell averages the jumps of the terrain's second derivatives at cell boundaries
  /// (bicubic interpolation is only C1), which a tiny step turns into spikes.
  double hessian_position_step = 0.0;
  /// Hermite-Simpson only: each midpoint's controls are the mean of its interval's node
  /// controls (2 linear equality rows "control_linearity" per interval, after the defects), so
  /// the controls are piecewise linear and their bounds (|v'| <= a_max) hold between the points
  /// too; free midpoint controls make them quadratic, which overshoots a bang-bang switch by up
  /// to 25 %.
  bool linear_controls = false;
  /// At a start or goal at rest, |omega'| <= kappa_max |v'| (the curvature there is omega' / v';
  /// the path rows' |omega| <= kappa_max v say nothing at v = 0): four linear rows at most,
  /// "kappa_max_at_rest", after the path rows. solveTranscription() adds them in a round when a
  /// re-simulation breaks a curvature rule near rest.
  bool rest_curvature = false;
  /// Collocation only: v_max, v >= 0, omega_max and kappa_max held on the whole of every
  /// interval for final times up to this [s] (IntervalBoundRows: the hull of the Bezier control
  /// points of v(t) and omega(t)), after the rest rows, named "<limit>_between_points"; 0: none.
  double interval_bounds_final_time = 0.0;
};

/// A uniform mesh of `intervals` (>= 1) intervals.
std::vector<double> uniformMesh(int intervals);

/// What a constraint row is.
struct ConstraintRow {
  bool defect = false;    ///< a dynamics defect (else a path constraint)
  int point = 0;          ///< the point (path constraints) or the interval (defects)
  const char* name = "";  ///< "defect" or the limit's name
};

/// The sparse NLP. Not thread-safe (it caches the last evaluation); no allocation after
/// construction except in the shooting integrator's first call.
class TranscriptionNlp {
 public:
  /// `model` must outlive the NLP. Throws std::invalid_argument for a mesh that is not
  /// increasing from 0 to 1 with at least one interval.
  TranscriptionNlp(const TranscriptionModel& model, TranscriptionLayout layout);
  ~TranscriptionNlp();
  TranscriptionNlp(const TranscriptionNlp&) = delete;
  TranscriptionNlp& operator=(const TranscriptionNlp&) = delete;

  const TranscriptionLayout& layout() const { return layout_; }
  const TranscriptionModel& model() const { return *model_; }
  int intervals() const { return static_cast<int>(layout_.mesh.size()) - 1; }
  int points() const { return static_cast<int>(tau_.size()); }
  int variableCount() const { return kPointSize * points() + 1; }
  int constraintCount() const { return defect_rows_ + path_rows_ + rest_rows_ + bounds_.count(); }
  /// Equality rows (dynamics defects, then the control-linearity rows): the first
  /// defectRowCount() rows of g.
  int defectRowCount() const { return defect_rows_; }
  /// First control-linearity row (== defectRowCount() without them); row r >= it holds
  /// v' (r even relative to it) or omega' (odd) of interval (r - controlRowStart()) / 2.
  int controlRowStart() const { return control_row_start_; }
  /// Index of t_f in x.
  int finalTimeIndex() const { return kPointSize * points(); }
  /// Normalised time of each point.
  const std::vector<double>& pointTimes() const { return tau_; }
  /// Whether a point is a mesh node (else a Hermite-Simpson midpoint).
  bool isNode(int point) const;
  /// The point of mesh node k.
  int nodePoint(int node) const;
  /// Quadrature weight of each point (they sum to 1).
  const std::vector<double>& quadratureWeights() const { return weights_; }
  /// What row `row` of g is.
  ConstraintRow row(int row) const;

  /// Sparsity of d g / d x (computed once): entry i is (jacobianRows()[i], jacobianCols()[i]).
  const std::vector<int>& jacobianRows() const { return jac_rows_; }
  const std::vector<int>& jacobianCols() const { return jac_cols_; }
  /// Sparsity of the lower triangle of the Lagrangian Hessian (collocation).
  const std::vector<int>& hessianRows() const { return hess_rows_; }
  const std::vector<int>& hessianCols() const { return hess_cols_; }
  /// Whether hessian() is available (collocation schemes).
  bool hasExactHessian() const { return layout_.scheme != TranscriptionScheme::kMultipleShooting; }

  /// Evaluates objective, gradient, constraints and Jacobian at x (variableCount() values)
  /// unless x is the point last evaluated. Returns false (message() says why) when the rover
  /// cannot be placed at a point, an interval cannot be integrated, or a value is not finite.
  bool evaluate(const double* x);
  double objective() const { return objective_; }
  const Eigen::VectorXd& gradient() const { return gradient_; }
  const Eigen::VectorXd& constraints() const { return constraints_; }
  /// Values in the order of jacobianRows().
  const Eigen::VectorXd& jacobianValues() const { return jac_values_; }
  /// The evaluation of each point at the last x.
  const PointEvaluation& pointEvaluation(int point) const {
    return evals_[static_cast<std::size_t>(point)];
  }

  /// Lower triangle of the Hessian of sigma J + lambda' g at x, in the order of hessianRows().
  /// Collocation only; false when an evaluation fails.
  bool hessian(const double* x, double sigma, const double* lambda, double* values);

  const std::string& message() const { return message_; }

 private:
  // Which entries of a defect term's 5 x 7 block can be non-zero.
  enum class TermPattern {
    kDense,     // shooting: d Phi / d (z, u) is dense
    kDynamics,  // collocation: (x, y, heading)' depend on z only; v' on v and v', omega' likewise
    kIdentity,  // a term with beta = 0: alpha I on z
  };
  struct Term {  // one point's part in a defect block: alpha z_p - t_f beta f_p
    int point;
    double alpha;
    double beta;
    TermPattern pattern = TermPattern::kDense;
  };
  // Calls visit(i, j) for each structural entry of a term's block, in a fixed order.
  template <typename Visit>
  static void forEachEntry(TermPattern pattern, Visit&& visit);
  struct DefectBlock {
    std::vector<Term> terms;
    int row;        // first of 5 rows
    int jac_start;  // first Jacobian entry: terms x 35 entries, then 5 for t_f
  };
  void buildStructure();
  void buildHessianStructure();  // block-diagonal per point, plus the t_f row
  bool evaluateCollocation(const Eigen::Map<const Eigen::VectorXd>& x);
  bool evaluateShooting(const Eigen::Map<const Eigen::VectorXd>& x);
  bool evaluatePoints(const Eigen::Map<const Eigen::VectorXd>& x);
  void evaluatePathAndCost(const Eigen::Map<const Eigen::VectorXd>& x);
  // Gradient of nu' f + mu' g + c l at w into `out` (7); false if the point cannot be placed.
  bool pointLagrangianGradient(const PointVector& w, const StateVector& nu, const double* mu,
                               double c, models::AttitudeWorkspace& workspace, PointVector& out);

  const TranscriptionModel* model_;
  TranscriptionLayout layout_;
  std::vector<double> tau_, weights_;
  std::vector<DefectBlock> blocks_;
  int defect_rows_ = 0, path_rows_ = 0, path_jac_start_ = 0;
  // The curvature at a boundary at rest: where v = 0, omega / v is omega' / v', so
  // |omega'| <= kappa_max |v'| there (two linear rows at a start at rest, two at a goal at
  // rest; the path rows' |omega| <= kappa_max v says nothing at v = 0).
  struct RestRow {
    int point = 0;
    double omega_dot = 0.0;  ///< coefficient of omega' (+-1)
    double v_dot = 0.0;      ///< coefficient of v' (-+kappa_max)
  };
  std::vector<RestRow> rest_;
  int rest_rows_ = 0, rest_jac_start_ = 0;
  IntervalBoundRows bounds_;  // layout_.interval_bounds_final_time (none when 0)
  int bound_jac_start_ = 0;
  int control_row_start_ = 0, control_jac_start_ = 0;
  std::vector<int> jac_rows_, jac_cols_, hess_rows_, hess_cols_;
  std::vector<PointEvaluation> evals_;
  std::vector<models::AttitudeWorkspace> workspaces_;
  PointEvaluation scratch_;
  std::vector<StateVector> nu_;  // Hessian: defect multipliers gathered per point
  Eigen::VectorXd last_x_;
  bool has_last_ = false, last_ok_ = false;
  double objective_ = 0.0;
  Eigen::VectorXd gradient_, constraints_, jac_values_;
  std::string message_;
  struct Shooting;
  std::unique_ptr<Shooting> shooting_;
};

/// The NLP's variables from a guess: the guess interpolated at the point times (scaled to the
/// guess's own final time), the boundary states of `problem` imposed, the goal heading unwrapped
/// next to the guess's. `guess` must hold at least two samples.
Eigen::VectorXd initialVariables(const TranscriptionNlp& nlp, const BoundaryValueProblem& problem,
                                 const TranscriptionGuess& guess);

}  // namespace terratraj::ocp
