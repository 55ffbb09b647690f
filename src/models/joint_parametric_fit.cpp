#include "odometry_calibration/models/joint_parametric_fit.h"

#include <limits>
#include <stdexcept>

#include "odometry_calibration/models/parameter_estimates.h"

namespace odometry_calibration {

std::vector<MotionPair> concatenatePairs(const std::vector<std::vector<MotionPair>>& pairs,
                                         std::vector<std::size_t>* sensor_of_pair)
{
  std::vector<MotionPair> all;
  sensor_of_pair->clear();
  for (std::size_t s = 0; s < pairs.size(); ++s) {
    all.insert(all.end(), pairs[s].begin(), pairs[s].end());
    sensor_of_pair->insert(sensor_of_pair->end(), pairs[s].size(), s);
  }
  return all;
}

namespace {

/// The rows and columns of `indices` of `matrix` (a marginal covariance).
Eigen::MatrixXd marginal(const Eigen::MatrixXd& matrix, const std::vector<Eigen::Index>& indices)
{
  const auto n = static_cast<Eigen::Index>(indices.size());
  Eigen::MatrixXd part(n, n);
  for (Eigen::Index a = 0; a < n; ++a)
    for (Eigen::Index b = 0; b < n; ++b)
      part(a, b) = matrix(indices[a], indices[b]);
  return part;
}

}  // namespace

void describeJointFit(const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                      const ParameterLayout& parameters, const Eigen::VectorXd& start,
                      const Eigen::VectorXd& value, const ObservabilityHints& hints,
                      JointFitReport* report)
{
  const auto sensors = static_cast<Eigen::Index>(pairs_per_sensor.size());
  const Eigen::Index n = value.size() - 3 * sensors;  // intrinsics
  if (n < 1 || static_cast<Eigen::Index>(parameters.names.size()) != n + 3)
    throw std::invalid_argument("describeJointFit: the values do not fit the parameter layout");
  const bool available = report->covariance_available;
  for (Eigen::Index s = 0; s < sensors; ++s) {
    // This sensor's view: the intrinsics and its own pose, in the layout's order.
    std::vector<Eigen::Index> indices;
    for (Eigen::Index i = 0; i < n; ++i)
      indices.push_back(i);
    for (Eigen::Index i = 0; i < 3; ++i)
      indices.push_back(n + 3 * s + i);
    Eigen::VectorXd own_start(n + 3), own_value(n + 3);
    for (Eigen::Index i = 0; i < n + 3; ++i) {
      own_start(i) = start(indices[static_cast<std::size_t>(i)]);
      own_value(i) = value(indices[static_cast<std::size_t>(i)]);
    }
    const Eigen::MatrixXd own_covariance =
        available ? marginal(report->covariance, indices) : Eigen::MatrixXd();
    const std::vector<ParameterEstimate> estimates = parameterEstimates(
        parameters.names, parameters.units, own_start, own_value, own_covariance, available);
    if (s == 0)
      report->intrinsics.assign(estimates.begin(), estimates.begin() + n);
    JointSensorReport& sensor = report->sensors[static_cast<std::size_t>(s)];
    sensor.pose.assign(estimates.begin() + n, estimates.end());
    sensor.warnings =
        observabilityWarnings(pairs_per_sensor[static_cast<std::size_t>(s)], estimates,
                              own_covariance, available, hints, &sensor.notes);
  }
}

}  // namespace odometry_calibration
