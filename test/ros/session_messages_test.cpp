#include "odometry_calibration/ros/session_messages.h"

#include <cmath>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace ros_conversions {
namespace {

TEST(SessionMessages, OdometryPutsTheCovarianceInRowsXYAndYaw)
{
  OdometryState state;
  state.stamp_s = 12.5;
  state.pose = Pose2(1.0, -2.0, 0.5);
  state.tracks_base = true;
  state.covariance << 1.0, 0.1, 0.2, 0.1, 2.0, 0.3, 0.2, 0.3, 3.0;
  state.velocity = Eigen::Vector3d(0.4, 0.05, -0.2);
  state.velocity_covariance = 0.01 * Eigen::Matrix3d::Identity();
  const nav_msgs::Odometry msg = toOdometryMsg(state, "odom", "base_link");
  EXPECT_DOUBLE_EQ(msg.header.stamp.toSec(), 12.5);
  EXPECT_EQ(msg.header.frame_id, "odom");
  EXPECT_EQ(msg.child_frame_id, "base_link");
  EXPECT_DOUBLE_EQ(msg.pose.pose.position.x, 1.0);
  EXPECT_DOUBLE_EQ(msg.pose.pose.position.y, -2.0);
  EXPECT_NEAR(2.0 * std::atan2(msg.pose.pose.orientation.z, msg.pose.pose.orientation.w), 0.5,
              1e-12);
  // (x, y, yaw) are ROS's rows and columns 0, 1, 5 of the 6x6.
  EXPECT_DOUBLE_EQ(msg.pose.covariance[0], 1.0);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[1], 0.1);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[5], 0.2);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[7], 2.0);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[11], 0.3);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[30], 0.2);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[35], 3.0);
  // z, roll and pitch are not estimated: a large variance, no correlation.
  for (int i : {2, 3, 4})
    EXPECT_DOUBLE_EQ(msg.pose.covariance[7 * i], 1e6);
  EXPECT_DOUBLE_EQ(msg.pose.covariance[2], 0.0);
  EXPECT_DOUBLE_EQ(msg.twist.twist.linear.x, 0.4);
  EXPECT_DOUBLE_EQ(msg.twist.twist.linear.y, 0.05);
  EXPECT_DOUBLE_EQ(msg.twist.twist.angular.z, -0.2);
  EXPECT_DOUBLE_EQ(msg.twist.covariance[35], 0.01);
}

TEST(SessionMessages, OdometryBeforeTheClockStartsIsStampedZero)
{
  OdometryState state;
  state.stamp_s = -0.3;  // an encoder stamp minus a time offset larger than it
  EXPECT_DOUBLE_EQ(toOdometryMsg(state, "odom", "laser").header.stamp.toSec(), 0.0);
}

TEST(SessionMessages, PathKeepsEveryPoseAndItsStamp)
{
  const std::vector<StampedPose2> poses = {{1.0, Pose2(0.0, 0.0, 0.0)},
                                           {2.0, Pose2(1.0, 0.5, 0.1)}};
  const nav_msgs::Path path = toPathMsg(poses, "odom", ros::Time(7.0));
  ASSERT_EQ(path.poses.size(), 2u);
  EXPECT_EQ(path.header.frame_id, "odom");
  EXPECT_DOUBLE_EQ(path.header.stamp.toSec(), 7.0);
  EXPECT_DOUBLE_EQ(path.poses[1].header.stamp.toSec(), 2.0);
  EXPECT_DOUBLE_EQ(path.poses[1].pose.position.y, 0.5);
}

TEST(SessionMessages, StatusKeepsLevelMessageAndValues)
{
  SessionStatusReport report;
  report.name = "encoders";
  report.level = SessionStatusReport::Level::kWarn;
  report.message = "stuck";
  report.values = {{"rate_hz", "49.8"}, {"glitches", "3"}};
  const diagnostic_msgs::DiagnosticStatus status =
      toDiagnosticStatus(report, "/node: encoders", "base_link");
  EXPECT_EQ(status.name, "/node: encoders");
  EXPECT_EQ(status.hardware_id, "base_link");
  EXPECT_EQ(status.level, diagnostic_msgs::DiagnosticStatus::WARN);
  EXPECT_EQ(status.message, "stuck");
  ASSERT_EQ(status.values.size(), 2u);
  EXPECT_EQ(status.values[1].key, "glitches");
  EXPECT_EQ(status.values[1].value, "3");
  report.level = SessionStatusReport::Level::kError;
  EXPECT_EQ(toDiagnosticStatus(report, "", "").level, diagnostic_msgs::DiagnosticStatus::ERROR);
  report.level = SessionStatusReport::Level::kOk;
  EXPECT_EQ(toDiagnosticStatus(report, "", "").level, diagnostic_msgs::DiagnosticStatus::OK);
}

TEST(SessionMessages, GuidanceMarkerColourSaysTheState)
{
  const GuidanceMarkerStyle style{"base_link", 1.2, 0.3};
  AssistantMarker state;
  state.text = "drive straight 2 m";
  const visualization_msgs::Marker collecting = toGuidanceMarker(state, style, ros::Time(3.0));
  EXPECT_EQ(collecting.header.frame_id, "base_link");
  EXPECT_EQ(collecting.type, visualization_msgs::Marker::TEXT_VIEW_FACING);
  EXPECT_DOUBLE_EQ(collecting.pose.position.z, 1.2);
  EXPECT_DOUBLE_EQ(collecting.scale.z, 0.3);
  EXPECT_EQ(collecting.text, "drive straight 2 m");
  EXPECT_FLOAT_EQ(collecting.color.r, 0.8f);  // orange
  EXPECT_FLOAT_EQ(collecting.color.g, 0.4f);
  state.ready = true;
  const visualization_msgs::Marker ready = toGuidanceMarker(state, style, ros::Time(3.0));
  EXPECT_FLOAT_EQ(ready.color.r, 0.0f);  // green
  EXPECT_FLOAT_EQ(ready.color.g, 0.5f);
  state.alarm = true;
  const visualization_msgs::Marker alarm = toGuidanceMarker(state, style, ros::Time(3.0));
  EXPECT_FLOAT_EQ(alarm.color.r, 0.85f);  // red: the calibration is stale
  EXPECT_FLOAT_EQ(alarm.color.g, 0.0f);
}

}  // namespace
}  // namespace ros_conversions
}  // namespace odometry_calibration
