#include "odometry_calibration/eval/tum_trajectory.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace odometry_calibration {

std::string tumTrajectoryText(const std::vector<double>& stamps_s, const std::vector<Pose2>& poses)
{
  if (stamps_s.size() != poses.size())
    throw std::invalid_argument("a TUM trajectory needs one stamp per pose");
  std::string text;
  char line[200];
  for (std::size_t k = 0; k < poses.size(); ++k) {
    const Pose2& pose = poses[k];
    if (!std::isfinite(stamps_s[k]) || !std::isfinite(pose.x()) || !std::isfinite(pose.y()) ||
        !std::isfinite(pose.theta())) {
      throw std::invalid_argument("a TUM trajectory's pose " + std::to_string(k) +
                                  " is not finite");
    }
    if (k > 0 && !(stamps_s[k] > stamps_s[k - 1])) {
      throw std::invalid_argument("a TUM trajectory's stamps must increase: pose " +
                                  std::to_string(k) + " at " + std::to_string(stamps_s[k]) +
                                  " s follows " + std::to_string(stamps_s[k - 1]) + " s");
    }
    const double half = 0.5 * pose.theta();
    std::snprintf(line, sizeof(line), "%.9f %.9f %.9f 0 0 0 %.12f %.12f\n", stamps_s[k], pose.x(),
                  pose.y(), std::sin(half), std::cos(half));
    text += line;
  }
  return text;
}

std::vector<Pose2> baseTrajectory(const std::vector<Pose2>& sensor_poses,
                                  const Pose2& T_base_sensor)
{
  const Pose2 T_sensor_base = T_base_sensor.inverse();
  std::vector<Pose2> base;
  base.reserve(sensor_poses.size());
  for (const Pose2& sensor : sensor_poses)
    base.push_back(T_base_sensor * sensor * T_sensor_base);
  return base;
}

std::vector<std::pair<std::string, std::string>> tumTrajectoryFiles(
    const std::vector<ModelScore>& scores)
{
  std::vector<std::pair<std::string, std::string>> files;
  const ModelScore* reference = nullptr;
  for (const ModelScore& score : scores) {
    if (score.predicted.empty())
      continue;  // skipped
    files.emplace_back(score.model + ".sensor.tum",
                       tumTrajectoryText(score.stamps_s, score.predicted));
    if (score.T_base_sensor) {
      files.emplace_back(
          score.model + ".base_link.tum",
          tumTrajectoryText(score.stamps_s, baseTrajectory(score.predicted, *score.T_base_sensor)));
    }
    if (!reference) {
      reference = &score;
      files.emplace_back("scan_matched.tum", tumTrajectoryText(score.stamps_s, score.measured));
    } else if (score.stamps_s != reference->stamps_s) {
      files.emplace_back(score.model + ".scan_matched.tum",
                         tumTrajectoryText(score.stamps_s, score.measured));
    }
  }
  return files;
}

}  // namespace odometry_calibration
