// Report rows of a fitted parameter vector, shared by the parametric models (diff drive,
// mecanum, tricycle): each value with its start and its standard deviation, the square root of
// the matching diagonal entry of the fit's covariance (the inverse Gauss-Newton information at
// the optimum, tricycle seed section 5).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// One ParameterEstimate per entry of `value`, named and united by `names` and `units` (same
/// length), started at `initial`. sigma_i = sqrt(covariance(i, i)); NaN when the covariance is
/// not available or the entry is not positive (the parameter is not determined).
std::vector<ParameterEstimate> parameterEstimates(const std::vector<std::string>& names,
                                                  const std::vector<std::string>& units,
                                                  const Eigen::VectorXd& initial,
                                                  const Eigen::VectorXd& value,
                                                  const Eigen::MatrixXd& covariance,
                                                  bool covariance_available);

}  // namespace odometry_calibration
