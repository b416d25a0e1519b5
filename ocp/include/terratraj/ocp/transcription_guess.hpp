#pragma once
// TranscriptionGuess: the initial trajectory direct transcription starts from, and how to make
// one from any trajectory (the parametric solution, a planner's candidate) or from a geometric
// path with only x, y (resampled by arc length, heading from the tangent, and a speed profile
// within the vehicle's speed, acceleration and yaw-rate limits).

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/transcription_model.hpp"
#include "terratraj/terrain/expected.hpp"

namespace terratraj::ocp {

/// A trajectory of transcription points w = (x, y, heading, v, omega, v', omega') at times t
/// (increasing from 0 [s]); the guess at any time is the linear interpolation.
struct TranscriptionGuess {
  std::vector<double> t;
  std::vector<PointVector> points;
  /// Final time [s] (t.back()).
  double finalTime() const { return t.empty() ? 0.0 : t.back(); }
  /// The interpolated point at time `time` [s] (clamped to [0, t_f]). Requires a non-empty guess.
  PointVector at(double time) const;
};

/// A guess from a time-sampled trajectory with t, x, y, heading and v (omega from the
/// curvature or the heading's rate when absent; v' and omega' from differences). Samples must
/// have increasing t; a failure with the reason otherwise.
Expected<TranscriptionGuess> guessFromTrajectory(const models::Trajectory& trajectory);

/// A guess from a geometric path (x, y points, at least 2 distinct): resampled every `spacing`
/// m of arc length, heading from the tangent (start and goal headings at the ends), speeds
/// from a forward-backward pass under v_max, a_max and omega_max / |curvature|, starting and
/// ending at the problem's speeds; times from the speeds. With `vehicle` (the terrain-following
/// model the problem is solved with), also under the problem's speed tables at the vehicle's
/// attitude on each sample (SpeedTables::speedCap, the Segway's acceleration bound by slope);
/// where a table forbids driving, a tenth of v_max and a_max. A failure with the reason for a
/// path with fewer than two distinct points or non-finite values.
Expected<TranscriptionGuess> guessFromPath(const std::vector<Eigen::Vector2d>& path,
                                           const BoundaryValueProblem& problem,
                                           double spacing = 0.25,
                                           const models::TerrainFollowingModel* vehicle = nullptr);

/// How far `guess` breaks the limits that depend on the ground, at `samples` (>= 2) instants
/// evenly spaced in time (linear interpolation, as a transcription mesh of that many points
/// reads it): the largest of |pitch| / pitch_max - 1, |roll| / roll_max - 1 and the speed over
/// the problem's speed tables at the vehicle's attitude (SpeedTables::speedCap), relative to
/// v_max; 0 when every sample holds them. A sample where the vehicle cannot be placed counts 1.
/// Tells whether a coarse mesh's solution skipped ground its points never touched.
double guessLimitExcess(const TranscriptionGuess& guess, const BoundaryValueProblem& problem,
                        const models::TerrainFollowingModel& vehicle, int samples);

/// The guess for a user's or a planner's trajectory: from its timing when it has t and v,
/// else from its x, y alone (guessFromPath).
Expected<TranscriptionGuess> guessFromCandidate(const models::Trajectory& candidate,
                                                const BoundaryValueProblem& problem);

}  // namespace terratraj::ocp
