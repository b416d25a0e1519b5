#include "terratraj/refine/candidate_refiner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>

#include "candidate_completion.hpp"
#include "format_number.hpp"
#include "terratraj/ocp/solution_verdict.hpp"
#include "terratraj/ocp/start_at_goal.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_model.hpp"
#include "terratraj/ocp/transcription_solver.hpp"
#include "terratraj/search/bang_bang_bound.hpp"

namespace terratraj::refine {

using search::PlanningProblem;
using search::ReferenceFrames;
namespace {

using models::TrajectoryColumn;

using detail::candidateError;
using detail::completeCandidate;
using detail::fillAttitude;
using detail::formatNumber;
using detail::formatPoint;
using detail::hasTiming;

// The coarse solve's stall acceptance (ocp::StallAcceptance), looser than the fine solve's: its
// solution is never a result, only the fine mesh's start.
constexpr double kCoarseStallCostChange = 1e-4;  // relative, over the window
constexpr double kCoarseStallViolation = 1e-3;   // the rows' violation, unscaled

int curvatureSignChanges(const models::Trajectory& t) {
  int changes = 0, sign = 0;
  for (const models::TrajectorySample& s : t.samples) {
    if (!std::isfinite(s.curvature) || std::abs(s.curvature) < 1e-3) continue;
    const int current = s.curvature > 0.0 ? 1 : -1;
    if (sign != 0 && current != sign) ++changes;
    sign = current;
  }
  return changes;
}

double polylineLength(const std::vector<Eigen::Vector2d>& points) {
  double length = 0.0;
  for (std::size_t i = 1; i < points.size(); ++i) length += (points[i] - points[i - 1]).norm();
  return length;
}

std::vector<Eigen::Vector2d> polyline(const models::Trajectory& t) {
  std::vector<Eigen::Vector2d> points;
  points.reserve(t.samples.size());
  for (const models::TrajectorySample& s : t.samples) points.emplace_back(s.x, s.y);
  return points;
}

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

double RefinementResult::costRatio() const {
  if (!candidate_figures || !refined_figures || !(candidate_figures->cost > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return refined_figures->cost / candidate_figures->cost;
}

namespace {
// Beyond the vehicle's sampling radius, how far the optimiser keeps from where the surface is
// undefined beside no data [m]: its constraints hold within Ipopt's tolerance, and the region's
// edge itself may be undefined.
constexpr double kNoDataEdgeMarginM = 0.01;
}  // namespace

CandidateRefiner::CandidateRefiner(const PlanningProblem& problem,
                                   const ocp::BoundaryValueProblem& bvp,
                                   const ReferenceFrames& frames, const RefinementOptions& options)
    : problem_(&problem),
      bvp_(&bvp),
      frames_(&frames),
      options_(options),
      clearance_(*problem.map, 1e3, problem.vehicle->surface().stencilReach(),
                 problem.vehicle->samplingRadius() + kNoDataEdgeMarginM),
      candidate_requirements_(requirementsOf(problem)),
      refined_requirements_(ocp::solveRequirements(*problem.vehicle, bvp,
                                                   options.parametric.criteria, problem.map)) {}

TrajectoryFigures CandidateRefiner::measure(
    const models::Trajectory& trajectory,
    const models::TrajectoryRequirements& requirements) const {
  TrajectoryFigures f = figuresOf(trajectory);
  f.check = models::checkTrajectory(trajectory, requirements);
  return f;
}

double CandidateRefiner::nearOptimalTime(double length) const {
  return options_.warm_start_time_ratio * search::bangBangTime(length, bvp_->start.v, bvp_->goal.v,
                                                               bvp_->goal.v, bvp_->limits.v_max,
                                                               bvp_->limits.a_max);
}

std::string CandidateRefiner::classOf(const std::vector<Eigen::Vector2d>& path) const {
  // Closed at the exact ends: a candidate stops anywhere in the goal region and a solver within
  // its tolerance, and a frame through the goal must count the same for both.
  return frames_
      ->signatureBetween(Eigen::Vector2d(bvp_->start.x, bvp_->start.y), path,
                         Eigen::Vector2d(bvp_->goal.x, bvp_->goal.y))
      .toString();
}

TrajectoryFigures CandidateRefiner::figuresOf(const models::Trajectory& trajectory) const {
  TrajectoryFigures f;
  const std::vector<models::TrajectorySample>& s = trajectory.samples;
  const bool dwell = bvp_->cost.kind == ocp::CostKind::kSlopeDwell;
  const auto integrand = [&](const models::TrajectorySample& x) {
    return dwell ? 1.0 + bvp_->cost.alpha * (x.roll * x.roll + x.pitch * x.pitch) : 1.0;
  };
  f.min_clearance_m = std::numeric_limits<double>::infinity();
  for (std::size_t i = 0; i < s.size(); ++i) {
    f.max_abs_pitch = std::max(f.max_abs_pitch, std::abs(s[i].pitch));
    f.max_abs_roll = std::max(f.max_abs_roll, std::abs(s[i].roll));
    f.max_speed = std::max(f.max_speed, s[i].v);
    const std::optional<terrain::Clearance> c =
        clearance_.hasImpassableCells() ? clearance_.at({s[i].x, s[i].y}) : std::nullopt;
    if (c) f.min_clearance_m = std::min(f.min_clearance_m, c->distance);
    if (i > 0) f.cost += 0.5 * (integrand(s[i - 1]) + integrand(s[i])) * (s[i].t - s[i - 1].t);
  }
  if (!s.empty()) f.duration_s = s.back().t - s.front().t;
  f.length_m = trajectory.planarLength();
  f.homotopy = classOf(polyline(trajectory));
  return f;
}

namespace {

// A candidate must run from the start to the goal: its ends within `tolerance` [m].
std::optional<std::string> endpointError(const models::Trajectory& candidate,
                                         const ocp::BoundaryValueProblem& bvp, double tolerance) {
  const models::TrajectorySample& first = candidate.samples.front();
  const models::TrajectorySample& last = candidate.samples.back();
  const double from_start = std::hypot(first.x - bvp.start.x, first.y - bvp.start.y);
  const double from_goal = std::hypot(last.x - bvp.goal.x, last.y - bvp.goal.y);
  if (from_start > tolerance) {
    return "the candidate starts at " + formatPoint(first.x, first.y) + ", " +
           formatNumber(from_start) + " m from the problem's start " +
           formatPoint(bvp.start.x, bvp.start.y) +
           " (refine.endpoint_tolerance_m = " + formatNumber(tolerance) +
           " m): it is not a candidate for this problem";
  }
  if (from_goal > tolerance) {
    return "the candidate ends at " + formatPoint(last.x, last.y) + ", " + formatNumber(from_goal) +
           " m from the problem's goal " + formatPoint(bvp.goal.x, bvp.goal.y) +
           " (refine.endpoint_tolerance_m = " + formatNumber(tolerance) +
           " m): it is not a candidate for this problem";
  }
  return std::nullopt;
}

}  // namespace

double CandidateRefiner::candidateCostAtGoal(const TrajectoryFigures& before,
                                             const RefinementResult& out) const {
  const models::TrajectorySample& last = out.candidate.samples.back();
  const double distance = std::hypot(last.x - bvp_->goal.x, last.y - bvp_->goal.y);
  return before.cost + distance / bvp_->limits.v_max;
}

bool CandidateRefiner::worseThanCandidate(const TrajectoryFigures& before,
                                          const RefinementResult& out) const {
  return out.status == ocp::SolveStatus::kConverged && before.check.ok() && out.refined_figures &&
         out.refined_figures->cost >
             candidateCostAtGoal(before, out) * (1.0 + options_.worse_tolerance);
}

void CandidateRefiner::accept(ocp::SolveStatus status, std::string reason,
                              models::TrajectoryVerdict verdict, const TrajectoryFigures& before,
                              RefinementResult& out) const {
  out.status = status;
  out.reason = std::move(reason);
  if (!out.verified.ok) return;
  out.verdict = std::move(verdict);
  TrajectoryFigures after = figuresOf(out.verified.trajectory);
  after.check = out.verdict.check;
  out.refined_figures = std::move(after);
  out.homotopy_kept = out.refined_figures->homotopy == before.homotopy;
  if (out.status != ocp::SolveStatus::kConverged) return;
  if (!out.homotopy_kept) {
    out.status = ocp::SolveStatus::kInfeasible;
    out.reason = "the refined trajectory left the candidate's homotopy class ('" + before.homotopy +
                 "' -> '" + out.refined_figures->homotopy + "')";
  }
}

ocp::SolveStatus CandidateRefiner::refineAtStart(RefinementResult& out) const {
  out.method_rule = "the start already meets the goal: nothing to drive";
  if (std::optional<models::Trajectory> here =
          ocp::startOnlyTrajectory(*problem_->vehicle, *bvp_)) {
    out.verified.ok = true;
    out.verified.trajectory = std::move(*here);
    out.verdict = models::judgeTrajectory(out.verified.trajectory, refined_requirements_);
    out.refined_figures = figuresOf(out.verified.trajectory);
    out.refined_figures->check = out.verdict.check;
    out.homotopy_kept = true;
  }
  return out.verified.ok ? ocp::statusAfterVerdict(ocp::SolveStatus::kConverged, out.verdict)
                         : ocp::SolveStatus::kInfeasible;
}

void CandidateRefiner::solveParametric(const TrajectoryFigures& before, const Deadline& deadline,
                                       RefinementResult& out) const {
  // The speed free to rise and fall: a cubic speed polynomial at least (a linear one fixes the
  // speed profile between the end speeds).
  ocp::BoundaryValueProblem parametric = *bvp_;
  parametric.orders.speed = std::max(parametric.orders.speed, 3);
  ocp::BoundaryValueOptions settings = options_.parametric;
  settings.method = out.method == RefineMethod::kNewton ? ocp::BoundaryValueMethod::kNewton
                                                        : ocp::BoundaryValueMethod::kIpopt;
  if (deadline.limit()) settings.time_limit_s = deadline.left();
  settings.stop = deadline.stop();
  out.parametric = ocp::solveBoundaryValue(*problem_->vehicle, parametric, settings, problem_->map);
  out.verified = out.parametric->verified;
  out.history = out.parametric->solver.history;
  out.iterations = out.parametric->solver.iterations;
  out.time_limit_reached = out.time_limit_reached || out.parametric->time_limit_reached;
  accept(out.parametric->status, out.parametric->reason, out.parametric->verdict, before, out);
}

RefinementResult CandidateRefiner::refine(const models::Trajectory& candidate) const {
  const auto started = std::chrono::steady_clock::now();
  RefinementResult out;
  out.method = options_.method;
  const auto finish = [&](ocp::SolveStatus status, std::string reason) -> RefinementResult& {
    out.status = status;
    out.reason = std::move(reason);
    out.solve_time_ms = millisecondsSince(started);
    return out;
  };
  if (std::optional<std::string> why = validateRefinementOptions(options_)) {
    return finish(ocp::SolveStatus::kError, "refinement options: " + *why);
  }
  if (ocp::startMeetsGoal(*bvp_, options_.parametric.criteria)) {
    // Nothing to drive, whatever the candidate.
    const ocp::SolveStatus status = refineAtStart(out);
    return finish(status,
                  status == ocp::SolveStatus::kConverged ? out.method_rule : out.verdict.reason);
  }

  if (std::optional<std::string> why = candidateError(candidate, problem_->map->geometry())) {
    return finish(ocp::SolveStatus::kError, *why);
  }
  if (std::optional<std::string> why =
          endpointError(candidate, *bvp_, options_.endpoint_tolerance_m)) {
    return finish(ocp::SolveStatus::kError, *why);
  }

  // 1. Complete the candidate and measure it.
  Expected<ocp::TranscriptionGuess> guess =
      hasTiming(candidate) ? ocp::guessFromTrajectory(candidate)
                           : ocp::guessFromPath(polyline(candidate), *bvp_,
                                                options_.guess_spacing_m, problem_->vehicle);
  if (!guess) return finish(ocp::SolveStatus::kError, "the candidate: " + guess.reason());
  for (std::size_t c = 0; c < models::kTrajectoryColumnCount; ++c) {
    if (!candidate.has_column[c]) {
      out.derived_columns.emplace_back(
          models::trajectoryColumnName(static_cast<TrajectoryColumn>(c)));
    }
  }
  out.candidate = completeCandidate(candidate, *guess);
  std::string why;
  if (!fillAttitude(*problem_->vehicle, out.candidate, why)) {
    return finish(ocp::SolveStatus::kError, "the candidate: " + why);
  }
  const auto measure_started = std::chrono::steady_clock::now();
  out.candidate_figures = measure(out.candidate, candidate_requirements_);
  const TrajectoryFigures& before = *out.candidate_figures;
  // Time kept back from the solvers for the final re-simulation and check (about what the
  // candidate's measurement took, twice, plus a margin).
  const double reserve_s =
      2.0 * millisecondsSince(measure_started) / 1000.0 + 0.005 + 1e-6 * before.duration_s;

  const ocp::TranscriptionGuess candidate_guess = *guess;
  const ocp::TranscriptionGuess start_guess = startingGuess(before, candidate_guess, out);

  // 2. Choose the method.
  out.method = chooseRefineMethod(options_, before.length_m, before.min_clearance_m,
                                  curvatureSignChanges(out.candidate), out.method_rule);
  const Deadline solver_deadline(
      started,
      options_.time_limit_s
          ? std::optional<double>(std::max(0.0, *options_.time_limit_s - reserve_s))
          : std::nullopt,
      options_.stop);

  // 3. Solve; with kAuto, a parametric solve that fails or ends worse than the candidate falls
  // back to collocation.
  if (out.method == RefineMethod::kNewton || out.method == RefineMethod::kIpopt) {
    solveParametric(before, solver_deadline, out);
    const bool worse = worseThanCandidate(before, out);
    const bool done = out.status == ocp::SolveStatus::kConverged && !worse;
    if (done || options_.method != RefineMethod::kAuto || solver_deadline.over()) {
      // kAuto's collocation skipped for lack of time.
      if (!done && options_.method == RefineMethod::kAuto) out.time_limit_reached = true;
      return finishRefinement(before, out, started);
    }
    out.method_rule +=
        "; ipopt ended " +
        std::string(worse ? "worse than the candidate" : ocp::solveStatusName(out.status)) +
        (out.reason.empty() ? "" : " (" + out.reason + ")") + ", so collocation";
    out.method = RefineMethod::kCollocation;
    out.refined_figures.reset();
    out.parametric.reset();
  }

  transcribe(start_guess, before, clearance_, solver_deadline, out);
  // Interior-point iterates may pass through a small obstacle: once the class is lost, solve
  // again from the candidate inside a corridor around it, which the clearance constraint keeps.
  const bool class_retry =
      out.refined_figures && !out.homotopy_kept && options_.corridor_radius_m > 0.0;
  const bool out_of_time = class_retry && solver_deadline.over();
  if (out_of_time) out.time_limit_reached = true;  // the retry skipped for lack of time
  if (class_retry && !out_of_time) {
    const terrain::ClearanceMap corridor(corridorMap(out.candidate));
    out.corridor_radius_m = options_.corridor_radius_m;
    out.refined_figures.reset();
    transcribe(candidate_guess, before, corridor, solver_deadline, out);
  }
  return finishRefinement(before, out, started);
}

ocp::TranscriptionGuess CandidateRefiner::startingGuess(const TrajectoryFigures& before,
                                                        const ocp::TranscriptionGuess& candidate,
                                                        RefinementResult& out) const {
  ocp::TranscriptionGuess guess = candidate;
  // A wiggly candidate (a PRM's first solution, with loops) starts the optimiser from its
  // shortcut path instead, when that keeps the class: loops and detours cost iterations and
  // can trap it.
  if (options_.shortcut_clearance_m > 0.0) {
    const std::vector<Eigen::Vector2d> shortcut =
        shortcutPath(polyline(out.candidate), options_.shortcut_clearance_m);
    const double length = polylineLength(shortcut);
    if (length < options_.shortcut_gain * before.length_m && classOf(shortcut) == before.homotopy) {
      if (Expected<ocp::TranscriptionGuess> shorter =
              ocp::guessFromPath(shortcut, *bvp_, options_.guess_spacing_m, problem_->vehicle)) {
        guess = std::move(*shorter);
        out.guess_shortcut_m = before.length_m - length;
      }
    }
  }
  // A slow candidate whose shortcut is not used (a PRM's first solution on a forest: its path
  // near the shortest, its speed profile slow) starts from its own path re-timed by the
  // forward-backward speed pass when that is faster: an evenly sampled, consistent guess (the
  // PRM's own samples change speed at every milestone). Forest PRM first solutions: 54-142 ->
  // 19-68 coarse iterations, the same optima (bench refine).
  if (out.guess_shortcut_m == 0.0 && !(guess.finalTime() <= nearOptimalTime(before.length_m))) {
    if (Expected<ocp::TranscriptionGuess> retimed = ocp::guessFromPath(
            polyline(out.candidate), *bvp_, options_.guess_spacing_m, problem_->vehicle)) {
      if (retimed->finalTime() < guess.finalTime()) {
        out.guess_retimed_s = guess.finalTime() - retimed->finalTime();
        guess = std::move(*retimed);
      }
    }
  }
  return guess;
}

RefinementResult& CandidateRefiner::finishRefinement(
    const TrajectoryFigures& before, RefinementResult& out,
    std::chrono::steady_clock::time_point started) const {
  // A refinement worse than its feasible candidate is not converged: the candidate is the
  // result.
  if (worseThanCandidate(before, out)) {
    out.status = ocp::SolveStatus::kDiverged;
    out.returned_candidate = true;
    out.reason = "the refinement ended at cost " + formatNumber(out.refined_figures->cost) +
                 ", worse than the feasible candidate's " + formatNumber(before.cost) +
                 " (credited with its distance to the exact goal at v_max: " +
                 formatNumber(candidateCostAtGoal(before, out)) + ", tolerance " +
                 formatNumber(100.0 * options_.worse_tolerance) +
                 " %); a worse local optimum: the candidate is returned";
  }
  out.solve_time_ms = millisecondsSince(started);
  return out;
}

std::optional<ocp::TranscriptionGuess> CandidateRefiner::solveCoarse(
    const ocp::TranscriptionGuess& guess, const ocp::DirectTranscriptionOptions& fine,
    double mesh_excess, int coarse_intervals, const Deadline& deadline,
    RefinementResult& out) const {
  ocp::DirectTranscriptionOptions coarse = fine;
  coarse.intervals = coarse_intervals;
  // Only a start for the fine mesh: a cycle near a kink of the terrain (the Segway's look-ups
  // on a DEM at rover scale: 250 iterations within 3e-5 of the cost, the rows broken by up to
  // 3e-4 on every other iterate) is as good a start as its end.
  coarse.stall.cost_change = kCoarseStallCostChange;
  coarse.stall.constraint_violation = kCoarseStallViolation;
  if (deadline.limit()) coarse.time_limit_s = deadline.left();
  coarse.stop = deadline.stop();
  ocp::BoundaryValueProblem tightened = *bvp_;
  tightened.limits.v_max = std::max(tightened.limits.v_max * (1.0 - options_.speed_margin),
                                    std::max(bvp_->start.v, bvp_->goal.v));
  tightened.limits.omega_max =
      std::max(tightened.limits.omega_max * (1.0 - options_.speed_margin),
               std::max(std::abs(bvp_->start.omega), std::abs(bvp_->goal.omega)));
  const ocp::TranscriptionSolution solution =
      ocp::solveDirectTranscription(*problem_->vehicle, tightened, guess, coarse);
  out.history = solution.result.history;
  out.iterations = solution.result.iterations;
  out.coarse_intervals = coarse_intervals;
  out.coarse_iterations = solution.result.iterations;
  out.coarse_status = solution.result.status;
  out.time_limit_reached = out.time_limit_reached || solution.result.time_limit_reached;
  if (solution.result.status != ocp::SolveStatus::kConverged) return std::nullopt;
  // A coarse solution can cut across ground its points never touched (a slope beyond the
  // Segway's drivable one between two points on a DEM at rover scale, case 405 of
  // `bench robustness --seed 11`); started there, the fine solve spends its budget in
  // restoration. It then starts from the guess instead.
  ocp::TranscriptionGuess coarse_solution = solution.asGuess();
  const int fine_points = 2 * fine.intervals + 1;
  out.coarse_limit_excess =
      ocp::guessLimitExcess(coarse_solution, *bvp_, *problem_->vehicle, fine_points);
  const double guess_excess = ocp::guessLimitExcess(guess, *bvp_, *problem_->vehicle, fine_points);
  if (!(out.coarse_limit_excess <= std::max(mesh_excess, guess_excess))) return std::nullopt;
  out.coarse_used = true;
  return coarse_solution;
}

void CandidateRefiner::transcribe(const ocp::TranscriptionGuess& guess,
                                  const TrajectoryFigures& before,
                                  const terrain::ClearanceMap& clearance, const Deadline& deadline,
                                  RefinementResult& out) const {
  ocp::TranscriptionSolveOptions solve;
  ocp::DirectTranscriptionOptions& transcription = solve.transcription;
  transcription = options_.transcription;
  if (out.method == RefineMethod::kShooting) {
    transcription.scheme = ocp::TranscriptionScheme::kMultipleShooting;
  } else if (transcription.scheme == ocp::TranscriptionScheme::kMultipleShooting) {
    transcription.scheme = ocp::TranscriptionScheme::kHermiteSimpson;
  }
  // Intervals by the length of the path the optimiser starts from (the shortcut's, if used).
  std::vector<Eigen::Vector2d> guess_path;
  guess_path.reserve(guess.points.size());
  for (const ocp::PointVector& w : guess.points) guess_path.emplace_back(w(0), w(1));
  const double length = polylineLength(guess_path);
  transcription.intervals =
      std::clamp(static_cast<int>(std::ceil(length / options_.interval_length_m)),
                 options_.min_intervals, options_.max_intervals);
  // The clearance constraint keeps the optimiser off impassable cells; a trajectory that clips
  // one between its points is solved again with at least half a cell of clearance (capped by
  // min_clearance_m): the bilinear distance transform rounds a lethal cell's corners.
  if (clearance_.hasImpassableCells()) {
    out.clearance_used_m =
        std::max(0.0, std::min(options_.min_clearance_m, 0.5 * before.min_clearance_m));
    transcription.model.clearance = {&clearance, out.clearance_used_m};
    solve.clearance_floor =
        std::min(options_.min_clearance_m, 0.5 * problem_->map->geometry().cell);
  }
  solve.criteria = options_.parametric.criteria;
  solve.map = problem_->map;
  solve.speed_margin = options_.speed_margin;
  solve.limit_margin = options_.limit_margin;
  solve.max_rounds = options_.margin_retries;
  solve.max_intervals = options_.max_intervals;
  solve.stop = deadline.stop();
  out.history.clear();
  out.iterations = 0;
  out.coarse_intervals = 0;
  out.coarse_iterations = 0;
  out.coarse_limit_excess = 0.0;
  out.coarse_used = false;
  // A coarse mesh first for a wiggly candidate (one whose shortcut guess is in use) or a slow
  // one (slower than warm_start_time_ratio x the bang-bang time along its path, as a PRM's
  // first solution): it is straightened and sped up there at a fraction of the cost, and the
  // fine mesh starts warm from a smooth, near-optimal guess (forest PRM first solutions, with
  // the re-timed guess: 1.7-3.8x faster, same optima, measured with bench refine). A near-optimal
  // candidate goes straight to the fine mesh: at 1 m intervals the clearance held only at the
  // points let a TAEASL route settle 2 % longer, round an unframed obstacle.
  ocp::TranscriptionGuess start = guess;
  const int coarse_intervals = std::clamp(
      static_cast<int>(std::ceil(length / options_.coarse_interval_length_m)),
      std::min(options_.min_intervals, transcription.intervals), transcription.intervals);
  const double fast_time_s = nearOptimalTime(length);
  const bool slow_guess = !(guess.finalTime() <= fast_time_s);
  if ((out.guess_shortcut_m > 0.0 || slow_guess) &&
      coarse_intervals < transcription.intervals / 2) {
    if (std::optional<ocp::TranscriptionGuess> coarse =
            solveCoarse(guess, transcription, solve.mesh_excess, coarse_intervals, deadline, out)) {
      start = std::move(*coarse);
    }
  }
  // Started near a locally optimal solution (the coarse mesh's, or a candidate that drives its
  // path about as fast as the limits allow), a monotone barrier from a small mu takes half the
  // iterations of the adaptive one; from a slow or wiggly guess it crawls.
  const bool near_optimal = out.coarse_used || start.finalTime() <= fast_time_s;
  out.warm_start = near_optimal;
  if (out.warm_start) {
    solve.transcription.barrier = ocp::TranscriptionBarrier::kWarm;
    solve.resolve_barrier = ocp::TranscriptionBarrier::kWarm;
  }
  if (deadline.limit()) solve.time_limit_s = deadline.left();
  ocp::VerifiedTranscription result =
      ocp::solveTranscription(*problem_->vehicle, *bvp_, start, solve);
  for (ocp::IterationRecord r : result.history) {
    r.iteration += out.iterations;
    out.history.push_back(r);
  }
  out.iterations += result.iterations;
  out.time_limit_reached = out.time_limit_reached || result.time_limit_reached;
  out.transcription = result.solution;
  out.intervals = static_cast<int>(result.solution.mesh.size()) - 1;
  out.margin_rounds = static_cast<int>(result.rounds.size());
  if (!result.rounds.empty()) {
    out.speed_margin_used = result.rounds.back().speed_margin;
    out.limit_margin_used = result.rounds.back().limit_margin;
    out.clearance_used_m = result.rounds.back().clearance_m;
  }
  out.verified = std::move(result.verified);
  out.refined_figures.reset();
  accept(result.status, result.reason, std::move(result.verdict), before, out);
  if (out.verdict.failure == models::VerdictFailure::kMissesGoal &&
      out.status == ocp::SolveStatus::kDiverged && out.intervals < options_.max_intervals) {
    out.reason += ": shorten refine.interval_length_m";
  } else if (out.verdict.failure == models::VerdictFailure::kMissesGoal) {
    out.reason += " (refine.max_intervals)";
  }
}

}  // namespace terratraj::refine
