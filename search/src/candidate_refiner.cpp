#include "terratraj/search/candidate_refiner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "terratraj/ocp/solution_verdict.hpp"
#include "terratraj/ocp/start_at_goal.hpp"
#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_model.hpp"
#include "terratraj/ocp/transcription_solver.hpp"

namespace terratraj::search {
namespace {

using models::TrajectoryColumn;

constexpr std::array<std::pair<RefineMethod, const char*>, 5> kMethodNames{{
    {RefineMethod::kAuto, "auto"},
    {RefineMethod::kCollocation, "collocation"},
    {RefineMethod::kShooting, "shooting"},
    {RefineMethod::kNewton, "newton"},
    {RefineMethod::kIpopt, "ipopt"},
}};

std::string formatNumber(double value) {
  std::ostringstream text;
  text << value;
  return text.str();
}

std::string formatPoint(double x, double y) {
  return "(" + formatNumber(x) + ", " + formatNumber(y) + ")";
}

// Why the candidate cannot be refined (a single point, NaN, off the map), or std::nullopt.
std::optional<std::string> candidateError(const models::Trajectory& candidate,
                                          const terrain::GridGeometry& geometry) {
  if (!candidate.has(TrajectoryColumn::kX) || !candidate.has(TrajectoryColumn::kY)) {
    return std::string("the candidate has no x and y columns");
  }
  if (candidate.samples.size() < 2) {
    return "the candidate is a single point (" + std::to_string(candidate.samples.size()) +
           " sample" + (candidate.samples.size() == 1 ? "" : "s") + "): a path needs two";
  }
  bool distinct = false;
  const models::TrajectorySample& first = candidate.samples.front();
  for (std::size_t i = 0; i < candidate.samples.size(); ++i) {
    const models::TrajectorySample& s = candidate.samples[i];
    if (!std::isfinite(s.x) || !std::isfinite(s.y)) {
      return candidate.sampleName(i) + ": x, y is not a finite number";
    }
    if (!geometry.contains({s.x, s.y})) {
      return candidate.sampleName(i) + " at " + formatPoint(s.x, s.y) + " leaves the map (0..." +
             formatNumber(geometry.width()) + " x 0..." + formatNumber(geometry.height()) +
             " m, local frame)";
    }
    if (std::hypot(s.x - first.x, s.y - first.y) > 1e-6) distinct = true;
  }
  if (!distinct) return std::string("the candidate is a single point: all its samples coincide");
  return std::nullopt;
}

bool hasTiming(const models::Trajectory& t) {
  if (!t.has(TrajectoryColumn::kT) || !t.has(TrajectoryColumn::kV) ||
      !t.has(TrajectoryColumn::kHeading)) {
    return false;
  }
  return std::all_of(t.samples.begin(), t.samples.end(), [](const models::TrajectorySample& s) {
    return std::isfinite(s.t) && std::isfinite(s.v) && std::isfinite(s.heading);
  });
}

// Fills z, roll, pitch from the vehicle model at every sample; false (and `why`) where the
// vehicle cannot rest.
bool fillAttitude(const models::TerrainFollowingModel& vehicle, models::Trajectory& trajectory,
                  std::string& why) {
  models::AttitudeWorkspace workspace;
  models::AttitudeResult result;
  for (std::size_t i = 0; i < trajectory.samples.size(); ++i) {
    models::TrajectorySample& s = trajectory.samples[i];
    const models::AttitudeStatus status = vehicle.compute({s.x, s.y, s.heading}, workspace, result);
    if (status != models::AttitudeStatus::kOk) {
      why = trajectory.sampleName(i) + " at " + formatPoint(s.x, s.y) +
            ": the vehicle cannot rest there (" + models::attitudeStatusName(status) + ")";
      return false;
    }
    s.z = result.attitude.z;
    s.roll = result.attitude.roll;
    s.pitch = result.attitude.pitch;
  }
  for (TrajectoryColumn c :
       {TrajectoryColumn::kZ, TrajectoryColumn::kRoll, TrajectoryColumn::kPitch}) {
    trajectory.has_column[static_cast<std::size_t>(c)] = true;
  }
  return true;
}

// The candidate with every column: its own samples when it has timing, else the samples of
// its guess (resampled by arc length with a feasible speed profile).
models::Trajectory completeCandidate(const models::Trajectory& candidate,
                                     const ocp::TranscriptionGuess& guess) {
  models::Trajectory full;
  if (hasTiming(candidate)) {
    full = candidate;
    // Fill what is missing from the guess built on the same samples.
    for (std::size_t i = 0; i < full.samples.size() && i < guess.points.size(); ++i) {
      models::TrajectorySample& s = full.samples[i];
      const ocp::PointVector& w = guess.points[i];
      if (!full.has(TrajectoryColumn::kOmega) || !std::isfinite(s.omega)) s.omega = w(4);
      if (!full.has(TrajectoryColumn::kCurvature) || !std::isfinite(s.curvature)) {
        s.curvature = s.v > 1e-9 ? s.omega / s.v : 0.0;
      }
    }
  } else {
    full.samples.reserve(guess.points.size());
    for (std::size_t i = 0; i < guess.points.size(); ++i) {
      const ocp::PointVector& w = guess.points[i];
      models::TrajectorySample s = models::TrajectorySample::unknown();
      s.t = guess.t[i];
      s.x = w(0);
      s.y = w(1);
      s.heading = w(2);
      s.v = w(3);
      s.omega = w(4);
      s.curvature = w(3) > 1e-9 ? w(4) / w(3) : 0.0;
      full.samples.push_back(s);
    }
  }
  full.ignored_columns.clear();
  for (TrajectoryColumn c : {TrajectoryColumn::kT, TrajectoryColumn::kX, TrajectoryColumn::kY,
                             TrajectoryColumn::kHeading, TrajectoryColumn::kV,
                             TrajectoryColumn::kOmega, TrajectoryColumn::kCurvature}) {
    full.has_column[static_cast<std::size_t>(c)] = true;
  }
  return full;
}

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

// Shortcutting: the candidate is resampled this often [m] and a straight segment may skip at
// most this many samples.
constexpr double kShortcutSpacing = 0.5;
constexpr std::size_t kShortcutWindow = 200;

double millisecondsSince(std::chrono::steady_clock::time_point start) {
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

}  // namespace

const char* refineMethodName(RefineMethod method) {
  for (const auto& [m, name] : kMethodNames) {
    if (m == method) return name;
  }
  return "?";
}

std::optional<RefineMethod> parseRefineMethod(std::string_view name) {
  for (const auto& [m, text] : kMethodNames) {
    if (name == text) return m;
  }
  return std::nullopt;
}

std::vector<std::string> refineMethodNames() {
  std::vector<std::string> names;
  for (const auto& entry : kMethodNames) names.emplace_back(entry.second);
  return names;
}

std::optional<std::string> validateRefinementOptions(const RefinementOptions& o) {
  if (!(o.interval_length_m > 0.0) || !std::isfinite(o.interval_length_m)) {
    return "interval_length_m must be a finite number > 0 (got " +
           formatNumber(o.interval_length_m) + ")";
  }
  if (o.min_intervals < 1) return "min_intervals must be >= 1";
  if (o.max_intervals < o.min_intervals) return "max_intervals must be >= min_intervals";
  if (!(o.min_clearance_m >= 0.0) || !std::isfinite(o.min_clearance_m)) {
    return "min_clearance_m must be a finite number >= 0 (got " + formatNumber(o.min_clearance_m) +
           ")";
  }
  if (!(o.guess_spacing_m > 0.0)) return "guess_spacing_m must be > 0";
  if (!(o.worse_tolerance >= 0.0) || !std::isfinite(o.worse_tolerance)) {
    return "worse_tolerance must be a finite number >= 0";
  }
  if (!(o.endpoint_tolerance_m > 0.0) || !std::isfinite(o.endpoint_tolerance_m)) {
    return "endpoint_tolerance_m must be a finite number > 0";
  }
  if (o.time_limit_s && !(*o.time_limit_s >= 0.0)) return "time_limit_s must be >= 0";
  if (o.margin_retries < 0) return "margin_retries must be >= 0";
  if (!(o.shortcut_clearance_m >= 0.0) || !std::isfinite(o.shortcut_clearance_m)) {
    return "shortcut_clearance_m must be a finite number >= 0";
  }
  if (!(o.shortcut_gain > 0.0 && o.shortcut_gain <= 1.0)) return "shortcut_gain must be in (0, 1]";
  if (!(o.corridor_radius_m >= 0.0) || !std::isfinite(o.corridor_radius_m)) {
    return "corridor_radius_m must be a finite number >= 0 (got " +
           formatNumber(o.corridor_radius_m) + ")";
  }
  if (!(o.coarse_interval_length_m > 0.0) || !std::isfinite(o.coarse_interval_length_m)) {
    return "coarse_interval_length_m must be a finite number > 0 (got " +
           formatNumber(o.coarse_interval_length_m) + ")";
  }
  if (!(o.speed_margin >= 0.0 && o.speed_margin < 0.5)) {
    return "speed_margin must be in [0, 0.5) (got " + formatNumber(o.speed_margin) + ")";
  }
  if (!(o.limit_margin >= 0.0 && o.limit_margin < 0.5)) {
    return "limit_margin must be in [0, 0.5) (got " + formatNumber(o.limit_margin) + ")";
  }
  return ocp::validateTranscriptionOptions(o.transcription);
}

double RefinementResult::costRatio() const {
  if (!candidate_figures || !refined_figures || !(candidate_figures->cost > 0.0)) {
    return std::numeric_limits<double>::quiet_NaN();
  }
  return refined_figures->cost / candidate_figures->cost;
}

RefineMethod chooseRefineMethod(const RefinementOptions& options, double length_m,
                                double min_clearance_m, int curvature_sign_changes,
                                std::string& rule) {
  if (options.method != RefineMethod::kAuto) {
    rule = "as configured";
    return options.method;
  }
  if (length_m > options.parametric_max_length_m) {
    rule = "collocation: the candidate is " + formatNumber(length_m) +
           " m long (polynomial controls up to " + formatNumber(options.parametric_max_length_m) +
           " m)";
    return RefineMethod::kCollocation;
  }
  if (min_clearance_m < options.parametric_min_clearance_m) {
    rule = "collocation: the candidate passes " + formatNumber(min_clearance_m) +
           " m from impassable cells (polynomial controls need " +
           formatNumber(options.parametric_min_clearance_m) +
           " m: they have no clearance constraint)";
    return RefineMethod::kCollocation;
  }
  if (curvature_sign_changes > options.parametric_max_curvature_sign_changes) {
    rule = "collocation: the candidate's curvature changes sign " +
           std::to_string(curvature_sign_changes) + " times (the yaw-rate polynomial " +
           "follows at most " + std::to_string(options.parametric_max_curvature_sign_changes) + ")";
    return RefineMethod::kCollocation;
  }
  rule = "ipopt (polynomial controls): short (" + formatNumber(length_m) +
         " m), clear of obstacles (" + formatNumber(min_clearance_m) + " m) and few turns (" +
         std::to_string(curvature_sign_changes) + " curvature sign changes)";
  return RefineMethod::kIpopt;
}

CandidateRefiner::CandidateRefiner(const PlanningProblem& problem,
                                   const ocp::BoundaryValueProblem& bvp,
                                   const ReferenceFrames& frames, const RefinementOptions& options)
    : problem_(&problem),
      bvp_(&bvp),
      frames_(&frames),
      options_(options),
      clearance_(*problem.map),
      candidate_requirements_(requirementsOf(problem)),
      refined_requirements_(ocp::solveRequirements(*problem.vehicle, bvp,
                                                   options.parametric.criteria, problem.map)) {}

double CandidateRefiner::Deadline::secondsLeft() const {
  if (!limit_s) return std::numeric_limits<double>::infinity();
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return std::max(0.0, *limit_s - elapsed);
}

bool CandidateRefiner::Deadline::over() const {
  return (stop != nullptr && stop->load()) || (limit_s && secondsLeft() <= 0.0);
}

TrajectoryFigures CandidateRefiner::measure(
    const models::Trajectory& trajectory,
    const models::TrajectoryRequirements& requirements) const {
  TrajectoryFigures f = figuresOf(trajectory);
  f.check = models::checkTrajectory(trajectory, requirements);
  return f;
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
  f.homotopy = frames_->signatureOf(polyline(trajectory)).toString();
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
    // Nothing to drive: the one-row trajectory at the start, whatever the candidate.
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
    const ocp::SolveStatus status =
        out.verified.ok ? ocp::statusAfterVerdict(ocp::SolveStatus::kConverged, out.verdict)
                        : ocp::SolveStatus::kInfeasible;
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
  std::string why;
  std::optional<ocp::TranscriptionGuess> guess =
      hasTiming(candidate)
          ? ocp::guessFromTrajectory(candidate, &why)
          : ocp::guessFromPath(polyline(candidate), *bvp_, options_.guess_spacing_m, &why);
  if (!guess) return finish(ocp::SolveStatus::kError, "the candidate: " + why);
  for (std::size_t c = 0; c < models::kTrajectoryColumnCount; ++c) {
    if (!candidate.has_column[c]) {
      out.derived_columns.emplace_back(
          models::trajectoryColumnName(static_cast<TrajectoryColumn>(c)));
    }
  }
  out.candidate = completeCandidate(candidate, *guess);
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

  // A wiggly candidate (a PRM's first solution, with loops) starts the optimiser from its
  // shortcut path instead, when that keeps the class: loops and detours cost iterations and
  // can trap it.
  const ocp::TranscriptionGuess candidate_guess = *guess;
  if (options_.shortcut_clearance_m > 0.0) {
    const std::vector<Eigen::Vector2d> shortcut =
        shortcutPath(polyline(out.candidate), options_.shortcut_clearance_m);
    const double length = polylineLength(shortcut);
    if (length < options_.shortcut_gain * before.length_m &&
        frames_->signatureOf(shortcut).toString() == before.homotopy) {
      if (std::optional<ocp::TranscriptionGuess> shorter =
              ocp::guessFromPath(shortcut, *bvp_, options_.guess_spacing_m, &why)) {
        guess = std::move(shorter);
        out.guess_shortcut_m = before.length_m - length;
      }
    }
  }

  // 2. Choose the method.
  out.method = chooseRefineMethod(options_, before.length_m, before.min_clearance_m,
                                  curvatureSignChanges(out.candidate), out.method_rule);
  const Deadline solver_deadline{
      started,
      options_.time_limit_s
          ? std::optional<double>(std::max(0.0, *options_.time_limit_s - reserve_s))
          : std::nullopt,
      options_.stop};

  // 3. Solve; with kAuto, a parametric solve that fails or ends worse than the candidate falls
  // back to collocation.
  if (out.method == RefineMethod::kNewton || out.method == RefineMethod::kIpopt) {
    // The speed free to rise and fall: a cubic speed polynomial at least (a linear one fixes
    // the speed profile between the end speeds).
    ocp::BoundaryValueProblem parametric = *bvp_;
    parametric.orders.speed = std::max(parametric.orders.speed, 3);
    ocp::BoundaryValueOptions settings = options_.parametric;
    settings.method = out.method == RefineMethod::kNewton ? ocp::BoundaryValueMethod::kNewton
                                                          : ocp::BoundaryValueMethod::kIpopt;
    if (solver_deadline.limit_s) settings.time_limit_s = solver_deadline.secondsLeft();
    out.parametric =
        ocp::solveBoundaryValue(*problem_->vehicle, parametric, settings, problem_->map);
    out.verified = out.parametric->verified;
    out.history = out.parametric->solver.history;
    out.iterations = out.parametric->solver.iterations;
    accept(out.parametric->status, out.parametric->reason, out.parametric->verdict, before, out);
    const bool worse = worseThanCandidate(before, out);
    if ((out.status == ocp::SolveStatus::kConverged && !worse) ||
        options_.method != RefineMethod::kAuto || solver_deadline.over()) {
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

  transcribe(*guess, before, clearance_, solver_deadline, out);
  // Interior-point iterates may pass through a small obstacle: once the class is lost, solve
  // again from the candidate inside a corridor around it, which the clearance constraint keeps.
  if (out.refined_figures && !out.homotopy_kept && options_.corridor_radius_m > 0.0 &&
      !solver_deadline.over()) {
    const terrain::ClearanceMap corridor(corridorMap(out.candidate));
    out.corridor_radius_m = options_.corridor_radius_m;
    out.refined_figures.reset();
    transcribe(candidate_guess, before, corridor, solver_deadline, out);
  }
  return finishRefinement(before, out, started);
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

terrain::ElevationMap CandidateRefiner::corridorMap(const models::Trajectory& candidate) const {
  terrain::ElevationMap map = *problem_->map;
  const terrain::GridGeometry& g = map.geometry();
  terrain::GridLayer& lethal = map.addLayer(terrain::layer_names::kLethal, 0.0f);
  std::vector<unsigned char> inside(g.cellCount(), 0);
  const double radius = options_.corridor_radius_m;
  const int reach = static_cast<int>(std::ceil(radius / g.cell));
  const auto markDisc = [&](const Eigen::Vector2d& centre) {
    const std::optional<terrain::CellIndex> c = g.cellAt(centre);
    if (!c) return;
    for (int r = std::max(0, c->row - reach); r <= std::min(g.rows - 1, c->row + reach); ++r) {
      for (int k = std::max(0, c->col - reach); k <= std::min(g.cols - 1, c->col + reach); ++k) {
        if ((g.cellCenter({r, k}) - centre).norm() <= radius) {
          inside[g.linearIndex({r, k})] = 1;
        }
      }
    }
  };
  // Discs every half cell along the candidate: their union is the corridor.
  const std::vector<models::TrajectorySample>& s = candidate.samples;
  for (std::size_t i = 0; i + 1 < s.size(); ++i) {
    const Eigen::Vector2d a(s[i].x, s[i].y), b(s[i + 1].x, s[i + 1].y);
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / (0.5 * g.cell))));
    for (int j = 0; j <= steps; ++j) markDisc(a + (b - a) * (static_cast<double>(j) / steps));
  }
  for (int r = 0; r < g.rows; ++r) {
    for (int k = 0; k < g.cols; ++k) {
      if (!inside[g.linearIndex({r, k})]) lethal(r, k) = 1.0f;
    }
  }
  return map;
}

std::vector<Eigen::Vector2d> CandidateRefiner::shortcutPath(
    const std::vector<Eigen::Vector2d>& path, double clearance) const {
  // The path every half metre.
  std::vector<Eigen::Vector2d> points{path.front()};
  for (std::size_t i = 1; i < path.size(); ++i) {
    const Eigen::Vector2d a = path[i - 1], b = path[i];
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / kShortcutSpacing)));
    for (int j = 1; j <= steps; ++j)
      points.push_back(a + (b - a) * (static_cast<double>(j) / steps));
  }
  const double step = 0.25 * problem_->map->geometry().cell;
  const auto clear = [&](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm() / step)));
    for (int j = 0; j <= steps; ++j) {
      const std::optional<terrain::Clearance> c =
          clearance_.at(a + (b - a) * (static_cast<double>(j) / steps));
      if (!c || c->distance < clearance) return false;
    }
    return true;
  };
  // Greedy: from each kept point, the farthest point within the window reachable straight.
  std::vector<Eigen::Vector2d> out{points.front()};
  std::size_t i = 0;
  const std::size_t last = points.size() - 1;
  while (i < last) {
    std::size_t best = i + 1;
    for (std::size_t j = std::min(last, i + kShortcutWindow); j > i + 1; --j) {
      if (clear(points[i], points[j])) {
        best = j;
        break;
      }
    }
    out.push_back(points[best]);
    i = best;
  }
  return out;
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
  solve.stop = deadline.stop;
  out.history.clear();
  out.iterations = 0;
  // A coarse mesh first for a wiggly candidate (one whose shortcut guess is in use): it is
  // straightened there at a fraction of the cost, and the fine mesh starts from a smooth guess.
  // A near-optimal candidate goes straight to the fine mesh: at 1 m intervals the clearance
  // held only at the points let a TAEASL route settle 2 % longer, round an unframed obstacle.
  ocp::TranscriptionGuess start = guess;
  const int coarse_intervals = std::clamp(
      static_cast<int>(std::ceil(length / options_.coarse_interval_length_m)),
      std::min(options_.min_intervals, transcription.intervals), transcription.intervals);
  if (out.guess_shortcut_m > 0.0 && coarse_intervals < transcription.intervals / 2) {
    ocp::DirectTranscriptionOptions coarse = transcription;
    coarse.intervals = coarse_intervals;
    if (deadline.limit_s) coarse.time_limit_s = deadline.secondsLeft();
    const ocp::TranscriptionSolution solution = ocp::solveDirectTranscription(
        *problem_->vehicle,
        [&] {
          ocp::BoundaryValueProblem tightened = *bvp_;
          tightened.limits.v_max = std::max(tightened.limits.v_max * (1.0 - options_.speed_margin),
                                            std::max(bvp_->start.v, bvp_->goal.v));
          tightened.limits.omega_max =
              std::max(tightened.limits.omega_max * (1.0 - options_.speed_margin),
                       std::max(std::abs(bvp_->start.omega), std::abs(bvp_->goal.omega)));
          return tightened;
        }(),
        start, coarse);
    out.history = solution.result.history;
    out.iterations = solution.result.iterations;
    out.coarse_intervals = coarse_intervals;
    out.coarse_status = solution.result.status;
    if (solution.result.status == ocp::SolveStatus::kConverged) start = solution.asGuess();
  }
  if (deadline.limit_s) solve.time_limit_s = deadline.secondsLeft();
  ocp::VerifiedTranscription result =
      ocp::solveTranscription(*problem_->vehicle, *bvp_, start, solve);
  for (ocp::IterationRecord r : result.history) {
    r.iteration += out.iterations;
    out.history.push_back(r);
  }
  out.iterations += result.iterations;
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

}  // namespace terratraj::search
