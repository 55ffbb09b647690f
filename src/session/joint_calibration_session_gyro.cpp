// JointCalibrationSession's gyro (gyro.topic): its readings into the gyro's source, watch and
// heading odometry, its fit after each ~calibrate, result.yaml with its block, and source 0's
// listener wrapped for the watch (pairs) and gyro.odom_heading (odometry).
#include "odometry_calibration/session/joint_calibration_session.h"

#include <filesystem>

#include "odometry_calibration/report/calibration_files.h"

namespace odometry_calibration {

SessionListener JointCalibrationSession::withGyro(SessionListener listener)
{
  if (gyro_health_)  // the gyro is fitted against source 0's pairs
    listener.pair = gyroWatchingPairs(std::move(listener.pair));
  if (gyro_heading_)  // only source 0's session integrates the odometry
    listener.odometry = gyroHeadingOdometry(std::move(listener.odometry));
  return listener;
}

std::function<void(const MotionPair&)> JointCalibrationSession::gyroWatchingPairs(
    std::function<void(const MotionPair&)> forward)
{
  return [this, forward = std::move(forward)](const MotionPair& pair) {
    gyro_health_->addPair(pair);
    if (forward)
      forward(pair);
  };
}

std::function<void(const OdometryState&)> JointCalibrationSession::gyroHeadingOdometry(
    std::function<void(const OdometryState&)> forward)
{
  return [this, forward = std::move(forward)](const OdometryState& state) {
    const OdometryState turned = gyro_heading_->apply(state);
    if (forward)
      forward(turned);
  };
}

std::string JointCalibrationSession::addGyroReading(double stamp_s,
                                                    const Eigen::VectorXd& angular_velocity,
                                                    const std::string& problem)
{
  if (!gyro_)
    return "an IMU reading without gyro.topic configured: set gyro.topic to use the gyro";
  if (!problem.empty())
    return gyro_->refuse(problem);
  if (angular_velocity.size() != 3)
    return gyro_->refuse("gyro reading with " + std::to_string(angular_velocity.size()) +
                         " angular velocity components, not 3");
  std::string problem_found = gyro_->add(stamp_s, angular_velocity);
  if (!problem_found.empty())
    return problem_found;
  const double yaw_rate_rad_s =
      gyroYawRate(angular_velocity.head<3>(), config_.gyro.roll_rad, config_.gyro.pitch_rad);
  if (gyro_health_)
    gyro_health_->addReading(stamp_s, yaw_rate_rad_s);
  if (gyro_heading_)
    gyro_heading_->addReading(stamp_s, yaw_rate_rad_s);  // kept by gyro_: finite, increasing
  return "";
}

void JointCalibrationSession::fitGyro(JointCalibrateOutcome* result)
{
  if (!gyro_)
    return;
  const std::vector<MotionPair>* pairs = nullptr;
  double pairs_time_offset_s = 0.0;
  if (!result->inputs.empty()) {
    pairs = &result->inputs.front().pairs;
    pairs_time_offset_s = result->inputs.front().time_offset_s;
  } else if (result->outcome.fit) {
    pairs = &result->outcome.fit->job.pairs;
    pairs_time_offset_s = result->outcome.fit->job.time_offset_s;
  }
  if (pairs == nullptr)
    return;
  result->gyro = gyro_->fit(*pairs, pairs_time_offset_s);
  gyro_fit_ = result->gyro;
  if (gyro_health_)
    gyro_health_->watch(*result->gyro);
  std::string line = gyroFitText(*result->gyro);
  if (gyro_heading_) {
    const std::string refused = gyro_heading_->setCalibration(*result->gyro);
    line += refused.empty()
                ? "; ~odom's heading from the gyro (gyro.odom_heading)"
                : "; ~odom's heading " +
                      std::string(gyro_heading_->calibrated() ? "from the gyro's previous fit: "
                                                              : "from the wheels: ") +
                      refused;
  }
  if (gyro_->refused() > 0) {
    line += "; " + std::to_string(gyro_->refused()) +
            " readings refused, the first: " + gyro_->firstProblem();
  }
  result->outcome.message += (result->outcome.message.empty() ? "" : "\n") + line;
}

std::pair<bool, std::string> JointCalibrationSession::saveWithGyro() const
{
  const std::string& directory = options_.output_directory;
  if (directory.empty())
    return {false, "nothing to save: the session has no output directory"};
  try {
    FileSet files = sessions_.front()->filesToSave();
    appendGyroResult(&files, *gyro_fit_, config_.gyro.topic);
    writeFileSet(directory, files);  // all replaced, or none
    std::string list;
    for (const auto& [name, content] : files.written)
      list += (list.empty() ? "" : ", ") + name;
    return {true, "saved the fit and the gyro's in " +
                      std::filesystem::absolute(directory).lexically_normal().string() + ": " +
                      list};
  } catch (const std::exception& error) {
    const std::string what = error.what();
    return {false, what.rfind("nothing to save", 0) == 0 ? what : "cannot save: " + what};
  }
}

}  // namespace odometry_calibration
