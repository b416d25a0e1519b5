#pragma once
// solveTranscription(): the whole direct-transcription solve of `terratraj solve --method
// collocation|shooting` and of refinement, mirroring solveBoundaryValue(): Ipopt on the
// transcription, an independent re-simulation of its controls, and the verdict
// (solution_verdict.hpp) on the re-simulated trajectory as written, which decides the status.
//
// A transcription imposes the limits at its points only, and its re-simulation drifts from the
// points by the discretisation error. So the problem is solved with the limits tightened by
// small margins, and a solution whose re-simulation still breaks a limit between the points,
// misses the goal beyond the tolerance, or clips a lethal cell is solved again from itself:
// with more clearance (a clipped cell), a finer mesh (up to a cap), or wider margins, until the
// verdict passes, the rounds run out or the time limit is reached. A finer mesh halves the
// intervals where the re-simulation breaks a ground limit or drifts (mesh_split.hpp), every
// interval when that is most of them or none is found. Every round is reported.

#include <atomic>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory_verdict.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/ocp/solve_result.hpp"
#include "terratraj/ocp/trajectory_verifier.hpp"
#include "terratraj/terrain/elevation_map.hpp"

namespace terratraj::ocp {

/// How to solve and verify a transcription.
struct TranscriptionSolveOptions {
  /// The first round's transcription (scheme, intervals, clearance, ...). Its time_limit_s is
  /// ignored: `time_limit_s` below covers every round.
  DirectTranscriptionOptions transcription;
  ConvergenceCriteria criteria;  ///< terminal tolerances of the verdict
  /// Lethal, no-data and off-map rules of the verdict; null: none.
  const terrain::ElevationMap* map = nullptr;
  /// v_max, omega_max and a_max are lowered by this fraction in the solve, in [0, 0.5) ...
  double speed_margin = 0.0005;
  /// ... and kappa_max, sigma_max, pitch_max, roll_max by this one, in [0, 0.5).
  double limit_margin = 0.002;
  int max_rounds = 4;  ///< re-solves after the first, >= 0
  /// A round whose re-simulation misses the goal, or breaks a limit between the points by more
  /// than this fraction of it, is solved again on a finer mesh (while max_intervals allows)
  /// rather than with wider margins, in (0, 0.5].
  double mesh_excess = 0.05;
  /// The barrier strategy of the re-solves, which start from the previous round's solution
  /// (the first round uses transcription.barrier). kWarm saves iterations when the rounds only
  /// refine the mesh of a near-optimal solution (refinement of a planner candidate); from Dubins
  /// seeds on the real DEMs it stalled re-solves with widened margins (docs/benchmarks.md).
  TranscriptionBarrier resolve_barrier = TranscriptionBarrier::kAdaptive;
  int max_intervals = 800;  ///< mesh refinement stops here, >= transcription.intervals
  /// A re-simulation over a lethal cell, or one that leaves the terrain between the points,
  /// raises the clearance constraint (when
  /// transcription.model.clearance has a map) to this [m], >= 0.
  double clearance_floor = 0.0;
  std::optional<double> time_limit_s;       ///< wall clock of all rounds [s], >= 0
  const std::atomic<bool>* stop = nullptr;  ///< set from outside (SIGINT): no further round
};

/// One round of solveTranscription().
struct TranscriptionRound {
  int intervals = 0;
  double speed_margin = 0.0, limit_margin = 0.0;  ///< the fractions solved with
  double clearance_m = 0.0;                       ///< the clearance constraint (0: none)
  SolveStatus status = SolveStatus::kError;       ///< after the verdict
  std::string reason;
  int iterations = 0;
};

/// A transcription solve and its verification.
struct VerifiedTranscription {
  SolveStatus status = SolveStatus::kError;  ///< after the verdict
  std::string reason;                        ///< why, for anything but kConverged
  TranscriptionSolution solution;            ///< the last round's (Ipopt's status in .result)
  VerifiedTrajectory verified;               ///< its re-simulation (ok false if impossible)
  models::TrajectoryVerdict verdict;         ///< the independent check of verified.trajectory
  std::vector<TranscriptionRound> rounds;    ///< every round, in order
  std::vector<IterationRecord> history;      ///< every round's iterations, numbered on
  int iterations = 0;                        ///< all rounds
  double solve_time_ms = 0.0;                ///< all rounds, with verification [ms]
  /// The time limit (or a stop) ended the last round's solve or a round the verdict asked for:
  /// with more time the result may differ (else the same options give the same result).
  bool time_limit_reached = false;
};

/// Why the options cannot be used, or std::nullopt.
std::optional<std::string> validateTranscriptionSolveOptions(
    const TranscriptionSolveOptions& options);

/// Solves `problem` on `vehicle` from `guess` and verifies it, in rounds (see above). Never
/// throws (except std::bad_alloc).
VerifiedTranscription solveTranscription(const models::TerrainFollowingModel& vehicle,
                                         const BoundaryValueProblem& problem,
                                         const TranscriptionGuess& guess,
                                         const TranscriptionSolveOptions& options);

/// The verification and verdict of one transcription solution of `problem` (what a round does
/// after Ipopt): fills `out.verified`, `out.verdict`, `out.status` and `out.reason` from
/// `out.solution`. `model` is the problem's with the true limits.
void verifyTranscription(const TranscriptionModel& model, const ConvergenceCriteria& criteria,
                         const terrain::ElevationMap* map, VerifiedTranscription& out);

}  // namespace terratraj::ocp
