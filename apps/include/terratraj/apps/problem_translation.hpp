#pragma once
// The one translation layer from a validated problem file (ProblemSpec) and its loaded scene
// (ProblemScene: terrain, vehicle, tables, start and goal in the local frame) to each module's
// inputs: the boundary-value problem with its tables and the solver settings (ocp), the
// seeded solve (refine), the planning problem, the lattice and TAEASL settings and the
// reference frames (search), the refinement settings (refine). Every command reads: load,
// translate here, run, report. Functions that validate throw InputError naming the file and key.

#include <atomic>
#include <optional>
#include <string>

#include "terratraj/apps/problem_spec.hpp"
#include "terratraj/ocp/boundary_value_problem.hpp"
#include "terratraj/ocp/boundary_value_solver.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/refine/refinement_options.hpp"
#include "terratraj/refine/seeded_solver.hpp"
#include "terratraj/search/lattice_planner.hpp"
#include "terratraj/search/planning_problem.hpp"
#include "terratraj/search/reference_frames.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/terrain/clearance_map.hpp"

namespace terratraj::apps {

class ProblemScene;

/// The parametric problem: the scene's start and goal (local frame), the cost, the control
/// orders, the limits and the scene's tables (which must outlive the problem).
ocp::BoundaryValueProblem boundaryValueProblem(const ProblemSpec& problem,
                                               const ProblemScene& scene);

/// The parametric solver's settings (tolerances, iterations, time limit); a transcription
/// method gets newton's, from which direct transcription may start.
ocp::BoundaryValueOptions boundaryValueOptions(const ProblemSpec& problem);

/// Whether a method is direct transcription (auto, shooting, collocation).
bool isTranscriptionMethod(SolverMethod method);

/// The direct-transcription settings (scheme, controls, Hessian, iterations, mesh refinement,
/// the Segway's constraints); the clearance constraint is attached by the caller. Throws
/// InputError ("<file>: solver: ...") for settings the transcription refuses.
ocp::DirectTranscriptionOptions transcriptionOptions(const ProblemSpec& problem);

/// The seeded solve's settings (`terratraj solve`): method, initial guess, the parametric and
/// transcription settings, the clearance constraint on `clearance` (solver.min_clearance_m;
/// null without), the search seed, the time limit and the outside stop flag.
refine::SeededSolveOptions seededSolveOptions(const ProblemSpec& problem,
                                              const terrain::ClearanceMap* clearance,
                                              const std::atomic<bool>* stop);

/// The planners' query: map, vehicle, limits, tables, the scene's start (the planners cannot
/// turn in place: InputError for v = 0 with omega != 0) and the goal region; InputError naming
/// the key when it is invalid.
search::PlanningProblem planningProblem(const ProblemSpec& problem, const ProblemScene& scene);

/// The lattice spacing of the lattice planners [m]: planner.lattice_resolution_m, else the
/// multiple of the map cell nearest 0.5 m (at least one cell).
double latticeResolution(const ProblemSpec& problem, const terrain::GridGeometry& geometry);

/// The planners' default wall-clock budget [s] (`plan` without planner.time_limit_s).
inline constexpr double kDefaultPlanningTimeS = 1.0;

/// `plan`'s wall-clock budget [s]: planner.time_limit_s, else kDefaultPlanningTimeS.
double planningTimeLimit(const ProblemSpec& problem);

/// `solve`'s search-seed budget before any time is spent [s]: refine::searchSeedBudget of the
/// options seededSolveOptions() gives (planner.time_limit_s, else refine::kDefaultSearchTimeS).
double searchSeedTime(const ProblemSpec& problem);

/// The goal region's radius [m]: planner.goal_position_tolerance_m; absent, 0.5 m, and for the
/// lattice planners at least the distance within which every goal has a lattice position
/// (spacing / sqrt 2, rounded up to the centimetre: 2.13 m on a 3 m DEM's lattice), so the
/// defaults plan on a coarse map.
double goalPositionTolerance(const ProblemSpec& problem, const terrain::GridGeometry& geometry);

/// A* / ARA* settings (planner.algorithm, initial_epsilon, epsilon_step).
search::LatticePlannerOptions latticePlannerOptions(const ProblemSpec& problem);

/// TAEASL's settings (planner.homotopy_classes, frame_radius_m, frame_anchor,
/// heuristic_weight, max_signature_length).
search::TaeaslOptions taeaslOptions(const ProblemSpec& problem);

/// The reference frames a problem's homotopy classes are named by (search::taeaslReferenceFrames
/// with planner.frame_anchor and planner.frame_radius_m): built once per run and handed to
/// TAEASL and to the refiner, so that `plan` and `refine` name the same classes.
search::ReferenceFrames problemReferenceFrames(const ProblemSpec& problem,
                                               const search::PlanningProblem& query);

/// The refinement settings: the `refine` section, the solver's terminal tolerances, scheme and
/// Hessian; `method` (a RefineMethod name, from --method) overrides refine.method. Throws
/// InputError naming the option for an unknown method or invalid settings.
refine::RefinementOptions refinementOptions(const ProblemSpec& problem,
                                            const std::optional<std::string>& method);

}  // namespace terratraj::apps
