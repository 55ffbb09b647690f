// JointCalibrationSession's wheel inputs: the encoders into every source's session, the wheel
// signals (ticks, joint velocities, a base's own odometry) made joint samples in order, and the
// watch of silent wheel tick topics said by tick().
#include "odometry_calibration/session/joint_calibration_session.h"

#include <chrono>

namespace odometry_calibration {

void JointCalibrationSession::addJointPositions(double stamp_s, const Eigen::VectorXd& raw,
                                                const std::string& publisher)
{
  for (const auto& session : sessions_)
    session->addJointPositions(stamp_s, raw, publisher);
}

void JointCalibrationSession::skipJointState(const std::string& problem,
                                             const std::string& publisher)
{
  for (const auto& session : sessions_)
    session->skipJointState(problem, publisher);
}

void JointCalibrationSession::feedWheelOutput(const WheelSignalOutput& output,
                                              const std::string& publisher)
{
  for (const EncoderSample& sample : output.samples)
    addJointPositions(sample.stamp_s, sample.values, publisher);
  if (!output.problem.empty())
    skipJointState(output.problem, publisher);
}

void JointCalibrationSession::addWheelTick(std::size_t wheel, double stamp_s, double raw,
                                           const std::string& publisher)
{
  // Held while feeding too: the joint samples reach the sessions in the order they were made.
  std::lock_guard<std::mutex> lock(wheel_mutex_);
  if (wheel == 0)
    wheel_publisher_ = publisher;
  if (wheel_watch_)
    wheel_watch_->received(wheel, wallNow());
  feedWheelOutput(wheel_signals_->addTick(wheel, stamp_s, raw), wheel_publisher_);
}

void JointCalibrationSession::addJointVelocities(double stamp_s, const Eigen::VectorXd& velocity,
                                                 const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(wheel_mutex_);
  feedWheelOutput(wheel_signals_->addVelocities(stamp_s, velocity), publisher);
}

void JointCalibrationSession::addBaseOdometry(double stamp_s, const Pose2& T_odom_base,
                                              const std::string& publisher)
{
  std::lock_guard<std::mutex> lock(wheel_mutex_);
  feedWheelOutput(wheel_signals_->addBaseOdometry(stamp_s, T_odom_base), publisher);
}

void JointCalibrationSession::tick()
{
  for (const auto& session : sessions_)
    session->tick();
  if (!wheel_watch_)
    return;
  std::vector<std::string> warnings;
  {
    std::lock_guard<std::mutex> lock(wheel_mutex_);
    warnings = wheel_watch_->silentWarnings(wallNow());
  }
  for (const std::string& warning : warnings) {
    if (options_.log)
      options_.log(SessionLogLevel::kWarn, warning);
  }
}

double JointCalibrationSession::wallNow() const
{
  if (options_.wall_clock)
    return options_.wall_clock();
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

}  // namespace odometry_calibration
