// Helpers of the node's replay rostests: the corrected odometry's end position against the
// simulator's ground truth, next to the nominal odometry's over the same run.
#pragma once

#include <cmath>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <nav_msgs/Path.h>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/ros/conversions.h"

namespace odometry_calibration {
namespace test {

/// A pose with its stamp [s].
struct Stamped
{
  double stamp_s;
  Pose2 pose;
};

/// The entry of a non-empty `poses` nearest in time to `stamp_s`.
inline Pose2 nearest(const std::vector<Stamped>& poses, double stamp_s)
{
  const Stamped* best = &poses.front();
  for (const Stamped& entry : poses)
    if (std::abs(entry.stamp_s - stamp_s) < std::abs(best->stamp_s - stamp_s))
      best = &entry;
  return best->pose;
}

/// Where two odometries end against the truth, at the stamp of the corrected one's last pose.
struct EndErrors
{
  double distance_m = 0.0;         ///< path length of the truth up to that stamp
  double corrected_error_m = 0.0;  ///< |position error| of the corrected odometry's last pose
  double nominal_error_m = 0.0;    ///< |position error| of the nominal odometry there
};

/// Both odometries start at the origin (odom = the truth's first pose): errors are measured in
/// the truth's first frame, e = |between(truth_start^-1 truth(t1), odometry(t1))|. All three
/// vectors must be non-empty.
inline EndErrors endErrors(const std::vector<Stamped>& corrected,
                           const std::vector<Stamped>& ground_truth,
                           const std::vector<Stamped>& nominal)
{
  const double t1 = corrected.back().stamp_s;
  const Pose2 truth_end = between(ground_truth.front().pose, nearest(ground_truth, t1));
  auto error = [&](const Pose2& pose) {
    const Pose2 e = between(truth_end, pose);
    return std::hypot(e.x(), e.y());
  };
  EndErrors result;
  result.corrected_error_m = error(corrected.back().pose);
  result.nominal_error_m = error(nearest(nominal, t1));
  for (std::size_t i = 1; i < ground_truth.size() && ground_truth[i].stamp_s <= t1; ++i) {
    const Pose2 step = between(ground_truth[i - 1].pose, ground_truth[i].pose);
    result.distance_m += std::hypot(step.x(), step.y());
  }
  return result;
}

/// The check every replay test makes once the player has ended: ~odom after the fit (entries
/// later than `fit_stamp_s`, integrated again from the start with the fitted model) ends within
/// 0.5 % of the distance travelled (> 10 m) from the truth, and at most a tenth of the nominal
/// odometry's (~path/nominal) end error. The three numbers are recorded as test properties.
inline void expectCorrectedOdometryEndsNearTheTruth(const std::vector<Stamped>& odometry,
                                                    double fit_stamp_s,
                                                    const std::vector<Stamped>& ground_truth,
                                                    const nav_msgs::Path& nominal_path)
{
  std::vector<Stamped> after;
  for (const Stamped& entry : odometry)
    if (entry.stamp_s > fit_stamp_s)
      after.push_back(entry);
  ASSERT_GT(after.size(), 500u);
  ASSERT_FALSE(ground_truth.empty());
  ASSERT_GT(nominal_path.poses.size(), 100u);
  std::vector<Stamped> nominal;
  for (const auto& pose : nominal_path.poses)
    nominal.push_back({pose.header.stamp.toSec(), ros_conversions::fromPoseMsg(pose.pose)});
  const EndErrors end = endErrors(after, ground_truth, nominal);
  ::testing::Test::RecordProperty("distance_m", std::to_string(end.distance_m));
  ::testing::Test::RecordProperty("corrected_end_error_m", std::to_string(end.corrected_error_m));
  ::testing::Test::RecordProperty("nominal_end_error_m", std::to_string(end.nominal_error_m));
  EXPECT_GT(end.distance_m, 10.0);
  EXPECT_LT(end.corrected_error_m, 0.005 * end.distance_m);
  EXPECT_LT(end.corrected_error_m, 0.1 * end.nominal_error_m);
}

}  // namespace test
}  // namespace odometry_calibration
