#pragma once
// The initial guess of the terrain-adaptive solve (004_... 3.5): a heuristic in the manner of
// Nagy & Kelly, the fully constrained flat-ground solution (Gauss-Newton, minimum-norm steps),
// then the flat-ground optimum; the multipliers from the right pseudo-inverse (eq. 15) and the
// flat optimum's Hessian of the Lagrangian (for BFGS's first W).

#include <Eigen/Core>
#include <chrono>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/terrain/terrain_surface.hpp"

namespace terratraj::ocp {

/// Where a solve starts.
struct InitialGuess {
  bool ok = false;  ///< false: the flat problem has no solution of this form (reason)
  std::string reason;
  Eigen::VectorXd q;
  Eigen::Vector3d lambda = Eigen::Vector3d::Zero();
  Eigen::MatrixXd hessian;    ///< empty when the flat optimisation did not converge
  bool flat_optimum = false;  ///< q is the flat-ground optimum (else the constrained solution)
  long integrations = 0;
};

/// Heuristic unknowns: t_f from the Nagy-Kelly arc-length estimate and a mean speed, yaw-rate
/// coefficients fitted to a turn-toward-then-align profile, speed coefficients fitted to a
/// cruise at 0.7 v_max.
Eigen::VectorXd heuristicGuess(const BoundaryValueProblem& problem);

/// The wall clock by which an initial guess must end (none: no limit).
using GuessDeadline = std::optional<std::chrono::steady_clock::time_point>;

/// The flat-ground initial guess. `surface` only stands behind the flat model (never sampled).
/// Past `deadline` no further integration is made and the guess fails (ok false, the reason
/// says the time limit ended it): an iterate with a huge final time costs seconds an
/// integration (a 13 m turn's word took 43 s before this limit). Never throws.
InitialGuess flatInitialGuess(const BoundaryValueProblem& problem,
                              const terrain::TerrainSurface& surface,
                              const GuessDeadline& deadline = std::nullopt);

/// The same from `start_q` (unknowns of problem's ParametricControls layout, e.g. fitted to a
/// global seed by fitParametricControls) instead of the heuristic.
InitialGuess flatInitialGuess(const BoundaryValueProblem& problem,
                              const terrain::TerrainSurface& surface,
                              const Eigen::VectorXd& start_q,
                              const GuessDeadline& deadline = std::nullopt);

/// The unknowns q whose polynomial controls best follow `t`, `v`, `omega` (least squares over
/// the samples, t from 0 to the final time), with t_f such that the path length is
/// `path_length` [m] when the fitted speed allows (else the samples' duration). Sizes must
/// agree and hold at least two samples.
Eigen::VectorXd fitParametricControls(const BoundaryValueProblem& problem,
                                      const std::vector<double>& t, const std::vector<double>& v,
                                      const std::vector<double>& omega, double path_length);

}  // namespace terratraj::ocp
