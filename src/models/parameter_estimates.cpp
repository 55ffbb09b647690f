#include "odometry_calibration/models/parameter_estimates.h"

#include <cmath>
#include <limits>
#include <stdexcept>

namespace odometry_calibration {

std::vector<ParameterEstimate> parameterEstimates(const std::vector<std::string>& names,
                                                  const std::vector<std::string>& units,
                                                  const Eigen::VectorXd& initial,
                                                  const Eigen::VectorXd& value,
                                                  const Eigen::MatrixXd& covariance,
                                                  bool covariance_available)
{
  const Eigen::Index n = value.size();
  if (static_cast<Eigen::Index>(names.size()) != n ||
      static_cast<Eigen::Index>(units.size()) != n || initial.size() != n) {
    throw std::invalid_argument(
        "parameterEstimates: names, units, initial and value differ in size");
  }
  const bool use_covariance =
      covariance_available && covariance.rows() == n && covariance.cols() == n;
  std::vector<ParameterEstimate> estimates;
  estimates.reserve(static_cast<std::size_t>(n));
  for (Eigen::Index i = 0; i < n; ++i) {
    const double variance = use_covariance ? covariance(i, i) : 0.0;
    const double sigma =
        variance > 0.0 ? std::sqrt(variance) : std::numeric_limits<double>::quiet_NaN();
    const auto k = static_cast<std::size_t>(i);
    estimates.push_back({names[k], units[k], initial(i), value(i), sigma});
  }
  return estimates;
}

}  // namespace odometry_calibration
