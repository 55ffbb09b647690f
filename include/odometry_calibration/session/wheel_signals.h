// The wheels' signals other than JointState positions made joint positions for the session, free
// of ROS, as `wheels.source` chooses: per-wheel tick topics unwrapped (data/tick_unwrapper.h)
// and aligned to common instants (data/wheel_sample_alignment.h), or JointState velocities
// integrated (data/velocity_integrator.h), or the base's own odometry made its cumulative path
// and heading (data/base_odometry_path.h). The joints' signs are applied to the positions; the
// positions are unwrapped already (encoderChannels: no channel wraps for these sources).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/base_odometry_path.h"
#include "odometry_calibration/data/tick_unwrapper.h"
#include "odometry_calibration/data/velocity_integrator.h"
#include "odometry_calibration/data/wheel_sample_alignment.h"

namespace odometry_calibration {

/// What one wheel message gave: joint samples for the session (positions in the joints' order,
/// signs applied), and the problem that kept the message from being used ("" when it was).
struct WheelSignalOutput
{
  std::vector<EncoderSample> samples;
  std::string problem;
};

class WheelSignals
{
public:
  /// For `config`'s joints and wheels section (any source; joint_state gives nothing to do).
  explicit WheelSignals(const CalibrationConfig& config);

  /// Joint `wheel`'s raw tick reading `raw` at `stamp_s` [s].
  WheelSignalOutput addTick(std::size_t wheel, double stamp_s, double raw);
  /// The joints' velocities [units/s] at `stamp_s` [s], in the joints' order.
  WheelSignalOutput addVelocities(double stamp_s, const Eigen::VectorXd& velocity);
  /// The base's own odometry pose `T_odom_base` at `stamp_s` [s] (wheels.source odometry): the
  /// base_forward, base_lateral, base_yaw joints.
  WheelSignalOutput addBaseOdometry(double stamp_s, const Pose2& T_odom_base);

private:
  /// The joints' signs applied to `samples`' values.
  std::vector<EncoderSample> signed_(std::vector<EncoderSample> samples) const;

  Eigen::VectorXd signs_;
  std::vector<TickUnwrapper> unwrappers_;
  WheelSampleAligner aligner_;
  VelocityIntegrator integrator_;
  BaseOdometryPath base_path_;
  std::vector<double> last_stamp_s_;  ///< each wheel's newest tick stamp [s]
};

}  // namespace odometry_calibration
