#include "odometry_calibration/eval/metrics.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {

double absoluteTrajectoryError(const std::vector<Pose2>& estimated,
                               const std::vector<Pose2>& reference)
{
  if (estimated.size() != reference.size() || estimated.empty()) {
    throw std::invalid_argument("ATE needs two non-empty trajectories of equal length");
  }
  double sum = 0.0;
  for (std::size_t k = 0; k < estimated.size(); ++k) {
    const Pose2 error = between(estimated[k], reference[k]);
    sum += error.x() * error.x() + error.y() * error.y();
  }
  return std::sqrt(sum / static_cast<double>(estimated.size()));
}

double relativePoseError(const std::vector<Pose2>& estimated, const std::vector<Pose2>& reference)
{
  if (estimated.size() != reference.size() || estimated.size() < 2) {
    throw std::invalid_argument("RPE needs two trajectories of equal length, at least two poses");
  }
  double sum = 0.0;
  for (std::size_t k = 0; k + 1 < estimated.size(); ++k) {
    const Pose2 error =
        between(between(estimated[k], estimated[k + 1]), between(reference[k], reference[k + 1]));
    sum += error.x() * error.x() + error.y() * error.y();
  }
  return std::sqrt(sum / static_cast<double>(estimated.size() - 1));
}

}  // namespace odometry_calibration
