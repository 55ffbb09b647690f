#include "odometry_calibration/sim/tricycle_log_sink.h"

#include <cinttypes>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "odometry_calibration/data/encoder.h"

namespace odometry_calibration {
namespace sim {

TricycleLogSink::TricycleLogSink(const Scenario& scenario, const TricycleParameters& nominal,
                                 double steering_ticks_per_rev, double traction_ticks_per_rev)
    : nominal_(nominal), start_time_s_(scenario.start_time_s)
{
  if (!scenario.encoders.output_ticks || scenario.encoders.counter_bits != 32) {
    throw std::invalid_argument(
        "the tricycle log format needs encoder output in ticks and a 32-bit traction counter");
  }
  layout_.steering_ticks_per_turn = steering_ticks_per_rev;
  layout_.traction_ticks_per_turn = traction_ticks_per_rev;
  layout_.steering_at_step_end = true;  // the seed robot's own odometry, as its logs hold
  char header[1024];
  const Pose2& laser = nominal.T_base_sensor;
  std::snprintf(header, sizeof(header),
                "#kinematic_model: traction_drive_wheel\n"
                "#parameters: [ Ksteer Ktraction axis_length steer_offset ]\n"
                "#parameter_values: %.9g %.9g %.9g %.9g \n"
                "#joints_max_enc: [ steering traction_wheel ]\n"
                "#joints_max_enc_values: %.0f %.0f \n"
                "#laser wrt base_link \n"
                "#\ttranslation:\t[ %.9g, %.9g, 0 ],\n"
                "#\trotation:\t [ 0, 0, %.9g, %.9g ]\n",
                nominal.steering_scale, nominal.traction_scale_m_per_turn, nominal.axis_length_m,
                nominal.steering_offset_rad, steering_ticks_per_rev, traction_ticks_per_rev,
                laser.x(), laser.y(), std::sin(0.5 * laser.theta()), std::cos(0.5 * laser.theta()));
  text_ = header;
}

void TricycleLogSink::onJointState(const JointStateSample& sample)
{
  if (sample.positions.size() != 2) {
    throw std::invalid_argument("the tricycle log needs two joints (steering, traction)");
  }
  last_joint_sample_ = sample;
  has_joint_sample_ = true;
}

void TricycleLogSink::onTracker(const TrackerSample& sample)
{
  if (!has_joint_sample_) {
    return;
  }
  const double steering = last_joint_sample_.positions[0];
  const double traction = last_joint_sample_.positions[1];
  // The robot's own odometry with the nominal parameters (the format's model_pose).
  EncoderSample decoded{
      last_joint_sample_.stamp_s,
      Eigen::Vector2d(signedAbsoluteReading(steering, layout_.steering_ticks_per_turn), 0.0)};
  if (rows_ > 0) {
    traction_cumulative_ += wrappedDifference(previous_traction_raw_, traction, 4294967296.0);
  }
  decoded.values(1) = traction_cumulative_;
  if (rows_ > 0) {
    const Eigen::Vector4d kinematic = nominal_.kinematicVector();
    T_odom_base_nominal_ =
        T_odom_base_nominal_ *
        integrateTricycleMotion(kinematic.data(), layout_, {previous_decoded_, decoded});
  }
  previous_decoded_ = decoded;
  previous_traction_raw_ = traction;
  // Whole seconds and nanoseconds separately: the format keeps 9 decimals.
  const std::int64_t stamp_ns =
      std::llround(start_time_s_ * 1e9) + std::llround(last_joint_sample_.stamp_s * 1e9);
  char row[512];
  std::snprintf(row, sizeof(row),
                "time: %" PRId64 ".%09" PRId64
                " ticks: %.0f %.0f model_pose: %.6g %.6g %.6g "
                "tracker_pose: %.6g %.6g %.6g\n",
                stamp_ns / 1000000000, stamp_ns % 1000000000, steering, traction,
                T_odom_base_nominal_.x(), T_odom_base_nominal_.y(), T_odom_base_nominal_.theta(),
                sample.T_world_sensor.x(), sample.T_world_sensor.y(),
                sample.T_world_sensor.theta());
  text_ += row;
  ++rows_;
}

bool canWriteTricycleLog(const Scenario& scenario)
{
  return scenario.robot.type == "tricycle" && scenario.tracker.enabled;
}

std::unique_ptr<TricycleLogSink> makeTricycleLogSink(const Scenario& scenario)
{
  if (!canWriteTricycleLog(scenario)) {
    throw std::invalid_argument("a tricycle log needs a tricycle robot with the tracker enabled");
  }
  const auto parameters = makeRobot(scenario.robot)->trueParameters();
  const TricycleParameters nominal = TricycleParameters::fromVectors(
      Eigen::Vector4d(0.1, 0.0106141, 1.4, 0.0), Eigen::Vector3d(1.5, 0.0, 0.0));
  return std::make_unique<TricycleLogSink>(scenario, nominal,
                                           parameters.at("steering_ticks_per_rev"),
                                           parameters.at("traction_ticks_per_rev"));
}
}  // namespace sim
}  // namespace odometry_calibration
