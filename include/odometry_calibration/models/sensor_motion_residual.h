// The residual of the parametric sensor-motion fits (tricycle seed sections 3-5; Censi et al.
// T-RO 2013): a pair's whitened SE(2) error e = Z^-1 * (T_bs^-1 * Delta_base * T_bs) between
// the sensor motion a kinematic model predicts and the measured one; the pairs of one or several
// sensors and how they are added to a Ceres problem.
//
// A kinematic model plugs in as a type with
//   using Layout = ...;                           // where its joints are
//   static constexpr int kIntrinsics = N;         // number of intrinsic parameters
//   template <typename T> static Pose2T<T> integrate(const T* intrinsic, const Layout&,
//                                                    const std::vector<EncoderSample>&);
#pragma once

#include <cstddef>
#include <vector>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/se2_manifold.h"

namespace odometry_calibration {

/// Cost functor for one pair: parameter blocks are the intrinsics and the sensor pose
/// (x, y, theta); the residual is the pair's whitened SE(2) error (3 values).
template <class Kinematics>
class SensorMotionResidual
{
public:
  /// Keeps a reference to `pair`, which must outlive the functor. `noise_scale` multiplies
  /// the pair's standard deviations (a robust estimate of how mis-scaled they are).
  SensorMotionResidual(const MotionPair& pair, const typename Kinematics::Layout& layout,
                       double noise_scale = 1.0)
      : pair_(pair), layout_(layout)
  {
    // L^-1 with covariance = L L^T, so that |L^-1 e|^2 = e^T Sigma^-1 e.
    const Eigen::Matrix3d lower = pair.covariance.llt().matrixL();
    sqrt_information_ = lower.inverse() / noise_scale;
  }

  template <typename T>
  bool operator()(const T* intrinsic, const T* sensor_pose, T* residual) const
  {
    const Pose2T<T> T_base_sensor(sensor_pose[0], sensor_pose[1], sensor_pose[2]);
    const Pose2T<T> base_motion = Kinematics::integrate(intrinsic, layout_, pair_.encoder_samples);
    const Eigen::Matrix<T, 3, 1> error =
        boxMinus(sensorMotionFromBodyMotion(T_base_sensor, base_motion),
                 pair_.sensor_motion.template cast<T>());
    Eigen::Map<Eigen::Matrix<T, 3, 1>> whitened(residual);
    whitened = sqrt_information_.cast<T>() * error;
    return true;
  }

private:
  const MotionPair& pair_;
  typename Kinematics::Layout layout_;
  Eigen::Matrix3d sqrt_information_;
};

/// Pairs of one or several sensors: `sensor[i]` is pair i's sensor (0, 1, ...), an empty
/// `sensor` puts every pair on sensor 0. The pairs are referenced, not copied.
struct SensorPairs
{
  const std::vector<MotionPair>& pairs;
  std::vector<std::size_t> sensor;

  std::size_t sensorOf(std::size_t i) const { return sensor.empty() ? 0 : sensor[i]; }
};

/// Adds one residual per pair to `problem` on the intrinsics and its sensor's pose
/// (`sensor_poses[sensorOf(i)]`, 3 values each on the SE(2) manifold), its covariance scaled by
/// its sensor's `noise_scales` entry: the several-sensor form of the function below.
template <class Kinematics>
void addSensorMotionResiduals(ceres::Problem& problem, const SensorPairs& pairs,
                              const typename Kinematics::Layout& layout, double huber_threshold,
                              const std::vector<double>& noise_scales, double* intrinsic,
                              const std::vector<double*>& sensor_poses)
{
  using Residual = SensorMotionResidual<Kinematics>;
  for (std::size_t i = 0; i < pairs.pairs.size(); ++i) {
    const std::size_t sensor = pairs.sensorOf(i);
    auto* cost = new ceres::AutoDiffCostFunction<Residual, 3, Kinematics::kIntrinsics, 3>(
        new Residual(pairs.pairs[i], layout, noise_scales[sensor]));
    ceres::LossFunction* loss =
        huber_threshold > 0.0 ? new ceres::HuberLoss(huber_threshold) : nullptr;
    problem.AddResidualBlock(cost, loss, intrinsic, sensor_poses[sensor]);
  }
  for (double* sensor_pose : sensor_poses) {
    if (problem.HasParameterBlock(sensor_pose))
      problem.SetManifold(sensor_pose, newSe2Manifold());
  }
}

/// Adds one residual per pair to `problem`: the pair's whitened SE(2) error
/// (SensorMotionResidual, its covariance scaled by `noise_scale`) under a Huber loss when
/// `huber_threshold` > 0, on the blocks `intrinsic` (Kinematics::kIntrinsics values) and
/// `sensor_pose` (x, y, theta, on the SE(2) manifold).
template <class Kinematics>
void addSensorMotionResiduals(ceres::Problem& problem, const std::vector<MotionPair>& pairs,
                              const typename Kinematics::Layout& layout, double huber_threshold,
                              double noise_scale, double* intrinsic, double* sensor_pose)
{
  addSensorMotionResiduals<Kinematics>(problem, SensorPairs{pairs, {}}, layout, huber_threshold,
                                       {noise_scale}, intrinsic, {sensor_pose});
}

/// RMS of the SE(2) errors of the model's predictions over `pairs` (those with `keep[i]` when
/// `keep` is given); per axis into `per_axis` and the errors' second moment (the per-pair
/// spread a prediction's covariance reports) into `spread`, when given.
template <class Kinematics>
ResidualRms sensorMotionResidualRms(const std::vector<MotionPair>& pairs,
                                    const typename Kinematics::Layout& layout,
                                    const double* intrinsic, const Pose2& T_base_sensor,
                                    const std::vector<bool>* keep = nullptr,
                                    Eigen::Vector3d* per_axis = nullptr,
                                    Eigen::Matrix3d* spread = nullptr)
{
  ResidualRms rms;
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  Eigen::Matrix3d outer = Eigen::Matrix3d::Zero();
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    if (keep && !(*keep)[i])
      continue;
    const Pose2 base = Kinematics::integrate(intrinsic, layout, pairs[i].encoder_samples);
    const Eigen::Vector3d e =
        boxMinus(sensorMotionFromBodyMotion(T_base_sensor, base), pairs[i].sensor_motion);
    sum += e.cwiseProduct(e);
    outer += e * e.transpose();
    ++rms.count;
  }
  if (rms.count > 0) {
    const double n = static_cast<double>(rms.count);
    rms.translation_m = std::sqrt((sum(0) + sum(1)) / n);
    rms.rotation_rad = std::sqrt(sum(2) / n);
    if (per_axis)
      *per_axis = (sum / n).cwiseSqrt();
    if (spread)
      *spread = outer / n;
  }
  return rms;
}

}  // namespace odometry_calibration
