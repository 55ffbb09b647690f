#include "odometry_calibration/session/converted_input.h"

#include <stdexcept>
#include <string>

#include "odometry_calibration/session/calibration_session.h"
#include "odometry_calibration/session/joint_calibration_session.h"

namespace odometry_calibration {
namespace {

/// An ego-motion input into its source's session.
void feedEgoMotion(CalibrationSession& session, const ConvertedInput& input)
{
  switch (input.kind) {
    case ConvertedInput::Kind::kScan:
      session.addScan(input.stamp_s, input.scan, input.frame, input.publisher);
      break;
    case ConvertedInput::Kind::kCloudScan:
      session.addCloudScan(input.stamp_s, input.scan, input.frame, input.problem, input.publisher);
      break;
    case ConvertedInput::Kind::kBadEgoMessage:
      session.skipEgoMessage(input.message_type, input.problem, input.publisher);
      break;
    case ConvertedInput::Kind::kSensorPose:
      session.addSensorPose(input.stamp_s, input.pose, input.frame, input.publisher);
      break;
    case ConvertedInput::Kind::kJoints:
    case ConvertedInput::Kind::kBadJoints:
    case ConvertedInput::Kind::kWheelTick:
    case ConvertedInput::Kind::kJointVelocities:
    case ConvertedInput::Kind::kBaseOdometry:
    case ConvertedInput::Kind::kGyro:
      break;
  }
}

}  // namespace

void feedInput(CalibrationSession& session, const ConvertedInput& input)
{
  if (input.kind == ConvertedInput::Kind::kWheelTick ||
      input.kind == ConvertedInput::Kind::kJointVelocities ||
      input.kind == ConvertedInput::Kind::kBaseOdometry ||
      input.kind == ConvertedInput::Kind::kGyro) {
    throw std::invalid_argument(
        "wheel ticks, joint velocities, base odometry and gyro readings go to a "
        "JointCalibrationSession (its wheel signals and gyro)");
  }
  if (input.kind == ConvertedInput::Kind::kJoints) {
    session.addJointPositions(input.stamp_s, input.raw, input.publisher);
  } else if (input.kind == ConvertedInput::Kind::kBadJoints) {
    session.skipJointState(input.problem, input.publisher);
  } else if (input.source != 0) {
    throw std::out_of_range("an input of ego-motion source " + std::to_string(input.source) +
                            " fed to a session of one source");
  } else {
    feedEgoMotion(session, input);
  }
}

void feedInput(JointCalibrationSession& sessions, const ConvertedInput& input)
{
  if (input.kind == ConvertedInput::Kind::kJoints)
    sessions.addJointPositions(input.stamp_s, input.raw, input.publisher);
  else if (input.kind == ConvertedInput::Kind::kBadJoints)
    sessions.skipJointState(input.problem, input.publisher);
  else if (input.kind == ConvertedInput::Kind::kWheelTick)
    sessions.addWheelTick(input.wheel, input.stamp_s, input.raw(0), input.publisher);
  else if (input.kind == ConvertedInput::Kind::kJointVelocities)
    sessions.addJointVelocities(input.stamp_s, input.raw, input.publisher);
  else if (input.kind == ConvertedInput::Kind::kBaseOdometry)
    sessions.addBaseOdometry(input.stamp_s, input.pose, input.publisher);
  else if (input.kind == ConvertedInput::Kind::kGyro)
    sessions.addGyroReading(input.stamp_s, input.raw, input.problem);
  else
    feedEgoMotion(sessions.source(input.source), input);
}

}  // namespace odometry_calibration
