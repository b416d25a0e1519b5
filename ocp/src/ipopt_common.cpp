#include "ipopt_common.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <sstream>

#include "terratraj/ocp/deadline.hpp"
#include "terratraj/ocp/path_constraints.hpp"

namespace terratraj::ocp::detail {

const char* ipoptStatusName(Ipopt::ApplicationReturnStatus status) {
  switch (status) {
    case Ipopt::Solve_Succeeded:
      return "Solve_Succeeded";
    case Ipopt::Solved_To_Acceptable_Level:
      return "Solved_To_Acceptable_Level";
    case Ipopt::Infeasible_Problem_Detected:
      return "Infeasible_Problem_Detected";
    case Ipopt::Search_Direction_Becomes_Too_Small:
      return "Search_Direction_Becomes_Too_Small";
    case Ipopt::Diverging_Iterates:
      return "Diverging_Iterates";
    case Ipopt::User_Requested_Stop:
      return "User_Requested_Stop";
    case Ipopt::Feasible_Point_Found:
      return "Feasible_Point_Found";
    case Ipopt::Maximum_Iterations_Exceeded:
      return "Maximum_Iterations_Exceeded";
    case Ipopt::Restoration_Failed:
      return "Restoration_Failed";
    case Ipopt::Error_In_Step_Computation:
      return "Error_In_Step_Computation";
    case Ipopt::Maximum_CpuTime_Exceeded:
      return "Maximum_CpuTime_Exceeded";
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
      return "Not_Enough_Degrees_Of_Freedom";
    case Ipopt::Invalid_Problem_Definition:
      return "Invalid_Problem_Definition";
    case Ipopt::Invalid_Option:
      return "Invalid_Option";
    case Ipopt::Invalid_Number_Detected:
      return "Invalid_Number_Detected";
    case Ipopt::Unrecoverable_Exception:
      return "Unrecoverable_Exception";
    case Ipopt::NonIpopt_Exception_Thrown:
      return "NonIpopt_Exception_Thrown";
    case Ipopt::Insufficient_Memory:
      return "Insufficient_Memory";
    case Ipopt::Internal_Error:
      return "Internal_Error";
  }
  return "unknown Ipopt status";
}

bool setBaseOptions(Ipopt::OptionsList& options, const IpoptBaseSettings& settings) {
  bool ok = options.SetStringValue("sb", "yes") &&
            options.SetIntegerValue("print_level", settings.print_level) &&
            options.SetStringValue("linear_solver", "mumps") &&
            options.SetIntegerValue("mumps_pivot_order", 2) &&
            options.SetIntegerValue("max_iter", settings.max_iterations);
  if (settings.max_cpu_time_s) {
    ok = ok && options.SetNumericValue("max_cpu_time", std::max(*settings.max_cpu_time_s, 1e-6));
  }
  return ok;
}

bool initializeIpopt(Ipopt::IpoptApplication& app) {
  const char* tuning = std::getenv("TERRATRAJ_IPOPT_OPTIONS");
  // "": no ipopt.opt file is read from the working directory.
  return app.Initialize(tuning != nullptr ? tuning : "") == Ipopt::Solve_Succeeded;
}

IpoptOutcome ipoptOutcome(Ipopt::ApplicationReturnStatus status, bool timed_out, int max_iterations,
                          std::optional<double> time_limit_s, bool stopped) {
  const std::string name = ipoptStatusName(status);
  std::ostringstream limit;
  if (stopped) {
    limit << kStoppedOnRequest;
  } else {
    limit << "time limit of " << time_limit_s.value_or(0.0) << " s reached";
  }
  if (timed_out && status != Ipopt::Solve_Succeeded &&
      status != Ipopt::Solved_To_Acceptable_Level) {
    return {SolveStatus::kMaxIterations, limit.str()};
  }
  switch (status) {
    case Ipopt::Solve_Succeeded:
    case Ipopt::Solved_To_Acceptable_Level:
      return {SolveStatus::kConverged, ""};
    case Ipopt::Maximum_Iterations_Exceeded:
      return {SolveStatus::kMaxIterations,
              "max_iterations = " + std::to_string(max_iterations) + " reached"};
    case Ipopt::Maximum_CpuTime_Exceeded:
      return {SolveStatus::kMaxIterations, limit.str() + " (Ipopt max_cpu_time)"};
    case Ipopt::User_Requested_Stop:
      if (timed_out) return {SolveStatus::kMaxIterations, limit.str()};
      return {SolveStatus::kDiverged, "Ipopt stopped: " + name};
    case Ipopt::Infeasible_Problem_Detected:
      return {SolveStatus::kInfeasible,
              "Ipopt: the constraints are locally infeasible (" + name + ")"};
    case Ipopt::Restoration_Failed:
      return {SolveStatus::kInfeasible,
              "Ipopt's feasibility restoration failed (" + name + "): no feasible point near here"};
    case Ipopt::Not_Enough_Degrees_Of_Freedom:
      return {SolveStatus::kInfeasible,
              "too few degrees of freedom (" + name + "): more unknowns are needed"};
    case Ipopt::Diverging_Iterates:
    case Ipopt::Search_Direction_Becomes_Too_Small:
    case Ipopt::Error_In_Step_Computation:
    case Ipopt::Invalid_Number_Detected:
    case Ipopt::Feasible_Point_Found:
      return {SolveStatus::kDiverged, "Ipopt returned " + name};
    default:
      return {SolveStatus::kError, "Ipopt returned " + name};
  }
}

bool degenerateAtRestEnd(const VehicleState& end, std::string_view limit) {
  return standsStill(end) && end.omega == 0.0 && vanishesAtRest(limit);
}

}  // namespace terratraj::ocp::detail
