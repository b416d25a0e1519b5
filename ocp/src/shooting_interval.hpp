#pragma once
// ShootingInterval: integrates the state-space rover over one shooting interval with CVODES,
// with forward sensitivities by the interval's start state, its controls and the final time
// (not installed; used by TranscriptionNlp).
//
// On the interval, in normalised time s in [0, 1]: z' = H f(z, u(s)) with H = t_f * delta the
// interval's duration and u(s) = u_k (piecewise-constant controls) or u_k + s (u_{k+1} - u_k)
// (piecewise-linear). Parameters p = (z_k [5], u_k [2], u_{k+1} [2, linear only], t_f).

#include <Eigen/Core>
#include <memory>
#include <string>

#include "terratraj/ocp/transcription_model.hpp"

namespace terratraj::ocp::detail {

/// The end of one interval and its sensitivities.
struct IntervalResult {
  StateVector end = StateVector::Zero();
  /// d end / d p: 5 x (5 + 2 + [2] + 1).
  Eigen::Matrix<double, kStateSize, Eigen::Dynamic> sensitivity;
  std::string message;  ///< why integrate() failed
};

/// One CVODES session, re-initialised for every interval.
class ShootingInterval {
 public:
  /// `linear_controls`: piecewise-linear controls (else constant).
  ShootingInterval(const TranscriptionModel& model, bool linear_controls, double relative_tolerance,
                   double absolute_tolerance);
  ~ShootingInterval();
  ShootingInterval(const ShootingInterval&) = delete;
  ShootingInterval& operator=(const ShootingInterval&) = delete;

  /// Number of sensitivity parameters.
  int parameterCount() const;

  /// Integrates from `start` over a fraction `delta` of the final time `t_f` with controls
  /// u_k = `u0` and u_{k+1} = `u1`. With `sensitivities`, also fills result.sensitivity.
  /// Returns false (result.message says why) off the map or when CVODES fails. Never throws.
  bool integrate(const StateVector& start, const Eigen::Vector2d& u0, const Eigen::Vector2d& u1,
                 double t_f, double delta, bool sensitivities, IntervalResult& result);

 private:
  struct Session;
  std::unique_ptr<Session> session_;
};

}  // namespace terratraj::ocp::detail
