#pragma once
// A candidate made complete (internal to refine/src): the checks a planner's or a user's
// candidate must pass before it is refined, and its missing columns (timing, omega, curvature,
// attitude) derived from its guess and the vehicle model.

#include <optional>
#include <string>

#include "terratraj/models/terrain_following_model.hpp"
#include "terratraj/models/trajectory.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/terrain/grid_geometry.hpp"

namespace terratraj::refine::detail {

/// "(x, y)" for messages [m].
std::string formatPoint(double x, double y);

/// Why the candidate cannot be refined (no x, y; a single point; NaN; off the map), or
/// std::nullopt.
std::optional<std::string> candidateError(const models::Trajectory& candidate,
                                          const terrain::GridGeometry& geometry);

/// Whether every sample has a finite t, v and heading (the candidate's own timing is usable).
bool hasTiming(const models::Trajectory& t);

/// Fills z, roll, pitch from the vehicle model at every sample; false (and `why`, naming the
/// sample) where the vehicle cannot rest.
bool fillAttitude(const models::TerrainFollowingModel& vehicle, models::Trajectory& trajectory,
                  std::string& why);

/// The candidate with every column: its own samples when it has timing (omega and curvature
/// filled from `guess`, built on the same samples), else the samples of its guess (resampled by
/// arc length with a feasible speed profile).
models::Trajectory completeCandidate(const models::Trajectory& candidate,
                                     const ocp::TranscriptionGuess& guess);

}  // namespace terratraj::refine::detail
