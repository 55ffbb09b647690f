#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/sim/robot.h"

namespace odometry_calibration {
namespace sim {
namespace {

Twist2 stepOnce(const Robot& robot, const Twist2& command, Eigen::VectorXd* joints,
                double dt = 0.01)
{
  return robot.step(command, dt, joints);
}

TEST(SimRobots, IntegrateTwistIsTheExactArc)
{
  // A quarter circle of radius 2: v = 2 w.
  const Pose2 motion = integrateTwist({M_PI, 0.0, M_PI / 2}, 1.0);
  EXPECT_NEAR(motion.x(), 2.0, 1e-12);
  EXPECT_NEAR(motion.y(), 2.0, 1e-12);
  EXPECT_NEAR(motion.theta(), M_PI / 2, 1e-12);
  const Pose2 sideways = integrateTwist({0.0, 0.5, 0.0}, 2.0);
  EXPECT_NEAR(sideways.y(), 1.0, 1e-12);
}

TEST(SimRobots, IdealDiffDriveRealisesTheCommandAndTurnsItsWheels)
{
  const auto robot = makeRobot({"diff_drive",
                                {{"wheel_radius_left_m", 0.07},
                                 {"wheel_radius_right_m", 0.08},
                                 {"wheel_separation_m", 0.4}}});
  Eigen::VectorXd joints = robot->initialJoints();
  const Twist2 twist = stepOnce(*robot, {0.3, 0.0, 0.5}, &joints, 0.1);
  EXPECT_NEAR(twist.vx_mps, 0.3, 1e-12);
  EXPECT_NEAR(twist.vy_mps, 0.0, 1e-12);
  EXPECT_NEAR(twist.omega_radps, 0.5, 1e-12);
  EXPECT_NEAR(joints(0), 0.1 * (0.3 - 0.2 * 0.5) / 0.07, 1e-12);  // left wheel angle [rad]
  EXPECT_NEAR(joints(1), 0.1 * (0.3 + 0.2 * 0.5) / 0.08, 1e-12);
}

TEST(SimRobots, SkidSteerTurnsAsAWiderDiffDrive)
{
  const auto robot = makeRobot({"skid_steer",
                                {{"wheel_radius_m", 0.1},
                                 {"wheel_separation_m", 0.5},
                                 {"effective_separation_factor", 1.5}}});
  ASSERT_EQ(robot->joints().size(), 4u);
  EXPECT_EQ(robot->joints()[1].name, "rear_left_wheel");
  Eigen::VectorXd joints = robot->initialJoints();
  // The controller commands the wheels for the geometric track width; the robot skids and
  // turns 1.5 times slower, at the commanded forward speed.
  const Twist2 twist = stepOnce(*robot, {0.3, 0.0, 0.6}, &joints, 0.1);
  EXPECT_NEAR(twist.vx_mps, 0.3, 1e-12);
  EXPECT_NEAR(twist.vy_mps, 0.0, 1e-12);
  EXPECT_NEAR(twist.omega_radps, 0.6 / 1.5, 1e-12);
  EXPECT_NEAR(joints(0), 0.1 * (0.3 - 0.25 * 0.6) / 0.1, 1e-12);  // front left [rad]
  EXPECT_NEAR(joints(1), joints(0), 1e-12);                       // rear left, chained
  EXPECT_NEAR(joints(2), 0.1 * (0.3 + 0.25 * 0.6) / 0.1, 1e-12);
  EXPECT_NEAR(joints(3), joints(2), 1e-12);
  EXPECT_THROW(makeRobot({"skid_steer", {{"effective_separation_factor", 0.8}}}),
               std::invalid_argument);
}

TEST(SimRobots, SlipShrinksTheRadiusWithSpeed)
{
  // 10 % less at 0.6 m/s of wheel surface speed.
  const auto robot = makeRobot({"diff_drive", {{"slip_per_speed", 0.1 / 0.6}}});
  Eigen::VectorXd joints = robot->initialJoints();
  EXPECT_NEAR(stepOnce(*robot, {0.6, 0.0, 0.0}, &joints).vx_mps, 0.54, 1e-12);
  EXPECT_NEAR(stepOnce(*robot, {0.3, 0.0, 0.0}, &joints).vx_mps, 0.3 * 0.95, 1e-12);
}

TEST(SimRobots, MisalignedAxisDriftsSideways)
{
  const auto robot = makeRobot({"diff_drive", {{"axis_misalignment_rad", 0.1}}});
  Eigen::VectorXd joints = robot->initialJoints();
  const Twist2 twist = stepOnce(*robot, {0.5, 0.0, 0.0}, &joints);
  EXPECT_NEAR(twist.vy_mps, 0.5 * 0.5 * std::sin(0.1), 1e-12);
  EXPECT_NEAR(twist.omega_radps, 0.5 * (1.0 - std::cos(0.1)) / 0.33, 1e-12);
}

TEST(SimRobots, NonCircularWheelRadiusFollowsItsAngle)
{
  const auto robot = makeRobot({"diff_drive", {{"non_circular_amplitude", 0.05}}});
  Eigen::VectorXd joints = robot->initialJoints();  // left wheel at angle 0: radius x 1.05
  const Twist2 at_zero = stepOnce(*robot, {0.2, 0.0, 0.0}, &joints, 1e-9);
  EXPECT_NEAR(at_zero.vx_mps, 0.5 * (0.2 * 1.05 + 0.2), 1e-9);
  joints(0) = M_PI;  // radius x 0.95
  EXPECT_NEAR(stepOnce(*robot, {0.2, 0.0, 0.0}, &joints, 1e-9).vx_mps, 0.5 * (0.2 * 0.95 + 0.2),
              1e-9);
}

TEST(SimRobots, TricycleSteersAtItsRateAndFollowsTheBicycleModel)
{
  const auto robot = makeRobot(
      {"tricycle",
       {{"axis_length_m", 1.5}, {"steering_rate_radps", 1.0}, {"steering_offset_rad", 0.0}}});
  Eigen::VectorXd joints = robot->initialJoints();
  const Twist2 command{0.5, 0.0, 0.5 * std::tan(0.4) / 1.5};  // asks for 0.4 rad of steering
  stepOnce(*robot, command, &joints, 0.1);
  EXPECT_NEAR(joints(0), 0.1, 1e-12);  // rate-limited
  for (int i = 0; i < 10; ++i)
    stepOnce(*robot, command, &joints, 0.1);
  EXPECT_NEAR(joints(0), 0.4, 1e-12);
  const Twist2 twist = stepOnce(*robot, command, &joints, 0.1);
  EXPECT_NEAR(twist.vx_mps, 0.5, 1e-12);
  EXPECT_NEAR(twist.omega_radps, command.omega_radps, 1e-12);
  // The steering encoder sees (alpha - offset) / Ks.
  EXPECT_NEAR(robot->encoderAngles(joints)(0), 0.4 / 0.56, 1e-12);
  EXPECT_FALSE(robot->canTurnInPlace());
}

TEST(SimRobots, MecanumDrivesSideways)
{
  const auto robot = makeRobot({"mecanum", {}});
  Eigen::VectorXd joints = robot->initialJoints();
  const Twist2 twist = stepOnce(*robot, {0.1, 0.3, -0.2}, &joints);
  EXPECT_NEAR(twist.vx_mps, 0.1, 1e-12);
  EXPECT_NEAR(twist.vy_mps, 0.3, 1e-12);
  EXPECT_NEAR(twist.omega_radps, -0.2, 1e-12);
  EXPECT_EQ(robot->joints().size(), 4u);
}

TEST(SimRobots, BadParametersAreNamed)
{
  auto message = [](const RobotOptions& options) -> std::string {
    try {
      makeRobot(options);
    } catch (const std::invalid_argument& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(message({"hovercraft", {}}).find("hovercraft"), std::string::npos);
  EXPECT_NE(message({"diff_drive", {{"wheel_radius_m", 0.1}}}).find("wheel_radius_m"),
            std::string::npos);
  EXPECT_NE(message({"diff_drive", {{"wheel_separation_m", -0.3}}}).find("wheel_separation_m"),
            std::string::npos);
  EXPECT_NE(message({"tricycle", {{"max_steering_rad", 2.0}}}).find("max_steering_rad"),
            std::string::npos);
}

}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
