#pragma once
// IntervalBoundRows: the limits linear in (v, omega) held on the whole of every collocation
// interval, not only at its points.
//
// Between two nodes a collocation solution's speed v(t) and yaw rate omega(t) are polynomials
// of the interval's controls (v', omega'): cubic on Hermite-Simpson (quadratic controls),
// quadratic on the trapezoidal rule (linear controls). The re-simulation that verifies a
// solution integrates the same interpolated controls, so it sees the same polynomials. A
// polynomial stays in the convex hull of its Bezier control points, so a linear limit
// c_v v + c_omega omega <= b that holds at the control points holds on the whole interval.
// With z = (v, omega), u = (v', omega') and h = t_f d_k the interval's duration [s]:
//   Hermite-Simpson: P1 = z_k + h u_k / 3,  P2 = z_{k+1} - h u_{k+1} / 3;
//   trapezoidal:     P1 = z_k + h u_k / 2.
// (P0 = z_k and the last control point z_{k+1} are the nodes, where the path rows hold.)
// Rows, each <= 0 at each interior control point: v - v_max, -v, +-omega - omega_max,
// +-omega - kappa_max v (|kappa| <= kappa_max as |omega| <= kappa_max v).
// The rows take h from a final time T fixed when the transcription is built (h = T d_k), which
// makes them linear: a row's value at P1 is linear in h and holds at the node (h = 0), so if
// it holds with T it holds for every t_f <= T. A solution whose t_f ends above T loses the
// guarantee (the verifying re-simulation then decides; a re-solve takes the new t_f). The
// exact rows, bilinear in t_f and the controls, put a t_f entry in every row: that dense
// column of the KKT matrix made MUMPS 5 times slower an iteration on a Segway problem.
// A sufficient condition: it costs a little time where a limit is reached with a steep slope
// (the polynomial must approach the bound flat), in exchange for no overshoot between the
// points, which the re-simulation would find (a bang-bang switch of the curvature overshoots
// kappa_max by 4 to 9 % at 55 to 220 intervals without them).
// Not for multiple shooting (its states between nodes come from CVODES).

#include <Eigen/Core>
#include <vector>

#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"

namespace terratraj::ocp {

enum class TranscriptionScheme;

/// The rows of one transcription. Immutable after construction; no allocation in evaluate().
class IntervalBoundRows {
 public:
  /// Entries of d g / d x per row: v, omega, v', omega' of its node (constant).
  static constexpr int kEntriesPerRow = 4;

  IntervalBoundRows() = default;
  /// The rows for `scheme` (none for multiple shooting) on the normalised `mesh` (node times
  /// from 0 to 1) with `limits` (the tightened limits the path rows hold; a limit that is not
  /// finite and > 0 gives no rows), for final times up to `final_time` [s] (> 0; else no rows).
  IntervalBoundRows(TranscriptionScheme scheme, const std::vector<double>& mesh,
                    const models::VehicleLimits& limits, double final_time);

  int count() const { return static_cast<int>(rows_.size()); }
  /// The point (index into the transcription's points) whose node a row starts from.
  int point(int row) const { return rows_[static_cast<std::size_t>(row)].point; }
  /// The limit a row holds, "<limit>_between_points" (v_max, v_min, omega_max, kappa_max).
  const char* name(int row) const { return rows_[static_cast<std::size_t>(row)].name; }

  /// Appends the sparsity of the rows, numbered from `first_row`: kEntriesPerRow entries each,
  /// in the order jacobian() gives them.
  void appendStructure(int first_row, std::vector<int>& rows, std::vector<int>& cols) const;
  /// The row values (count()) into `g` at the variables `x` (the transcription's: 7 per
  /// point, then t_f).
  void evaluate(const Eigen::Ref<const Eigen::VectorXd>& x, double* g) const;
  /// The Jacobian values (kEntriesPerRow per row; constant) into `jacobian`.
  void jacobian(double* jacobian) const;

 private:
  struct Row {
    int point = 0;         // the node the control point is taken from
    double step = 0.0;     // s d_k T [s]: the control point is z_p + step u_p
    double c_v = 0.0;      // coefficient of v [1]
    double c_omega = 0.0;  // coefficient of omega [s / rad: per the limit's units]
    double bound = 0.0;    // b in c_v v + c_omega omega <= b
    const char* name = "";
  };
  std::vector<Row> rows_;
};

/// The final time T [s] to build the rows for from a guess taking `guess_final_time` [s]: the
/// guess's, at most twice the time to drive straight from the start to the goal at v_max after
/// accelerating to it. The rows hold for t_f <= T and are the tighter the larger T / t_f: a
/// planner's detour (an 84 m PRM path for a 10.7 m problem) gives a guess several times slower
/// than the optimum, and rows built for it made a solve locally infeasible. Below the
/// optimum's t_f the rows only lose their guarantee (the re-simulation decides).
double intervalBoundsFinalTime(const BoundaryValueProblem& problem, double guess_final_time);

}  // namespace terratraj::ocp
