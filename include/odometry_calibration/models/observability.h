// Says in words which parameters of a parametric model the data cannot determine, and why
// (the report's observability verdict names the missing motion).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// What a model's parameters need, phrased for the user.
struct ObservabilityHints
{
  /// Parameters that straight driving cannot determine, e.g. "axis_length and sensor_y".
  std::string unobservable_without_turning;
  /// What turning one way only leaves confused, e.g. "steering_offset cannot be separated
  /// from steering_scale".
  std::string confused_by_one_way_turns;
  /// Parameters whose sigma is judged relative to their value (scales, radii, lengths of the
  /// robot); all others by absolute thresholds (0.05 m, 0.02 rad).
  std::vector<std::string> relative_parameters;
};

/// Warnings that a parameter is not determined: about the motion in `pairs` (too little
/// travel, no turns, turns one way only) and about the fit (covariance unavailable, a sigma large
/// against the value or an absolute tolerance). `covariance` is in the order of `estimates`.
/// Empty when all is well determined. Two parameters that are almost perfectly correlated but
/// each well determined are no warning: they go to `notes` (if given) as information.
std::vector<std::string> observabilityWarnings(const std::vector<MotionPair>& pairs,
                                               const std::vector<ParameterEstimate>& estimates,
                                               const Eigen::MatrixXd& covariance,
                                               bool covariance_available,
                                               const ObservabilityHints& hints,
                                               std::vector<std::string>* notes = nullptr);

}  // namespace odometry_calibration
