#pragma once
// ProblemSpec: the whole problem file (the "Problem file (YAML)" section of the user-facing
// contract, docs/problem-file.md) as plain values. SI units throughout; angles in radians.
//
// Filled by loadProblem() / parseProblem() (problem_loader.hpp), which validate every value;
// the defaults below are the ones a key takes when the file omits it.

#include <array>
#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "terratraj/models/vehicle_factory.hpp"
#include "terratraj/models/vehicle_limits.hpp"
#include "terratraj/ocp/direct_transcription.hpp"
#include "terratraj/refine/refinement_options.hpp"
#include "terratraj/search/lattice_planner.hpp"
#include "terratraj/search/taeasl_planner.hpp"
#include "terratraj/terrain/terrain_source.hpp"

namespace terratraj::apps {

// ---------------------------------------------------------------------------------------------
// Enumerations and their names.

// Vehicle models (point | four_wheel | rocker_bogie | segway_rmp): models/vehicle_factory.hpp.
using models::parseVehicleModelKind;
using models::VehicleModelKind;
using models::vehicleModelName;
using models::vehicleModelNames;

/// Costs, named in YAML as time | slope_dwell.
enum class CostKind {
  kTime,        ///< J = final time
  kSlopeDwell,  ///< J = integral of 1 + alpha * (roll^2 + pitch^2) dt
};

/// Boundary-value solvers, named in YAML as newton | newton_fd | ipopt | ceres | shooting |
/// collocation.
enum class SolverMethod { kAuto, kNewton, kNewtonFd, kIpopt, kCeres, kShooting, kCollocation };

/// Where the solvers start, named in YAML as auto | flat.
enum class InitialGuessKind { kAuto, kFlat };

/// Planners, named in YAML as prm | lattice | taeasl.
enum class PlannerKind { kPrm, kLattice, kTaeasl };

namespace detail {

/// One entry of an enum <-> name table.
template <typename Enum>
struct EnumName {
  Enum value;
  const char* name;
};

template <typename Enum, std::size_t N>
std::optional<Enum> parseEnumName(const std::array<EnumName<Enum>, N>& table,
                                  std::string_view name) {
  for (const auto& entry : table) {
    if (name == entry.name) return entry.value;
  }
  return std::nullopt;
}

template <typename Enum, std::size_t N>
const char* enumName(const std::array<EnumName<Enum>, N>& table, Enum value) {
  for (const auto& entry : table) {
    if (entry.value == value) return entry.name;
  }
  return "unknown";
}

template <typename Enum, std::size_t N>
std::vector<std::string> enumNames(const std::array<EnumName<Enum>, N>& table) {
  std::vector<std::string> names;
  names.reserve(N);
  for (const auto& entry : table) names.emplace_back(entry.name);
  return names;
}

inline constexpr std::array<EnumName<CostKind>, 2> kCostKindNames{{
    {CostKind::kTime, "time"},
    {CostKind::kSlopeDwell, "slope_dwell"},
}};
inline constexpr std::array<EnumName<SolverMethod>, 7> kSolverMethodNames{{
    {SolverMethod::kAuto, "auto"},
    {SolverMethod::kNewton, "newton"},
    {SolverMethod::kNewtonFd, "newton_fd"},
    {SolverMethod::kIpopt, "ipopt"},
    {SolverMethod::kCeres, "ceres"},
    {SolverMethod::kShooting, "shooting"},
    {SolverMethod::kCollocation, "collocation"},
}};
inline constexpr std::array<EnumName<PlannerKind>, 3> kPlannerKindNames{{
    {PlannerKind::kPrm, "prm"},
    {PlannerKind::kLattice, "lattice"},
    {PlannerKind::kTaeasl, "taeasl"},
}};

}  // namespace detail

/// Parses a cost name ("time", "slope_dwell"); std::nullopt if it is not one.
inline std::optional<CostKind> parseCostKind(std::string_view name) {
  return detail::parseEnumName(detail::kCostKindNames, name);
}
/// The YAML name of a cost.
inline const char* costKindName(CostKind kind) {
  return detail::enumName(detail::kCostKindNames, kind);
}
/// Every cost name, in declaration order.
inline std::vector<std::string> costKindNames() {
  return detail::enumNames(detail::kCostKindNames);
}

/// Parses a solver method name ("newton", ...); std::nullopt if it is not one.
inline std::optional<SolverMethod> parseSolverMethod(std::string_view name) {
  return detail::parseEnumName(detail::kSolverMethodNames, name);
}
/// The YAML name of a solver method.
inline const char* solverMethodName(SolverMethod method) {
  return detail::enumName(detail::kSolverMethodNames, method);
}
/// Every solver method name, in declaration order.
inline std::vector<std::string> solverMethodNames() {
  return detail::enumNames(detail::kSolverMethodNames);
}

/// Parses a planner name ("prm", "lattice", "taeasl"); std::nullopt if it is not one.
inline std::optional<PlannerKind> parsePlannerKind(std::string_view name) {
  return detail::parseEnumName(detail::kPlannerKindNames, name);
}
/// The YAML name of a planner.
inline const char* plannerKindName(PlannerKind kind) {
  return detail::enumName(detail::kPlannerKindNames, kind);
}
/// Every planner name, in declaration order.
inline std::vector<std::string> plannerKindNames() {
  return detail::enumNames(detail::kPlannerKindNames);
}

// ---------------------------------------------------------------------------------------------
// Sections of the problem file.

/// Degrees -> radians factor.
using models::kRadiansPerDegree;

/// `vehicle.limits`: bounds the trajectory must respect. All > 0.
using models::VehicleLimits;

/// `vehicle.tables`: optional kinodynamic look-up tables (JSON files; relative paths are
/// resolved against the problem file's folder by the loader).
struct VehicleTables {
  std::optional<std::filesystem::path> pitch;           ///< v_max [m/s] by pitch bin
  std::optional<std::filesystem::path> roll_curvature;  ///< v_max [m/s] by roll x curvature bin
};

/// `vehicle`: the model and its limits.
struct VehicleSpec {
  VehicleModelKind model = VehicleModelKind::kPoint;
  VehicleLimits limits;
  VehicleTables tables;
};

/// `start` / `goal`: a boundary state of the trajectory, in the frame given by
/// ProblemSpec::pose_frame.
struct BoundaryState {
  double x = 0.0;        ///< [m]
  double y = 0.0;        ///< [m]
  double heading = 0.0;  ///< yaw [rad], 0 along +x, counter-clockwise; wrapped to (-pi, pi]
  double v = 0.0;        ///< forward speed [m/s], in [0, v_max]
  double omega = 0.0;    ///< yaw rate [rad/s], |omega| <= omega_max
};

/// `cost`: what the optimiser minimises.
struct CostSpec {
  CostKind kind = CostKind::kTime;
  double alpha = 0.0;  ///< slope_dwell weight on roll^2 + pitch^2 [1/rad^2], >= 0
};

/// `solve`'s wall clock when the problem file gives no solver.time_limit_s [s]. The global
/// seeds' rounds double the budget of every seed they cut until one converges or the time
/// runs out, so without a limit a problem no seed converges on would never end.
inline constexpr double kDefaultSolveTimeLimitS = 300.0;

/// `solver`: the boundary-value solver and its stopping rules.
struct SolverSpec {
  SolverMethod method = SolverMethod::kAuto;  ///< auto: global seeds, collocation, best verified
  InitialGuessKind initial_guess = InitialGuessKind::kAuto;  ///< auto: global seeds; flat: 004's
  /// Shooting / collocation intervals, >= 2; absent: one per 0.25 m of the seed's length.
  std::optional<int> intervals;
  /// The verification rounds double the intervals up to this many, >= intervals.
  int max_intervals = 800;
  int max_iterations = 100;  ///< >= 1 (parametric solvers)
  /// Ipopt iterations of a shooting / collocation solve, >= 1; absent: 5 x max_iterations
  /// (an interior-point transcription takes more, cheaper iterations).
  std::optional<int> transcription_max_iterations;
  /// Iterations of the parametric ipopt, >= 1; absent: 3 x max_iterations (its limited-memory
  /// quasi-Newton iterations are more, and cheaper, than newton's).
  std::optional<int> ipopt_max_iterations;
  double tolerance_position_m = 0.001;         ///< terminal position error [m], > 0
  double tolerance_heading_rad = 0.001;        ///< terminal heading error [rad], > 0
  double tolerance_lagrangian_gradient = 0.1;  ///< |dJ/dq + lambda' dc/dq|_inf, > 0
  int yaw_rate_order = 4;  ///< parametric solvers: yaw-rate polynomial order, in [1, 8]
  int speed_order = 1;     ///< parametric solvers: speed polynomial order, in [1, 8]
  // Direct transcription (shooting / collocation); docs/problem-file.md.
  /// collocation: hermite_simpson | trapezoidal
  ocp::TranscriptionScheme scheme = ocp::TranscriptionScheme::kHermiteSimpson;
  /// shooting: linear | constant
  ocp::ShootingControls shooting_controls = ocp::ShootingControls::kPiecewiseLinear;
  /// exact | limited_memory; absent: auto (exact for collocation without the Segway)
  std::optional<ocp::TranscriptionHessian> hessian;
  double control_effort = 0.0;              ///< weight of the integral of v'^2 + omega'^2, >= 0
  int mesh_refinement_rounds = 0;           ///< re-solves with split intervals, >= 0
  double mesh_refinement_tolerance = 1e-3;  ///< local error that splits an interval [m, rad]
  std::optional<double> min_clearance_m;    ///< clearance from lethal cells [m]; absent = none
  /// Wall-clock limit of the whole solve [s], >= 0 (the solve report's `time_limit_s`). In
  /// `refine` and `plan --refine` it caps each solve of a refinement without refine.time_limit_s.
  std::optional<double> time_limit_s = kDefaultSolveTimeLimitS;
  /// auto seeds: each seed's first budget [s], > 0, doubled for the seeds it cut each round;
  /// absent: refine::kDefaultSeedTimeS
  std::optional<double> seed_time_s;
  /// auto seeds: the first seed's first budget [s], > 0; absent: refine::kDefaultFirstSeedTimeS
  std::optional<double> first_seed_time_s;
  /// The search seed: milestones the PRM continues for after a failed refinement of its route,
  /// >= 0; absent: refine::kDefaultSearchImproveMilestones
  std::optional<int> search_improve_milestones;
  /// The search seed: at most this many such continuations, >= 0; absent:
  /// refine::kDefaultSearchImprovements
  std::optional<int> search_improvements;
};

/// `planner`: the global planner.
struct PlannerSpec {
  PlannerKind kind = PlannerKind::kPrm;
  /// Wall-clock budget [s], >= 0. Absent: plan 1 s (planningTimeLimit()); the search seed of
  /// `solve` refine::kDefaultSearchTimeS (it stops at its first solution).
  std::optional<double> time_limit_s;
  /// Iteration budget (PRM milestones, lattice expansions), >= 1; absent: none. With it and a
  /// time limit that is not reached, the same seed gives the same files.
  std::optional<int> max_iterations;
  std::uint64_t seed = 1;        ///< random seed
  int homotopy_classes = 3;      ///< taeasl: most distinct classes returned, >= 1
  double frame_radius_m = 10.0;  ///< taeasl: frame radius [m], > 0
  /// Goal region radius [m], > 0; absent: goalPositionTolerance() (problem_translation.hpp).
  std::optional<double> goal_position_tolerance_m;
  double goal_heading_tolerance = 0.35;  ///< prm: goal heading tolerance [rad], > 0
  double goal_speed_tolerance = 0.1;     ///< prm: goal speed tolerance [m/s], > 0
  // Lattice planners (lattice, taeasl); docs/planning.md.
  /// Lattice spacing [m], > 0 (a multiple of the map cell is fastest); absent: the multiple of
  /// the cell nearest 0.5 m.
  std::optional<double> lattice_resolution_m;
  int heading_count = 16;                           ///< headings of the lattice, in [4, 1024]
  std::optional<std::filesystem::path> primitives;  ///< primitive file; absent: the cache
  std::optional<double> primitive_speed;            ///< generation speed [m/s]; absent: v_max
  search::LatticeAlgorithm algorithm = search::LatticeAlgorithm::kAraStar;  ///< lattice
  double initial_epsilon = 3.0;  ///< arastar: first heuristic weight, >= 1
  double epsilon_step = 0.5;     ///< arastar: decrease per round, > 0
  search::FrameAnchor frame_anchor = search::FrameAnchor::kMapCenter;  ///< taeasl
  double heuristic_weight = 1.0;            ///< taeasl: weight of the heuristic, >= 1
  std::optional<int> max_signature_length;  ///< taeasl: absent: 2 x frames + 2
};

/// `refine`: how `plan --refine` and `refine` turn candidates into locally optimal trajectories
/// (refine::CandidateRefiner; docs/refinement.md).
struct RefineSpec {
  refine::RefineMethod method = refine::RefineMethod::kAuto;  ///< refine::parseRefineMethod
  double interval_length_m = 0.25;  ///< one transcription interval per this much length [m], > 0
  int min_intervals = 20;           ///< fewest transcription intervals, >= 2
  int max_intervals = 800;          ///< most transcription intervals, >= min_intervals
  double min_clearance_m = 0.25;    ///< clearance from lethal / no-data cells [m], >= 0
  double limit_margin = 0.02;    ///< kappa, sigma, pitch, roll solved this much tighter, [0, 0.5)
  double speed_margin = 0.0005;  ///< v_max, omega_max solved this much tighter, [0, 0.5)
  /// Weight of the integral of v'^2 + omega'^2 [s^4/m^2], >= 0: damps the controls' ringing
  /// between points on arcs at v_max (where any alternating sequence takes the same time).
  double control_effort = 1e-4;
  int max_iterations = 500;            ///< Ipopt iterations per candidate, >= 1
  std::optional<double> time_limit_s;  ///< wall clock per candidate [s], >= 0; absent = none
  double parametric_max_length_m =
      10.0;  ///< auto: polynomial controls only up to this length [m], >= 0
  double parametric_min_clearance_m = 3.0;  ///< auto: ... and this far from obstacles [m], >= 0
  /// A wiggly candidate is first solved on a coarse mesh of one interval per this length [m], > 0.
  double coarse_interval_length_m = 1.0;
  /// A candidate must start and end within this distance of the start and goal [m], > 0.
  double endpoint_tolerance_m = 0.5;
  /// The fine solve starts Ipopt's barrier warm when its guess takes at most this multiple of
  /// the bang-bang time along its own path (refine::RefinementOptions), >= 1.
  double warm_start_time_ratio = 1.1;
};
/// The whole problem file.
struct ProblemSpec {
  /// The file it was read from, as given (for messages); for parseProblem(), its display name.
  std::filesystem::path source_file;
  /// Where the terrain comes from; paths already resolved against the file's folder.
  terrain::TerrainSource terrain;
  VehicleSpec vehicle;
  BoundaryState start;
  BoundaryState goal;
  CostSpec cost;
  SolverSpec solver;
  PlannerSpec planner;
  RefineSpec refine;
  /// The frame start and goal are written in (terrain.frame); ProblemScene::start() / goal()
  /// are the poses in the local frame.
  terrain::CoordinateFrame pose_frame = terrain::CoordinateFrame::kLocal;
};

}  // namespace terratraj::apps
