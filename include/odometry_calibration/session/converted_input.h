// One input message, converted for the session: what a front end (the live node's subscriptions,
// the bag reader) makes of a message before the session takes it, free of ROS. A message that
// could not be converted is a "bad" input carrying the reason; feedInput hands every kind to the
// session method that takes it, so that the node and calibrate_bag skip and count the same
// messages: a bad input is skipped and counted (SessionCounts' bad_encoder_messages or
// bad_ego_messages, the first reason kept), and so is an input the session refuses (too few
// usable readings, a cloud in another frame than the first one's, ...).
#pragma once

#include <cstddef>
#include <string>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

class CalibrationSession;
class JointCalibrationSession;

/// One message made a session input.
struct ConvertedInput
{
  enum class Kind
  {
    kJoints,           ///< `raw`: the configured joints' positions (encoderChannels order, signs
                       ///< applied)
    kBadJoints,        ///< an encoder message that could not be used (`problem` says why)
    kScan,             ///< `scan` from a laser scan in `frame` (empty: unnamed)
    kCloudScan,        ///< `scan` from a 3D lidar's cloud in `frame`; `problem` non-empty: the
                       ///< cloud's per-point times were not used, and why
    kBadEgoMessage,    ///< an ego-motion message that gave nothing: `message_type`, `problem`
    kSensorPose,       ///< `pose`: the sensor's pose in the world; `frame` its child frame (or "")
    kWheelTick,        ///< `raw(0)`: joint `wheel`'s raw tick reading (wheels.source ticks)
    kJointVelocities,  ///< `raw`: the joints' velocities (encoderChannels order, no signs)
    kBaseOdometry,  ///< `pose`: the base's own odometry pose T_odom_base (wheels.source odometry)
    kGyro,          ///< `raw`: an IMU's angular velocity (x, y, z) in its frame [rad/s];
                    ///< `problem` non-empty: a reading that could not be read, and why
  };
  Kind kind = Kind::kJoints;
  /// The ego-motion source the message came from (egoMotionSources order; 0 with one source
  /// and for encoder messages, which go to every source).
  std::size_t source = 0;
  std::size_t wheel = 0;  ///< kWheelTick: the joint whose topic it came on (joints' order)
  /// The message's stamp [s]; a tick topic's messages have none: the receive time (live) or
  /// the record time (bag).
  double stamp_s = 0.0;
  Eigen::VectorXd raw;
  Scan scan;
  Pose2 pose;
  std::string frame;
  std::string problem;
  std::string message_type;  ///< a bad ego-motion message's type ("LaserScan", "pose", ...)
  std::string publisher;     ///< the node that published it (empty: unknown)
};

/// `input` into a session of one ego-motion source (its calibrate_bag form). Throws
/// std::out_of_range for an ego-motion input of another source than 0.
void feedInput(CalibrationSession& session, const ConvertedInput& input);

/// `input` into a session of every source: encoder inputs to all of them (the joint session's
/// own methods), ego-motion inputs to `sessions.source(input.source)` (std::out_of_range
/// beyond the sources).
void feedInput(JointCalibrationSession& sessions, const ConvertedInput& input);

}  // namespace odometry_calibration
