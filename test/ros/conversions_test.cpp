#include "odometry_calibration/ros/conversions.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace ros_conversions {
namespace {

// Difference of two angles wrapped to [-pi, pi].
double angleDifference(double a, double b)
{
  return std::remainder(a - b, 2.0 * M_PI);
}

geometry_msgs::Transform transformWithRotation(double x, double y, double z, double w)
{
  geometry_msgs::Transform transform;
  transform.translation.x = 1.5;
  transform.translation.y = -2.5;
  transform.rotation.x = x;
  transform.rotation.y = y;
  transform.rotation.z = z;
  transform.rotation.w = w;
  return transform;
}

template <typename Function>
std::string invalidArgumentMessage(Function function)
{
  try {
    function();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  ADD_FAILURE() << "expected std::invalid_argument";
  return "";
}

TEST(RosConversionsTest, TransformRoundTrip)
{
  const std::vector<Pose2> poses{Pose2(0.0, 0.0, 0.0),           Pose2(1.0, -2.0, 0.7),
                                 Pose2(-3.5, 0.25, -1.2),        Pose2(0.1, 0.2, M_PI),
                                 Pose2(0.1, 0.2, -M_PI),         Pose2(4.0, 5.0, M_PI - 1e-9),
                                 Pose2(-4.0, -5.0, -M_PI + 1e-9)};
  for (const Pose2& pose : poses) {
    const geometry_msgs::Transform message = toTransformMsg(pose);
    EXPECT_EQ(message.translation.z, 0.0);
    EXPECT_EQ(message.rotation.x, 0.0);
    EXPECT_EQ(message.rotation.y, 0.0);
    const Pose2 back = fromTransformMsg(message);
    EXPECT_DOUBLE_EQ(back.x(), pose.x());
    EXPECT_DOUBLE_EQ(back.y(), pose.y());
    EXPECT_NEAR(angleDifference(back.theta(), pose.theta()), 0.0, 1e-12) << pose.theta();
    EXPECT_LE(std::abs(back.theta()), M_PI);
  }
}

TEST(RosConversionsTest, HandBuiltQuaternionGivesYaw)
{
  const Pose2 pose = fromTransformMsg(transformWithRotation(0, 0, std::sin(0.35), std::cos(0.35)));
  EXPECT_EQ(pose.x(), 1.5);
  EXPECT_EQ(pose.y(), -2.5);
  EXPECT_NEAR(pose.theta(), 0.7, 1e-12);
  const Pose2 negative =
      fromTransformMsg(transformWithRotation(0, 0, -std::sin(1.0), std::cos(1.0)));
  EXPECT_NEAR(negative.theta(), -2.0, 1e-12);
}

TEST(RosConversionsTest, NonNormalisedQuaternionGivesSameYaw)
{
  const double z = 2.0 * std::sin(0.35), w = 2.0 * std::cos(0.35);
  EXPECT_NEAR(fromTransformMsg(transformWithRotation(0, 0, z, w)).theta(), 0.7, 1e-12);
  // Scaled by 0.1 and negated (q and -q are the same rotation).
  EXPECT_NEAR(fromTransformMsg(transformWithRotation(0, 0, -0.05 * z, -0.05 * w)).theta(), 0.7,
              1e-12);
}

TEST(RosConversionsTest, InvalidQuaternionThrows)
{
  EXPECT_THROW(fromTransformMsg(transformWithRotation(0, 0, 0, 0)), std::invalid_argument);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_THROW(fromTransformMsg(transformWithRotation(0, 0, nan, 1)), std::invalid_argument);
}

TEST(RosConversionsTest, PoseMsgMatchesTransformMsg)
{
  const Pose2 pose(2.0, -0.5, -2.3);
  const geometry_msgs::Transform transform = toTransformMsg(pose);
  const geometry_msgs::Pose message = toPoseMsg(pose);
  EXPECT_EQ(message.position.x, transform.translation.x);
  EXPECT_EQ(message.position.y, transform.translation.y);
  EXPECT_EQ(message.position.z, 0.0);
  EXPECT_EQ(message.orientation.x, transform.rotation.x);
  EXPECT_EQ(message.orientation.y, transform.rotation.y);
  EXPECT_EQ(message.orientation.z, transform.rotation.z);
  EXPECT_EQ(message.orientation.w, transform.rotation.w);
  EXPECT_NEAR(message.orientation.z, std::sin(-1.15), 1e-15);
  EXPECT_NEAR(message.orientation.w, std::cos(-1.15), 1e-15);
}

std::vector<EncoderChannelOptions> channels(const std::vector<std::string>& names)
{
  std::vector<EncoderChannelOptions> result(names.size());
  for (std::size_t i = 0; i < names.size(); ++i)
    result[i].name = names[i];
  result.back().kind = EncoderKind::kAbsolute;
  return result;
}

TEST(RosConversionsTest, RawJointPositionsPicksJointsByName)
{
  sensor_msgs::JointState message;
  message.name = {"caster", "steer", "left_wheel", "traction"};
  message.position = {9.0, -0.4, 3.0, 1234.0};
  const Eigen::VectorXd raw = rawJointPositions(message, channels({"traction", "steer"}));
  ASSERT_EQ(raw.size(), 2);
  EXPECT_EQ(raw(0), 1234.0);
  EXPECT_EQ(raw(1), -0.4);
}

TEST(RosConversionsTest, RawJointPositionsLengthMismatchNamesBothSizes)
{
  sensor_msgs::JointState message;
  message.name = {"a", "b", "c", "d"};
  message.position = {1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0};
  const std::string what =
      invalidArgumentMessage([&] { rawJointPositions(message, channels({"a"})); });
  EXPECT_NE(what.find('4'), std::string::npos) << what;
  EXPECT_NE(what.find('7'), std::string::npos) << what;
}

TEST(RosConversionsTest, RawJointPositionsMissingJointIsNamed)
{
  sensor_msgs::JointState message;
  message.name = {"traction", "left_wheel"};
  message.position = {1.0, 2.0};
  const std::string what = invalidArgumentMessage([&] {
    rawJointPositions(message, channels({"traction", "steering_joint"}));
  });
  // The configured joint missing, and the joints the message has.
  EXPECT_EQ(what,
            "JointState lacks the configured joint 'steering_joint': it has 'traction', "
            "'left_wheel'");
}

TEST(RosConversionsTest, RawJointPositionsNonFiniteValueIsNamed)
{
  sensor_msgs::JointState message;
  message.name = {"traction", "steering_joint"};
  message.position = {1.0, std::numeric_limits<double>::quiet_NaN()};
  const std::string what = invalidArgumentMessage([&] {
    rawJointPositions(message, channels({"traction", "steering_joint"}));
  });
  EXPECT_NE(what.find("steering_joint"), std::string::npos) << what;
  message.position[1] = std::numeric_limits<double>::infinity();
  EXPECT_THROW(rawJointPositions(message, channels({"traction", "steering_joint"})),
               std::invalid_argument);
}

}  // namespace
}  // namespace ros_conversions
}  // namespace odometry_calibration
