#include "terratraj/ocp/transcription_solver.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "terratraj/ocp/deadline.hpp"
#include "terratraj/ocp/mesh_split.hpp"
#include "terratraj/ocp/solution_verdict.hpp"
#include "terratraj/ocp/start_at_goal.hpp"
#include "terratraj/ocp/transcription_model.hpp"

namespace terratraj::ocp {
namespace {

using Clock = std::chrono::steady_clock;

double secondsSince(Clock::time_point start) {
  return std::chrono::duration<double>(Clock::now() - start).count();
}

// `problem` with its limits lowered by the margins.
BoundaryValueProblem tightened(const BoundaryValueProblem& problem, double speed_margin,
                               double limit_margin) {
  BoundaryValueProblem out = problem;
  // Never below the boundary values themselves: the first and last points must stay feasible.
  out.limits.v_max =
      std::max(out.limits.v_max * (1.0 - speed_margin), std::max(problem.start.v, problem.goal.v));
  out.limits.omega_max =
      std::max(out.limits.omega_max * (1.0 - speed_margin),
               std::max(std::abs(problem.start.omega), std::abs(problem.goal.omega)));
  out.limits.a_max *= 1.0 - speed_margin;
  for (double* limit : {&out.limits.kappa_max, &out.limits.sigma_max, &out.limits.pitch_max,
                        &out.limits.roll_max}) {
    *limit *= 1.0 - limit_margin;
  }
  return out;
}

// The largest relative excess of the broken limits of each margin group: (v_max, a_max,
// omega_max, the Segway's look-ups) and (kappa_max, sigma_max, pitch_max, roll_max, the
// tables).
std::pair<double, double> relativeExcess(const models::CheckReport& check) {
  double speed = 0.0, other = 0.0;
  for (const models::CheckViolation& v : check.violations) {
    if (!(v.bound > 0.0) || !std::isfinite(v.amount)) continue;
    const double excess = v.amount / v.bound;
    if (v.limit == "v_max" || v.limit == "a_max" || v.limit == "omega_max" ||
        v.limit.rfind("segway_", 0) == 0) {
      speed = std::max(speed, excess);
    } else if (v.limit == "kappa_max" || v.limit == "sigma_max" || v.limit == "pitch_max" ||
               v.limit == "roll_max" || v.limit.rfind("table_", 0) == 0) {
      other = std::max(other, excess);
    }
  }
  return {speed, other};
}

bool clipsMap(const models::CheckReport& check) {
  return check.find("lethal") != nullptr || check.find("no_data") != nullptr;
}

// The next round's mesh, from this round's verification (mesh_split.hpp): the intervals where
// the re-simulation breaks a ground limit by more than a quarter of the worst interval's excess
// (and the check's 1e-3), with their two neighbours (the re-solve shifts the trajectory along
// the mesh), and, when it misses the goal, those whose local integration error is above the
// terminal tolerance over the number of intervals (so that the others add up to less than it)
// are halved; every interval when neither finds one (a limit the ground does not set: the
// overshoot shrinks with every interval) or where more than half would be.
void refineMesh(const TranscriptionModel& model, const BoundaryValueProblem& problem,
                const TranscriptionSolveOptions& options, const VerifiedTranscription& out,
                DirectTranscriptionOptions& transcription) {
  const std::vector<double>& mesh = out.solution.mesh;
  const int intervals = static_cast<int>(mesh.size()) - 1;
  std::vector<bool> split(static_cast<std::size_t>(std::max(intervals, 0)), false);
  int chosen = 0;
  if (out.verified.ok && intervals > 0) {
    std::vector<double> node_times(mesh.size());
    for (std::size_t k = 0; k < mesh.size(); ++k) {
      node_times[k] = mesh[k] * out.solution.final_time;
    }
    const std::vector<double> excess =
        intervalLimitExcess(out.verified.trajectory, node_times, problem);
    const double worst = *std::max_element(excess.begin(), excess.end());
    constexpr double kCheckRelative = 1e-3;  // the verdict's relative slack
    for (int k = 0; k < intervals; ++k) {
      const double e = excess[static_cast<std::size_t>(k)];
      if (!(e > kCheckRelative && e >= 0.25 * worst)) continue;
      // With its neighbours: the re-solve shifts the trajectory along the mesh.
      for (int j = std::max(k - 1, 0); j <= std::min(k + 1, intervals - 1); ++j) {
        split[static_cast<std::size_t>(j)] = true;
      }
    }
    if (out.verdict.misses_goal) {
      if (const std::optional<std::vector<double>> errors = intervalErrors(model, out.solution)) {
        const double tolerance =
            std::min(options.criteria.position_m, options.criteria.heading_rad) / intervals;
        for (int k = 0; k < intervals; ++k) {
          if ((*errors)[static_cast<std::size_t>(k)] > tolerance) {
            split[static_cast<std::size_t>(k)] = true;
          }
        }
      }
    }
    chosen = static_cast<int>(std::count(split.begin(), split.end(), true));
  }
  if (chosen == 0 || 2 * chosen > intervals) {
    std::fill(split.begin(), split.end(), true);  // every interval: a finer spot stays finer
  }
  transcription.mesh = splitIntervals(mesh, split, options.max_intervals);
  transcription.intervals = static_cast<int>(transcription.mesh.size()) - 1;
}

}  // namespace

std::optional<std::string> validateTranscriptionSolveOptions(const TranscriptionSolveOptions& o) {
  if (!(o.speed_margin >= 0.0 && o.speed_margin < 0.5)) {
    return "speed_margin must be in [0, 0.5)";
  }
  if (!(o.limit_margin >= 0.0 && o.limit_margin < 0.5)) {
    return "limit_margin must be in [0, 0.5)";
  }
  if (o.max_rounds < 0) return "max_rounds must be >= 0";
  if (!(o.mesh_excess > 0.0 && o.mesh_excess <= 0.5)) return "mesh_excess must be in (0, 0.5]";
  if (o.max_intervals < o.transcription.intervals) {
    return "max_intervals (" + std::to_string(o.max_intervals) + ") must be >= intervals (" +
           std::to_string(o.transcription.intervals) + ")";
  }
  if (!(o.clearance_floor >= 0.0) || !std::isfinite(o.clearance_floor)) {
    return "clearance_floor must be a finite number >= 0";
  }
  if (o.time_limit_s && !(*o.time_limit_s >= 0.0)) return "time_limit_s must be >= 0";
  return validateTranscriptionOptions(o.transcription);
}

void verifyTranscription(const TranscriptionModel& model, const ConvergenceCriteria& criteria,
                         const terrain::ElevationMap* map, VerifiedTranscription& out) {
  const SolveResult& result = out.solution.result;
  // A solve stopped by its time limit is not re-simulated (the re-simulation of a wild iterate
  // can take as long again: a four-wheel attempt given 13.7 s took 31.8 s): its status already
  // says why it ended.
  if (result.time_limit_reached) {
    out.verified = VerifiedTrajectory{};
    out.verified.message = "not re-simulated: the time limit was reached";
    out.status = result.status;
    out.reason = result.reason;
    return;
  }
  out.verified = out.solution.points.empty()
                     ? VerifiedTrajectory{}
                     : verifyTranscriptionSolution(model, out.solution, map);
  if (out.verified.ok) {
    out.verdict = models::judgeTrajectory(
        out.verified.trajectory,
        solveRequirements(model.kinematics().model(), model.problem(), criteria, map));
  } else if (out.verified.message.empty()) {
    out.verified.message = "no solution to re-simulate";
  }
  if (result.status != SolveStatus::kConverged) {
    out.status = result.status;
    out.reason = result.reason;
    return;
  }
  if (!out.verified.ok) {
    out.status = SolveStatus::kDiverged;
    out.reason = "the re-simulation failed: " + out.verified.message;
    return;
  }
  out.status = statusAfterVerdict(SolveStatus::kConverged, out.verdict);
  out.reason = out.verdict.reason;
  // The Segway's own constraints, which the trajectory check cannot see (they need the
  // platform's dynamics), from the re-simulation.
  if (out.status == SolveStatus::kConverged && out.verified.violation.amount > 1e-3 &&
      out.verified.violation.limit.rfind("segway", 0) == 0) {
    out.status = SolveStatus::kInfeasible;
    out.reason = "the re-simulation breaks " + out.verified.violation.limit + " by " +
                 std::to_string(out.verified.violation.amount);
  }
}

namespace {

// A start that already meets the goal: nothing to drive; the one-row trajectory at the start,
// judged like any other.
void stayAtTheStart(const models::TerrainFollowingModel& vehicle,
                    const BoundaryValueProblem& problem, const TranscriptionSolveOptions& options,
                    VerifiedTranscription& out) {
  if (std::optional<models::Trajectory> here = startOnlyTrajectory(vehicle, problem)) {
    out.verified.ok = true;
    out.verified.trajectory = std::move(*here);
    out.verdict =
        models::judgeTrajectory(out.verified.trajectory,
                                solveRequirements(vehicle, problem, options.criteria, options.map));
  }
  out.status = out.verified.ok ? statusAfterVerdict(SolveStatus::kConverged, out.verdict)
                               : SolveStatus::kInfeasible;
  out.solution.result.status = out.status;
  out.reason = out.status == SolveStatus::kConverged
                   ? "the start already meets the goal: nothing to drive"
                   : "the start meets the goal but fails the check: " + out.verdict.reason;
}

}  // namespace

VerifiedTranscription solveTranscription(const models::TerrainFollowingModel& vehicle,
                                         const BoundaryValueProblem& problem,
                                         const TranscriptionGuess& guess,
                                         const TranscriptionSolveOptions& options) {
  const Clock::time_point started = Clock::now();
  VerifiedTranscription out;
  const auto finish = [&]() -> VerifiedTranscription& {
    out.solve_time_ms = 1e3 * secondsSince(started);
    out.time_limit_reached = out.time_limit_reached || out.solution.result.time_limit_reached ||
                             (out.status != SolveStatus::kConverged && options.time_limit_s &&
                              out.solve_time_ms >= 1e3 * *options.time_limit_s);
    return out;
  };
  if (std::optional<std::string> why = validateTranscriptionSolveOptions(options)) {
    out.status = SolveStatus::kError;
    out.reason = *why;
    return finish();
  }
  if (startMeetsGoal(problem, options.criteria)) {
    stayAtTheStart(vehicle, problem, options, out);
    return finish();
  }
  const Deadline deadline(started, options.time_limit_s, options.stop);
  DirectTranscriptionOptions transcription = options.transcription;
  transcription.stop = options.stop;
  // The problem's Segway look-ups (the verdict checks them) are constraints here too.
  if (problem.tables.segway != nullptr && !transcription.model.segway) {
    transcription.model.segway = SegwayConstraints{*problem.tables.segway};
  }
  // Verified against the true limits, and against lethal cells only (the verdict) rather than
  // the clearance the solver kept.
  TranscriptionModelOptions verification = transcription.model;
  verification.clearance.min_clearance = 0.0;
  const TranscriptionModel model(vehicle, problem, verification);
  double speed_margin = options.speed_margin, limit_margin = options.limit_margin;
  bool refined_again = false, widened = false;
  TranscriptionGuess start = guess;
  for (int round = 0; round <= options.max_rounds; ++round) {
    if (round > 0 && deadline.over()) {
      out.reason += " (no further round: the time limit is reached or a stop was requested)";
      out.time_limit_reached = true;
      break;
    }
    transcription.time_limit_s = deadline.left();
    if (transcription.model.segway) transcription.model.segway->bound_scale = 1.0 - speed_margin;
    out.solution = solveDirectTranscription(vehicle, tightened(problem, speed_margin, limit_margin),
                                            start, transcription);
    verifyTranscription(model, options.criteria, options.map, out);
    for (IterationRecord r : out.solution.result.history) {
      r.iteration += out.iterations;
      out.history.push_back(r);
    }
    out.iterations += out.solution.result.iterations;
    const int intervals = static_cast<int>(out.solution.mesh.size()) - 1;
    out.rounds.push_back({intervals, speed_margin, limit_margin,
                          transcription.model.clearance.map != nullptr
                              ? transcription.model.clearance.min_clearance
                              : 0.0,
                          out.status, out.reason, out.solution.result.iterations});
    if (out.status == SolveStatus::kConverged) break;
    if (out.solution.result.status != SolveStatus::kConverged) break;
    // Every further round starts from this one's solution.
    start = out.solution.asGuess();
    transcription.barrier = options.resolve_barrier;
    if (!out.verified.ok) {
      // Between its points the trajectory left the terrain (beside no data, where the clearance
      // it kept at the points is all that holds it): once more with the clearance floor.
      if (!out.verified.off_terrain || transcription.model.clearance.map == nullptr ||
          !(transcription.model.clearance.min_clearance < options.clearance_floor)) {
        break;
      }
      transcription.model.clearance.min_clearance = options.clearance_floor;
      continue;
    }
    // A curvature rule broken at rest: the rows that hold it there.
    if (!transcription.rest_curvature &&
        (standsStill(problem.start) || standsStill(problem.goal)) &&
        (out.verdict.check.find("kappa_max") != nullptr ||
         out.verdict.check.find("sigma_max") != nullptr)) {
      transcription.rest_curvature = true;
      continue;
    }
    const bool can_refine = transcription.intervals < options.max_intervals;
    const auto [speed_excess, limit_excess] = relativeExcess(out.verdict.check);
    // A missed goal (with limits broken or not) or a limit broken far between the points is the
    // discretisation's error: more intervals, before margins that would cost that much time.
    const bool coarse =
        out.verdict.misses_goal || std::max(speed_excess, limit_excess) > options.mesh_excess;
    if (coarse && can_refine && !clipsMap(out.verdict.check)) {
      refineMesh(model, problem, options, out, transcription);
    } else if (out.verdict.failure == models::VerdictFailure::kMissesGoal) {
      // The discretisation error: more intervals.
      if (!can_refine) {
        out.reason += ": the mesh is at its cap of " + std::to_string(options.max_intervals) +
                      " intervals (raise it)";
        break;
      }
      refineMesh(model, problem, options, out, transcription);
    } else if (clipsMap(out.verdict.check) && transcription.model.clearance.map != nullptr &&
               transcription.model.clearance.min_clearance < options.clearance_floor) {
      transcription.model.clearance.min_clearance = options.clearance_floor;
    } else if (widened && !refined_again && can_refine) {
      // A limit still broken between the points: the overshoot shrinks with the interval.
      refineMesh(model, problem, options, out, transcription);
      refined_again = true;
    } else {
      // A limit broken between the points (the states are quadratic there): margins wider by
      // the measured excess, with room to spare (margins cost optimality, little).
      double speed_excess_used = speed_excess;  // with the Segway's look-ups
      const LimitViolation& segway = out.verified.violation;
      if (segway.limit.rfind("segway", 0) == 0 && segway.amount > 0.0) {
        // The Segway's look-ups as the re-simulation checks them (the optimiser's C1 versions,
        // relative to v_max or a_max), beside the check's (their grids, relative to the
        // looked-up bound: relativeExcess).
        const double bound =
            segway.limit == "segway_slope_v_max" ? problem.limits.v_max : problem.limits.a_max;
        speed_excess_used = std::max(speed_excess, segway.amount / std::max(bound, 1e-9));
      }
      const double speed_floor = std::max(speed_margin, 1e-4);
      const double limit_floor = std::max(limit_margin, 1e-3);
      if (speed_excess_used > 0.0) {
        speed_margin =
            std::min(0.25, std::max(2.0 * speed_floor, speed_floor + 2.0 * speed_excess_used));
      }
      if (limit_excess > 0.0) {
        limit_margin =
            std::min(0.25, std::max(2.0 * limit_floor, limit_floor + 2.0 * limit_excess));
      }
      if (speed_excess_used == 0.0 && limit_excess == 0.0) {
        speed_margin = std::min(0.25, 4.0 * speed_floor);
        limit_margin = std::min(0.25, 2.0 * limit_floor);
      }
      widened = true;
    }
  }
  return finish();
}

}  // namespace terratraj::ocp
