#include "odometry_calibration/ros/report_messages.h"

#include <limits>

#include <ros/time.h>

namespace odometry_calibration {
namespace ros_conversions {

odometry_calibration::CalibrationReport toReportMsg(const ModelReport& report,
                                                    std::size_t pairs_collected,
                                                    double time_offset_s)
{
  odometry_calibration::CalibrationReport msg;
  msg.model = report.model;
  for (const ParameterEstimate& p : report.parameters) {
    odometry_calibration::CalibrationParameter parameter;
    parameter.name = p.name;
    parameter.unit = p.unit;
    parameter.initial = p.initial;
    parameter.value = p.value;
    parameter.sigma = p.sigma;
    msg.parameters.push_back(parameter);
  }
  // Model-free fits have no start values: no "before" (NaN), never a 0 that looks measured.
  const bool has_before = report.before.count > 0;
  const double none = std::numeric_limits<double>::quiet_NaN();
  msg.residual_rms_translation_before_m = has_before ? report.before.translation_m : none;
  msg.residual_rms_rotation_before_rad = has_before ? report.before.rotation_rad : none;
  msg.residual_rms_translation_after_m = report.after.translation_m;
  msg.residual_rms_rotation_after_rad = report.after.rotation_rad;
  for (int i = 0; i < 3; ++i)
    msg.residual_rms_xytheta[i] = report.residual_rms_xytheta(i);
  msg.pairs_collected = static_cast<uint32_t>(pairs_collected);
  msg.pairs_used = static_cast<uint32_t>(report.pairs_used);
  msg.pairs_rejected = static_cast<uint32_t>(report.rejected);
  msg.pairs_down_weighted = static_cast<uint32_t>(report.down_weighted);
  msg.iterations = report.iterations;
  msg.converged = report.converged;
  msg.termination = report.termination;
  msg.fit_time_s = report.fit_time_s;
  msg.has_extrinsic = report.has_extrinsic;
  msg.T_base_laser.x = report.T_base_sensor.x();
  msg.T_base_laser.y = report.T_base_sensor.y();
  msg.T_base_laser.theta = report.T_base_sensor.theta();
  msg.time_offset_s = time_offset_s;
  msg.warnings = report.warnings;
  return msg;
}

odometry_calibration::CalibrationPair toPairMsg(const MotionPair& pair, const JointLayout& joints,
                                                const std::string& sensor_frame)
{
  odometry_calibration::CalibrationPair msg;
  msg.header.stamp = ros::Time(pair.end_stamp_s);
  msg.header.frame_id = sensor_frame;
  msg.start = ros::Time(pair.start_stamp_s);
  msg.end = ros::Time(pair.end_stamp_s);
  msg.sensor_motion.x = pair.sensor_motion.x();
  msg.sensor_motion.y = pair.sensor_motion.y();
  msg.sensor_motion.theta = pair.sensor_motion.theta();
  for (int i = 0; i < 9; ++i)
    msg.covariance[i] = pair.covariance(i / 3, i % 3);
  msg.joints = joints.names;
  const Eigen::VectorXd features = pairFeatures(pair.encoder_samples, joints);
  msg.increments.assign(features.data(), features.data() + features.size());
  msg.encoder_samples = static_cast<uint32_t>(pair.encoder_samples.size());
  return msg;
}

}  // namespace ros_conversions
}  // namespace odometry_calibration
