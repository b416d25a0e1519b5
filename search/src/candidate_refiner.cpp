#include "terratraj/search/candidate_refiner.hpp"

#include <algorithm>
#include <array>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include "terratraj/ocp/transcription_guess.hpp"
#include "terratraj/ocp/transcription_model.hpp"

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
      return "sample " + std::to_string(i) + ": x, y is not a finite number";
    }
    if (!geometry.contains({s.x, s.y})) {
      return "sample " + std::to_string(i) + " at " + formatPoint(s.x, s.y) +
             " leaves the map (0..." + formatNumber(geometry.width()) + " x 0..." +
             formatNumber(geometry.height()) + " m, local frame)";
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
      why = "sample " + std::to_string(i) + " at " + formatPoint(s.x, s.y) +
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

// Speeds below this are rest [m/s]: their curvature omega / v is rounding noise.
constexpr double kRestSpeed = 1e-9;

// The integrator leaves the curvature of a sample at rest (v = 0) undefined (NaN), or computes
// it from rounding noise; a refined trajectory at rest gets v = omega = 0 and the curvature of
// its nearest sample in motion (0 when none moves), so that every column is a number.
void fillCurvatureAtRest(models::Trajectory& trajectory) {
  std::vector<models::TrajectorySample>& s = trajectory.samples;
  for (models::TrajectorySample& sample : s) {
    if (std::abs(sample.v) < kRestSpeed && std::abs(sample.omega) < kRestSpeed) {
      sample.v = sample.omega = 0.0;
      sample.curvature = std::numeric_limits<double>::quiet_NaN();
    }
  }
  for (std::size_t i = 0; i < s.size(); ++i) {
    if (std::isfinite(s[i].curvature)) continue;
    double value = 0.0;
    for (std::size_t d = 1; d < s.size(); ++d) {
      if (i >= d && std::isfinite(s[i - d].curvature)) {
        value = s[i - d].curvature;
        break;
      }
      if (i + d < s.size() && std::isfinite(s[i + d].curvature)) {
        value = s[i + d].curvature;
        break;
      }
    }
    s[i].curvature = value;
  }
}

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
      clearance_(*problem.map) {}

TrajectoryFigures CandidateRefiner::measure(const models::Trajectory& trajectory,
                                            const CheckTolerances& tolerances) const {
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
  f.check = TrajectoryChecker(*problem_, tolerances).check(trajectory, true);
  f.homotopy = frames_->signatureOf(polyline(trajectory)).toString();
  return f;
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
  if (std::optional<std::string> why = candidateError(candidate, problem_->map->geometry())) {
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
  out.candidate_figures = measure(out.candidate, CheckTolerances{});
  const TrajectoryFigures& before = *out.candidate_figures;

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

  // 3. Solve; with kAuto, a failed parametric solve falls back to collocation.
  const auto accept = [&](ocp::SolveStatus status, std::string reason) {
    out.status = status;
    out.reason = std::move(reason);
    if (!out.verified.ok) return;
    if (!out.refined_figures) {  // transcribe() measures what it accepts
      fillCurvatureAtRest(out.verified.trajectory);
      out.refined_figures = measure(out.verified.trajectory, options_.check);
    }
    const TrajectoryFigures& after = *out.refined_figures;
    out.homotopy_kept = after.homotopy == before.homotopy;
    if (out.status != ocp::SolveStatus::kConverged) return;
    if (!after.check.ok()) {
      out.status = ocp::SolveStatus::kInfeasible;
      out.reason = "the independent re-check of the refined trajectory: " + after.check.summary();
    } else if (!out.homotopy_kept) {
      out.status = ocp::SolveStatus::kInfeasible;
      out.reason = "the refined trajectory left the candidate's homotopy class ('" +
                   before.homotopy + "' -> '" + after.homotopy + "')";
    }
  };

  if (out.method == RefineMethod::kNewton || out.method == RefineMethod::kIpopt) {
    // A linear speed polynomial cannot leave and return to rest: a cubic can.
    ocp::BoundaryValueProblem parametric = *bvp_;
    if (parametric.start.v == 0.0 && parametric.goal.v == 0.0 && parametric.orders.speed < 3) {
      parametric.orders.speed = 3;
    }
    ocp::BoundaryValueOptions settings = options_.parametric;
    settings.method = out.method == RefineMethod::kNewton ? ocp::BoundaryValueMethod::kNewton
                                                          : ocp::BoundaryValueMethod::kIpopt;
    out.parametric =
        ocp::solveBoundaryValue(*problem_->vehicle, parametric, settings, problem_->map);
    out.verified = out.parametric->verified;
    out.history = out.parametric->solver.history;
    out.iterations = out.parametric->solver.iterations;
    accept(out.parametric->status, out.parametric->reason);
    if (out.status == ocp::SolveStatus::kConverged || options_.method != RefineMethod::kAuto) {
      return finish(out.status, out.reason);
    }
    out.method_rule += "; ipopt ended " + std::string(ocp::solveStatusName(out.status)) + " (" +
                       out.reason + "), so collocation";
    out.method = RefineMethod::kCollocation;
    out.refined_figures.reset();
    out.parametric.reset();
  }

  transcribe(*guess, before, clearance_, out);
  accept(out.status, out.reason);
  // Interior-point iterates may pass through a small obstacle: once the class is lost, solve
  // again from the candidate inside a corridor around it, which the clearance constraint keeps.
  if (out.refined_figures && !out.homotopy_kept && options_.corridor_radius_m > 0.0) {
    const terrain::ClearanceMap corridor(corridorMap(out.candidate));
    out.corridor_radius_m = options_.corridor_radius_m;
    out.refined_figures.reset();
    transcribe(candidate_guess, before, corridor, out);
    accept(out.status, out.reason);
  }
  return finish(out.status, out.reason);
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
                                  const terrain::ClearanceMap& clearance,
                                  RefinementResult& out) const {
  ocp::DirectTranscriptionOptions transcription = options_.transcription;
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
  const bool has_obstacles = clearance_.hasImpassableCells();
  // A trajectory that clips a lethal cell between its points is solved again with at least half
  // a cell of clearance (capped by min_clearance_m): the bilinear distance transform rounds a
  // lethal cell's corners.
  const double clearance_floor =
      std::min(options_.min_clearance_m, 0.5 * problem_->map->geometry().cell);
  if (has_obstacles) {
    out.clearance_used_m =
        std::max(0.0, std::min(options_.min_clearance_m, 0.5 * before.min_clearance_m));
    transcription.model.clearance = {&clearance, out.clearance_used_m};
  }
  // Verified against the true limits, and against lethal cells only (clearance >= 0) rather
  // than the clearance the solver kept.
  ocp::TranscriptionModelOptions verification = transcription.model;
  verification.clearance.min_clearance = 0.0;
  const ocp::TranscriptionModel model(*problem_->vehicle, *bvp_, verification);
  const ocp::ConvergenceCriteria& criteria = options_.parametric.criteria;

  // Solved with the limits tightened by the margins; a solution whose re-simulation still
  // breaks a limit between the points is solved again from itself, with twice the intervals,
  // then with wider margins.
  double speed_margin = options_.speed_margin, limit_margin = options_.limit_margin;
  const auto tighten = [&]() {
    ocp::BoundaryValueProblem tightened = *bvp_;
    tightened.limits.v_max *= 1.0 - speed_margin;
    tightened.limits.omega_max *= 1.0 - speed_margin;
    for (double* limit : {&tightened.limits.kappa_max, &tightened.limits.sigma_max,
                          &tightened.limits.pitch_max, &tightened.limits.roll_max}) {
      *limit *= 1.0 - limit_margin;
    }
    return tightened;
  };
  const auto record = [&](const ocp::TranscriptionSolution& solution) {
    for (ocp::IterationRecord r : solution.result.history) {
      r.iteration += out.iterations;
      out.history.push_back(r);
    }
    out.iterations += solution.result.iterations;
  };
  ocp::TranscriptionGuess start = guess;
  out.history.clear();
  // A coarse mesh first for a wiggly candidate (one whose shortcut guess is in use): it is
  // straightened there at a fraction of the cost, and the fine mesh starts from a smooth guess.
  // A near-optimal candidate goes straight to the fine mesh: at 1 m intervals the clearance
  // held only at the points let a TAEASL route settle 2 % longer, round an unframed obstacle.
  const int coarse_intervals = std::clamp(
      static_cast<int>(std::ceil(length / options_.coarse_interval_length_m)),
      std::min(options_.min_intervals, transcription.intervals), transcription.intervals);
  if (out.guess_shortcut_m > 0.0 && coarse_intervals < transcription.intervals / 2) {
    ocp::DirectTranscriptionOptions coarse = transcription;
    coarse.intervals = coarse_intervals;
    const ocp::TranscriptionSolution solution =
        ocp::solveDirectTranscription(*problem_->vehicle, tighten(), start, coarse);
    record(solution);
    out.coarse_intervals = coarse_intervals;
    out.coarse_status = solution.result.status;
    if (solution.result.status == ocp::SolveStatus::kConverged) start = solution.asGuess();
  }
  bool doubled = false;
  for (int round = 0; round <= options_.margin_retries; ++round) {
    out.refined_figures.reset();  // each round's solution is measured anew
    const ocp::BoundaryValueProblem tightened = tighten();
    out.speed_margin_used = speed_margin;
    out.limit_margin_used = limit_margin;
    out.margin_rounds = round + 1;
    out.transcription =
        ocp::solveDirectTranscription(*problem_->vehicle, tightened, start, transcription);
    const ocp::TranscriptionSolution& solution = *out.transcription;
    out.intervals = static_cast<int>(solution.mesh.size()) - 1;
    record(solution);
    out.verified = solution.points.empty()
                       ? ocp::VerifiedTrajectory{}
                       : ocp::verifyTranscriptionSolution(model, solution, problem_->map);
    out.status = solution.result.status;
    out.reason = solution.result.reason;
    if (out.status != ocp::SolveStatus::kConverged) return;
    const double position = out.verified.terminal_error.head<2>().norm();
    const double heading = std::abs(out.verified.terminal_error.z());
    if (!out.verified.ok) {
      out.status = ocp::SolveStatus::kDiverged;
      out.reason = "the re-simulation failed: " + out.verified.message;
      return;
    }
    if (position > criteria.position_m || heading > criteria.heading_rad) {
      out.status = ocp::SolveStatus::kDiverged;
      out.reason = "the re-simulated trajectory ends " + formatNumber(position) + " m, " +
                   formatNumber(heading) + " rad from the goal (tolerance " +
                   formatNumber(criteria.position_m) + " m, " + formatNumber(criteria.heading_rad) +
                   " rad): shorten refine.interval_length_m";
      return;
    }
    // The independent checker too (it reads the curvature column, where the solver's
    // |omega| <= kappa_max v is loosest: near rest).
    std::string limit = out.verified.violation.limit;
    if (out.verified.violation.amount <= options_.parametric.limit_tolerance) {
      fillCurvatureAtRest(out.verified.trajectory);
      out.refined_figures = measure(out.verified.trajectory, options_.check);
      const CheckReport& check = out.refined_figures->check;
      if (check.ok()) return;
      limit = check.violations.front().limit;
      out.status = ocp::SolveStatus::kInfeasible;
      out.reason = "the independent re-check of the refined trajectory: " + check.summary();
    } else {
      out.status = ocp::SolveStatus::kInfeasible;
      out.reason = "the re-simulated trajectory breaks " + limit + " by " +
                   formatNumber(out.verified.violation.amount) + " between the points (margins " +
                   formatNumber(speed_margin) + ", " + formatNumber(limit_margin) + ")";
    }
    start = solution.asGuess();
    // A clipped lethal cell: more clearance. Otherwise the overshoot between points shrinks
    // with the interval: first twice the intervals, then wider margins (which cost time).
    if (has_obstacles && (limit == "lethal" || limit == "clearance") &&
        out.clearance_used_m < clearance_floor) {
      out.clearance_used_m = clearance_floor;
      transcription.model.clearance.min_clearance = clearance_floor;
    } else if (!doubled && 2 * transcription.intervals <= options_.max_intervals) {
      transcription.intervals *= 2;
      doubled = true;
    } else {
      speed_margin = std::min(0.25, 4.0 * speed_margin);
      limit_margin = std::min(0.25, 2.0 * limit_margin);
    }
  }
}

}  // namespace terratraj::search
