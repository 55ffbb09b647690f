// One calibration of the wheels and of several sensors' poses (a front and a rear
// laser): one set of intrinsics, one pose per sensor, every pair weighted by its own
// covariance (sensor_motion_fit.h's solver with a sensor index per pair, each sensor's
// covariances rescaled by its own robust noise scale). Each sensor is first fitted alone
// (fitParametricModel, with its global starts); the joint fit starts from the mean of those
// intrinsics and each sensor's own pose. The reports keep the fits alone too: the agreement of
// the sensors' implied wheel parameters is a consistency figure of the calibration.
#pragma once

#include <algorithm>
#include <chrono>
#include <cmath>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/joint_fit_report.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/parametric_model.h"

namespace odometry_calibration {

/// Fills the joint report from a solution: the intrinsics' and each sensor's estimates with σ
/// (the covariance's diagonal), and the per-sensor observability from `pairs_per_sensor`.
void describeJointFit(const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                      const ParameterLayout& parameters, const Eigen::VectorXd& start,
                      const Eigen::VectorXd& value, const ObservabilityHints& hints,
                      JointFitReport* report);

/// The pairs of several sensors as one set with a sensor index per pair (SensorPairs).
std::vector<MotionPair> concatenatePairs(const std::vector<std::vector<MotionPair>>& pairs,
                                         std::vector<std::size_t>* sensor_of_pair);

/// Start values of a joint fit: the intrinsics, then x, y, theta of each sensor.
template <int N>
struct JointStart
{
  Eigen::Matrix<double, N, 1> intrinsic;
  std::vector<Eigen::Vector3d> poses;

  Eigen::VectorXd vector() const
  {
    Eigen::VectorXd values(N + 3 * static_cast<Eigen::Index>(poses.size()));
    values.template head<N>() = intrinsic;
    for (std::size_t s = 0; s < poses.size(); ++s)
      values.template segment<3>(N + 3 * static_cast<Eigen::Index>(s)) = poses[s];
    return values;
  }
};

/// Each sensor's pairs fitted alone (fitParametricModel from `start`, its pose from
/// `start_poses[s]`) into report->alone; returns the joint fit's start: the mean of their
/// intrinsics and each sensor's own pose.
template <class Kinematics, class Mirrored>
JointStart<Kinematics::kIntrinsics> fitSensorsAlone(
    const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
    const typename Kinematics::Layout& layout, const SensorMotionFitOptions& options,
    const ParameterLayout& parameters, Mirrored mirrored,
    const SensorMotionState<Kinematics::kIntrinsics>& start, const std::vector<Pose2>& start_poses,
    JointFitReport* report)
{
  constexpr int N = Kinematics::kIntrinsics;
  JointStart<N> joint{Eigen::Matrix<double, N, 1>::Zero(), {}};
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    SensorMotionState<N> alone = start;
    alone.T_base_sensor = start_poses.at(s);
    report->alone.push_back(fitParametricModel<Kinematics>(report->model, pairs_per_sensor[s],
                                                           layout, options, parameters, mirrored,
                                                           &alone)
                                .report);
    joint.intrinsic += alone.intrinsics / static_cast<double>(pairs_per_sensor.size());
    joint.poses.push_back(alone.T_base_sensor.vector());
  }
  return joint;
}

/// Each sensor's pose, pair counts, noise scale and residuals (all pairs; per axis its inliers)
/// at the joint solution `joint`.
template <class Kinematics>
void reportJointSensors(const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                        const typename Kinematics::Layout& layout,
                        const JointStart<Kinematics::kIntrinsics>& joint,
                        const SensorPairClasses& classes, const std::vector<double>& noise_scales,
                        JointFitReport* report)
{
  report->sensors.resize(pairs_per_sensor.size());
  std::ptrdiff_t first = 0;  // the sensor's first pair in classes.inlier
  for (std::size_t s = 0; s < pairs_per_sensor.size(); ++s) {
    JointSensorReport& sensor = report->sensors[s];
    const Eigen::Vector3d& pose = joint.poses[s];
    sensor.T_base_sensor = Pose2(pose(0), pose(1), normalizeAngle(pose(2)));
    sensor.pairs = pairs_per_sensor[s].size();
    sensor.outliers = classes.outliers[s];
    sensor.rejected = classes.gross_outliers[s];
    sensor.noise_scale = noise_scales[s];
    sensor.after = sensorMotionResidualRms<Kinematics>(
        pairs_per_sensor[s], layout, joint.intrinsic.data(), sensor.T_base_sensor);
    const std::vector<bool> inlier(classes.inlier.begin() + first,
                                   classes.inlier.begin() + first + sensor.pairs);
    sensorMotionResidualRms<Kinematics>(pairs_per_sensor[s], layout, joint.intrinsic.data(),
                                        sensor.T_base_sensor, &inlier,
                                        &sensor.residual_rms_xytheta);
    first += static_cast<std::ptrdiff_t>(sensor.pairs);
  }
}

/// The joint solve from `joint` (each sensor's pairs already fitted alone into report->alone,
/// `joint` their mean intrinsics and each sensor's pose): one set of intrinsics and one pose
/// per sensor, every pair weighted by its covariance times its sensor's noise scale; the
/// convergence, covariance, each sensor's residuals and the parameter rows into `report` (the
/// intrinsics' start values `configured`, the poses' their fits alone). fit_time_s is the
/// caller's.
template <class Kinematics>
void solveJointParametricModel(const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
                               const typename Kinematics::Layout& layout,
                               const SensorMotionFitOptions& options,
                               const ParameterLayout& parameters, const ObservabilityHints& hints,
                               const Eigen::Matrix<double, Kinematics::kIntrinsics, 1>& configured,
                               JointStart<Kinematics::kIntrinsics> joint, JointFitReport* report)
{
  constexpr int N = Kinematics::kIntrinsics;
  JointStart<N> start_values = joint;
  start_values.intrinsic = configured;
  std::vector<std::size_t> sensor_of_pair;
  const std::vector<MotionPair> all = concatenatePairs(pairs_per_sensor, &sensor_of_pair);
  const SensorPairs tagged{all, sensor_of_pair};
  std::vector<double*> pose_blocks;
  for (Eigen::Vector3d& pose : joint.poses)
    pose_blocks.push_back(pose.data());
  const std::vector<const double*> const_poses(pose_blocks.begin(), pose_blocks.end());
  const SensorMotionSolve solve =
      solveSensorMotion<Kinematics>(tagged, layout, options, joint.intrinsic.data(), pose_blocks);
  report->iterations = solve.iterations;
  report->termination = solve.summary.message;
  report->converged = solve.summary.termination_type == ceres::CONVERGENCE &&
                      std::isfinite(solve.summary.final_cost) && joint.vector().allFinite();
  const SensorPairClasses classes = classifySensorMotionPairs<Kinematics>(
      tagged, layout, options, joint.intrinsic.data(), const_poses, solve.noise_scales);
  report->chi2_per_dof = classes.chi2_per_dof;
  if (report->converged) {
    report->covariance_available =
        sensorMotionCovariance(*solve.problem, joint.intrinsic.data(), N, const_poses,
                               classes.chi2_per_dof, &report->covariance);
  }
  reportJointSensors<Kinematics>(pairs_per_sensor, layout, joint, classes, solve.noise_scales,
                                 report);
  Eigen::VectorXd values = joint.vector();
  for (std::size_t s = 0; s < joint.poses.size(); ++s)
    values(N + 3 * static_cast<Eigen::Index>(s) + 2) = report->sensors[s].T_base_sensor.theta();
  describeJointFit(pairs_per_sensor, parameters, start_values.vector(), values, hints, report);
}

/// Fits one set of intrinsics and one pose per sensor to `pairs_per_sensor` (at least one set;
/// each set fitted alone first from `start`'s intrinsics and its own `start_poses` entry, see
/// the file comment; then solveJointParametricModel, the intrinsics' start values reported as
/// `start`'s). `mirrored` as in fitParametricModel; `hints` for each sensor's observability
/// verdict. Throws what a fit alone throws for a set too small.
template <class Kinematics, class Mirrored>
JointFitReport fitJointParametricModel(
    const std::string& model, const std::vector<std::vector<MotionPair>>& pairs_per_sensor,
    const typename Kinematics::Layout& layout, const SensorMotionFitOptions& options,
    const ParameterLayout& parameters, Mirrored mirrored, const ObservabilityHints& hints,
    const SensorMotionState<Kinematics::kIntrinsics>& start, const std::vector<Pose2>& start_poses)
{
  const auto started = std::chrono::steady_clock::now();
  JointFitReport report;
  report.model = model;
  const JointStart<Kinematics::kIntrinsics> joint = fitSensorsAlone<Kinematics>(
      pairs_per_sensor, layout, options, parameters, mirrored, start, start_poses, &report);
  solveJointParametricModel<Kinematics>(pairs_per_sensor, layout, options, parameters, hints,
                                        start.intrinsics, joint, &report);
  report.fit_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
  return report;
}

}  // namespace odometry_calibration
