#include "terratraj/apps/problem_translation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "message_number.hpp"
#include "terratraj/apps/problem_scene.hpp"
#include "terratraj/models/segway_lookups.hpp"
#include "terratraj/refine/search_seed.hpp"
#include "terratraj/terrain/input_error.hpp"

namespace terratraj::apps {
namespace {

ocp::VehicleState toState(const BoundaryState& s) { return {s.x, s.y, s.heading, s.v, s.omega}; }

std::optional<ocp::BoundaryValueMethod> parametricMethod(SolverMethod method) {
  switch (method) {
    case SolverMethod::kNewton:
      return ocp::BoundaryValueMethod::kNewton;
    case SolverMethod::kNewtonFd:
      return ocp::BoundaryValueMethod::kNewtonFd;
    case SolverMethod::kIpopt:
      return ocp::BoundaryValueMethod::kIpopt;
    case SolverMethod::kCeres:
      return ocp::BoundaryValueMethod::kCeres;
    case SolverMethod::kAuto:
    case SolverMethod::kShooting:
    case SolverMethod::kCollocation:
      return std::nullopt;
  }
  return std::nullopt;
}

refine::CoreMethod coreMethod(SolverMethod method) {
  switch (method) {
    case SolverMethod::kAuto:
      return refine::CoreMethod::kAuto;
    case SolverMethod::kNewton:
      return refine::CoreMethod::kNewton;
    case SolverMethod::kNewtonFd:
      return refine::CoreMethod::kNewtonFd;
    case SolverMethod::kIpopt:
      return refine::CoreMethod::kIpopt;
    case SolverMethod::kCeres:
      return refine::CoreMethod::kCeres;
    case SolverMethod::kShooting:
      return refine::CoreMethod::kShooting;
    case SolverMethod::kCollocation:
      return refine::CoreMethod::kCollocation;
  }
  return refine::CoreMethod::kAuto;
}

// The planner's view of the problem file's start and goal.
search::PlannerState startState(const ProblemSpec& problem, const BoundaryState& s) {
  if (s.v == 0.0 && s.omega != 0.0) {
    throw InputError(problem.source_file.string() +
                     ": start.omega: the planners cannot turn in place: omega must be 0 when "
                     "v = 0 (got " +
                     formatNumber(s.omega) + " rad/s)");
  }
  search::PlannerState state;
  state.position = {s.x, s.y};
  state.heading = s.heading;
  state.v = s.v;
  state.curvature = s.v > 0.0 ? s.omega / s.v : 0.0;
  return state;
}

search::GoalRegion goalRegion(const ProblemSpec& problem, const BoundaryState& g,
                              const terrain::GridGeometry& geometry) {
  search::GoalRegion goal;
  goal.position = {g.x, g.y};
  goal.heading = g.heading;
  goal.v = g.v;
  goal.position_tolerance = goalPositionTolerance(problem, geometry);
  goal.heading_tolerance = problem.planner.goal_heading_tolerance;
  goal.speed_tolerance = problem.planner.goal_speed_tolerance;
  return goal;
}

}  // namespace

ocp::BoundaryValueProblem boundaryValueProblem(const ProblemSpec& problem,
                                               const ProblemScene& scene) {
  ocp::BoundaryValueProblem bvp;
  bvp.start = toState(scene.start());
  bvp.goal = toState(scene.goal());
  bvp.cost.kind = problem.cost.kind == CostKind::kSlopeDwell ? ocp::CostKind::kSlopeDwell
                                                             : ocp::CostKind::kTime;
  bvp.cost.alpha = problem.cost.alpha;
  bvp.orders = {problem.solver.yaw_rate_order, problem.solver.speed_order};
  bvp.limits = problem.vehicle.limits;
  bvp.tables = {scene.pitchTable(), scene.rollCurvatureTable(), scene.segwayLookups()};
  return bvp;
}

ocp::BoundaryValueOptions boundaryValueOptions(const ProblemSpec& problem) {
  ocp::BoundaryValueOptions options;
  // Direct transcription starts from the parametric solution: newton's settings then.
  options.method =
      parametricMethod(problem.solver.method).value_or(ocp::BoundaryValueMethod::kNewton);
  options.criteria = {problem.solver.tolerance_position_m, problem.solver.tolerance_heading_rad,
                      problem.solver.tolerance_lagrangian_gradient};
  options.max_iterations = problem.solver.max_iterations;
  options.time_limit_s = problem.solver.time_limit_s;
  return options;
}

bool isTranscriptionMethod(SolverMethod method) {
  return method == SolverMethod::kAuto || method == SolverMethod::kShooting ||
         method == SolverMethod::kCollocation;
}

ocp::DirectTranscriptionOptions transcriptionOptions(const ProblemSpec& problem) {
  const SolverSpec& solver = problem.solver;
  ocp::DirectTranscriptionOptions options;
  options.scheme = solver.method == SolverMethod::kShooting
                       ? ocp::TranscriptionScheme::kMultipleShooting
                       : solver.scheme;
  options.shooting_controls = solver.shooting_controls;
  options.hessian = solver.hessian;
  options.intervals = solver.intervals.value_or(0);  // 0: by the seed's length (solveSeeded)
  // Piecewise-linear controls on Hermite-Simpson intervals: |v'| <= a_max and |omega'| hold
  // between the points too (the quadratic interpolation of a bang-bang control overshoots).
  options.linear_controls = true;
  options.max_iterations = solver.transcription_max_iterations.value_or(5 * solver.max_iterations);
  options.time_limit_s = solver.time_limit_s;
  options.refinement.max_rounds = solver.mesh_refinement_rounds;
  options.refinement.tolerance = solver.mesh_refinement_tolerance;
  options.model.control_effort_weight = solver.control_effort;
  if (problem.vehicle.model == VehicleModelKind::kSegwayRmp) {
    options.model.segway = ocp::SegwayConstraints{models::defaultSegwayLookups()};
  }
  ocp::DirectTranscriptionOptions checked = options;
  checked.intervals = std::max(checked.intervals, 1);  // 0 (auto) is resolved per seed
  if (std::optional<std::string> why = ocp::validateTranscriptionOptions(checked)) {
    throw InputError(problem.source_file.string() + ": solver: " + *why);
  }
  return options;
}

refine::SeededSolveOptions seededSolveOptions(const ProblemSpec& problem,
                                              const terrain::ClearanceMap* clearance,
                                              const std::atomic<bool>* stop) {
  refine::SeededSolveOptions seeded;
  seeded.method = coreMethod(problem.solver.method);
  seeded.initial_guess = problem.solver.initial_guess == InitialGuessKind::kFlat
                             ? refine::InitialGuessKind::kFlat
                             : refine::InitialGuessKind::kAuto;
  seeded.parametric = boundaryValueOptions(problem);
  if (isTranscriptionMethod(problem.solver.method)) {
    seeded.transcription.transcription = transcriptionOptions(problem);
    seeded.transcription.max_intervals =
        std::max(problem.solver.max_intervals, problem.solver.intervals.value_or(0));
    if (clearance != nullptr && problem.solver.min_clearance_m) {
      seeded.transcription.transcription.model.clearance = {clearance,
                                                            *problem.solver.min_clearance_m};
    }
  }
  seeded.ipopt_max_iterations = problem.solver.ipopt_max_iterations;
  seeded.search_seed = problem.planner.seed;
  // The PRM stops at its first solution; absent, refine::kDefaultSearchTimeS.
  seeded.search_time_s = problem.planner.time_limit_s;
  seeded.time_limit_s = problem.solver.time_limit_s;
  if (problem.solver.seed_time_s) seeded.seed_time_s = *problem.solver.seed_time_s;
  if (problem.solver.first_seed_time_s) {
    seeded.first_seed_time_s = *problem.solver.first_seed_time_s;
  }
  if (problem.solver.search_improve_milestones) {
    seeded.search_improve_milestones =
        static_cast<std::size_t>(*problem.solver.search_improve_milestones);
  }
  if (problem.solver.search_improvements) {
    seeded.search_improvements = *problem.solver.search_improvements;
  }
  seeded.stop = stop;
  return seeded;
}

search::PlanningProblem planningProblem(const ProblemSpec& problem, const ProblemScene& scene) {
  search::PlanningProblem query(scene.map(), scene.vehicle());
  query.limits = problem.vehicle.limits;
  query.start = startState(problem, scene.start());
  query.goal = goalRegion(problem, scene.goal(), scene.map().geometry());
  query.pitch_table = scene.searchPitchTable();
  query.roll_curvature_table = scene.rollCurvatureTable();
  if (const std::optional<std::string> error = query.validate()) {
    throw InputError(problem.source_file.string() + ": " + *error);
  }
  return query;
}

double latticeResolution(const ProblemSpec& problem, const terrain::GridGeometry& geometry) {
  if (problem.planner.lattice_resolution_m) return *problem.planner.lattice_resolution_m;
  return geometry.cell * std::max(1.0, std::round(0.5 / geometry.cell));
}

double planningTimeLimit(const ProblemSpec& problem) {
  return problem.planner.time_limit_s.value_or(kDefaultPlanningTimeS);
}

double searchSeedTime(const ProblemSpec& problem) {
  refine::SeededSolveOptions options;
  options.search_time_s = problem.planner.time_limit_s;
  return refine::searchSeedBudget(options, std::nullopt);
}

double goalPositionTolerance(const ProblemSpec& problem, const terrain::GridGeometry& geometry) {
  if (problem.planner.goal_position_tolerance_m) return *problem.planner.goal_position_tolerance_m;
  if (problem.planner.kind == PlannerKind::kPrm) return search::kDefaultGoalPositionTolerance;
  const double holding =
      std::ceil(latticeResolution(problem, geometry) * std::sqrt(0.5) * 100.0) / 100.0;
  return std::max(search::kDefaultGoalPositionTolerance, holding);
}

search::LatticePlannerOptions latticePlannerOptions(const ProblemSpec& problem) {
  search::LatticePlannerOptions options;
  options.algorithm = problem.planner.algorithm;
  options.initial_epsilon = problem.planner.initial_epsilon;
  options.epsilon_step = problem.planner.epsilon_step;
  return options;
}

search::TaeaslOptions taeaslOptions(const ProblemSpec& problem) {
  search::TaeaslOptions options;
  options.homotopy_classes = problem.planner.homotopy_classes;
  options.frame_radius = problem.planner.frame_radius_m;
  options.anchor = problem.planner.frame_anchor;
  options.heuristic_weight = problem.planner.heuristic_weight;
  if (problem.planner.max_signature_length) {
    options.max_signature_length = *problem.planner.max_signature_length;
  }
  return options;
}

search::ReferenceFrames problemReferenceFrames(const ProblemSpec& problem,
                                               const search::PlanningProblem& query) {
  return search::taeaslReferenceFrames(query, problem.planner.frame_anchor,
                                       problem.planner.frame_radius_m);
}

refine::RefinementOptions refinementOptions(const ProblemSpec& problem,
                                            const std::optional<std::string>& method) {
  const RefineSpec& spec = problem.refine;
  refine::RefinementOptions options;
  options.method = spec.method;  // validated by the loader
  if (method) {
    const std::optional<refine::RefineMethod> parsed = refine::parseRefineMethod(*method);
    if (!parsed) {
      throw InputError("--method: unknown method '" + *method +
                       "' (auto, collocation, shooting, newton, ipopt)");
    }
    options.method = *parsed;
  }
  options.interval_length_m = spec.interval_length_m;
  options.min_intervals = spec.min_intervals;
  options.max_intervals = spec.max_intervals;
  options.min_clearance_m = spec.min_clearance_m;
  options.parametric_max_length_m = spec.parametric_max_length_m;
  options.parametric_min_clearance_m = spec.parametric_min_clearance_m;
  // The solver section's transcription settings (scheme, Hessian, effort, mesh refinement),
  // with refine's own iteration and time limits.
  ProblemSpec collocation = problem;
  collocation.solver.method = SolverMethod::kCollocation;
  options.transcription = transcriptionOptions(collocation);
  options.transcription.intervals = options.min_intervals;  // set per candidate by its length
  options.transcription.max_iterations = spec.max_iterations;
  options.transcription.linear_controls = true;
  options.limit_margin = spec.limit_margin;
  options.speed_margin = spec.speed_margin;
  options.transcription.model.control_effort_weight = spec.control_effort;
  options.coarse_interval_length_m = spec.coarse_interval_length_m;
  options.endpoint_tolerance_m = spec.endpoint_tolerance_m;
  options.warm_start_time_ratio = spec.warm_start_time_ratio;
  options.time_limit_s = spec.time_limit_s;  // the whole refinement: solves get what is left
  options.parametric = boundaryValueOptions(problem);  // its method is set per refinement
  if (std::optional<std::string> why = refine::validateRefinementOptions(options)) {
    throw InputError(problem.source_file.string() + ": refine: " + *why);
  }
  return options;
}

}  // namespace terratraj::apps
