#pragma once
// Pieces shared by the fixed-step and CVODES parts of RoverIntegrator (not installed).

#include <vector>

#include "terratraj/models/rover_integrator.hpp"

namespace terratraj::models::detail {

/// Throws std::invalid_argument for non-positive step, tolerances or max_steps.
void validateOptions(const IntegratorOptions& options);
/// kNoTerrain for kNoTerrain, kNoContact otherwise.
IntegrationStatus fromAttitudeStatus(AttitudeStatus status);
/// A trajectory row; curvature omega / v (NaN when v = 0).
TrajectorySample makeSample(double t, const Eigen::Vector3d& state, double v, double omega,
                            const Attitude& attitude);
/// Checks duration and sample times; on failure sets result's status and message.
bool validateRequest(double duration, const std::vector<double>& sample_times,
                     IntegrationResult& result);
/// Resets result for a new integration (keeps its storage).
void prepareResult(const Eigen::Vector3d& initial, int parameter_count, bool sensitivities,
                   std::size_t sample_count, IntegrationResult& result);

}  // namespace terratraj::models::detail
