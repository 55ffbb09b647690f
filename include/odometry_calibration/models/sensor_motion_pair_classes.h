// How the pairs of a sensor-motion fit sit around its solution: each sensor's robust noise scale
// (the median whitened error against unit Gaussian noise) and the inliers, outliers and gross
// outliers with the inliers' chi^2 per degree of freedom.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/sensor_motion_fit_result.h"
#include "odometry_calibration/models/sensor_motion_residual.h"

namespace odometry_calibration {

/// The robust noise scale of each sensor (sensorMotionNoiseScale over that sensor's pairs; 1
/// for a sensor without pairs).
template <class Kinematics>
std::vector<double> sensorMotionNoiseScales(const SensorPairs& pairs,
                                            const typename Kinematics::Layout& layout,
                                            const double* intrinsic,
                                            const std::vector<const double*>& sensor_poses)
{
  std::vector<std::vector<double>> norms(sensor_poses.size());
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i) {
    const std::size_t sensor = pairs.sensorOf(i);
    Eigen::Vector3d whitened;
    SensorMotionResidual<Kinematics>(pairs.pairs[i], layout)(intrinsic, sensor_poses[sensor],
                                                             whitened.data());
    norms[sensor].push_back(whitened.norm());
  }
  std::vector<double> scales(sensor_poses.size(), 1.0);
  for (std::size_t s = 0; s < norms.size(); ++s) {
    if (norms[s].empty())
      continue;
    std::vector<double>& n = norms[s];
    std::nth_element(n.begin(), n.begin() + n.size() / 2, n.end());
    scales[s] = std::max(n[n.size() / 2] / 1.538, 1e-6);
  }
  return scales;
}

/// The robust noise scale of a solution: the median whitened error norm of the pairs against
/// that of unit Gaussian noise (3-D: sqrt(chi2_3 median 2.366) = 1.538), at least 1e-6.
template <class Kinematics>
double sensorMotionNoiseScale(const std::vector<MotionPair>& pairs,
                              const typename Kinematics::Layout& layout, const double* intrinsic,
                              const double* sensor_pose)
{
  return sensorMotionNoiseScales<Kinematics>(SensorPairs{pairs, {}}, layout, intrinsic,
                                             {sensor_pose})[0];
}

/// The pairs of a fit sorted by their whitened errors: inliers, and per sensor the outliers and
/// the gross ones among them; chi2_per_dof of the inliers (NaN without degrees of freedom).
struct SensorPairClasses
{
  std::vector<bool> inlier;
  std::vector<std::size_t> outliers, gross_outliers;
  double chi2_per_dof = std::numeric_limits<double>::quiet_NaN();
};

/// The several-sensor form of the function below: each pair whitened with its sensor's noise
/// scale, the degrees of freedom 3 per inlier less the N + 3 S parameters.
template <class Kinematics>
SensorPairClasses classifySensorMotionPairs(const SensorPairs& pairs,
                                            const typename Kinematics::Layout& layout,
                                            const SensorMotionFitOptions& options,
                                            const double* intrinsic,
                                            const std::vector<const double*>& sensor_poses,
                                            const std::vector<double>& noise_scales)
{
  constexpr int N = Kinematics::kIntrinsics;
  const std::size_t sensors = sensor_poses.size();
  SensorPairClasses classes;
  classes.outliers.assign(sensors, 0);
  classes.gross_outliers.assign(sensors, 0);
  double chi2_inliers = 0.0;
  std::size_t inlier_count = 0;
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i) {
    const std::size_t sensor = pairs.sensorOf(i);
    Eigen::Vector3d whitened;
    SensorMotionResidual<Kinematics>(pairs.pairs[i], layout, noise_scales[sensor])(
        intrinsic, sensor_poses[sensor], whitened.data());
    const double chi2 = whitened.squaredNorm();
    const bool is_inlier =
        options.huber_threshold <= 0.0 || chi2 <= options.huber_threshold * options.huber_threshold;
    classes.inlier.push_back(is_inlier);
    if (is_inlier) {
      chi2_inliers += chi2;
      ++inlier_count;
      continue;
    }
    ++classes.outliers[sensor];
    if (chi2 > options.gross_threshold * options.gross_threshold)
      ++classes.gross_outliers[sensor];
  }
  const double dof = 3.0 * static_cast<double>(inlier_count) - (N + 3.0 * sensors);
  if (dof > 0.0)
    classes.chi2_per_dof = chi2_inliers / dof;
  return classes;
}

/// Marks each pair an inlier when its whitened error (noise scale applied) is within the Huber
/// threshold, counts the outliers and the gross ones among them, and sets chi2_per_dof from the
/// inliers' chi^2 (3 per pair less the N + 3 parameters).
template <class Kinematics>
void classifySensorMotionPairs(const std::vector<MotionPair>& pairs,
                               const typename Kinematics::Layout& layout,
                               const SensorMotionFitOptions& options, const double* intrinsic,
                               const double* sensor_pose,
                               SensorMotionFit<Kinematics::kIntrinsics>* fit)
{
  const SensorPairClasses classes = classifySensorMotionPairs<Kinematics>(
      SensorPairs{pairs, {}}, layout, options, intrinsic, {sensor_pose}, {fit->noise_scale});
  fit->inlier.insert(fit->inlier.end(), classes.inlier.begin(), classes.inlier.end());
  fit->outliers = classes.outliers[0];
  fit->gross_outliers += classes.gross_outliers[0];
  if (std::isfinite(classes.chi2_per_dof))
    fit->chi2_per_dof = classes.chi2_per_dof;
}

}  // namespace odometry_calibration
