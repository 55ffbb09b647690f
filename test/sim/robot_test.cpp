#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/SVD>

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

TEST(SimRobots, TurnSlipTurnsLessThanTheWheelsSay)
{
  // k = 0.05 s/rad: a turn at w loses 0.05 |w| of it (3 % at 0.6 rad/s on diff_drive), the
  // wheels and the translation as commanded.
  for (const char* type : {"diff_drive", "skid_steer", "mecanum"}) {
    const auto ideal = makeRobot({type, {}});
    const auto slipping = makeRobot({type, {{"turn_slip_per_radps", 0.05}}});
    Eigen::VectorXd ideal_joints = ideal->initialJoints(), joints = slipping->initialJoints();
    const Twist2 wheels = stepOnce(*ideal, {0.3, 0.0, -0.6}, &ideal_joints);
    const Twist2 twist = stepOnce(*slipping, {0.3, 0.0, -0.6}, &joints);
    EXPECT_NEAR(twist.omega_radps, wheels.omega_radps * (1.0 - 0.05 * std::abs(wheels.omega_radps)),
                1e-12)
        << type;
    EXPECT_NEAR(twist.vx_mps, wheels.vx_mps, 1e-12) << type;
    EXPECT_EQ(joints, ideal_joints) << type;
    EXPECT_EQ(slipping->trueParameters().at("turn_slip_per_radps"), 0.05);
  }
  const auto spinning = makeRobot({"diff_drive", {{"turn_slip_per_radps", 1.0}}});
  Eigen::VectorXd joints = spinning->initialJoints();
  EXPECT_EQ(stepOnce(*spinning, {0.0, 0.0, 2.0}, &joints).omega_radps, 0.0);  // never backwards
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

/// The twist a mecanum robot realises from wheel surface speeds `s` (FL, FR, RL, RR) when wheel
/// `k` is yawed by `yaw` and tilted by `tilt` [rad], built here from the description (contact
/// constraints n_i . (v + w x p_i) = s_i, n_i the roller axis on the ground) and solved by SVD.
Eigen::Vector3d leastSquaresTwist(const Eigen::Vector4d& s, int k, double yaw, double tilt)
{
  const double lx = 0.15, ly = 0.2;
  const Eigen::Vector2d p[4] = {{lx, ly}, {lx, -ly}, {-lx, ly}, {-lx, -ly}};
  const Eigen::Vector2d n0[4] = {{1, -1}, {1, 1}, {1, 1}, {1, -1}};
  Eigen::Matrix<double, 4, 3> a;
  Eigen::Vector4d b = s;
  for (int i = 0; i < 4; ++i) {
    Eigen::Vector2d n = n0[i];
    if (i == k) {
      n.y() *= std::cos(tilt);
      n = Eigen::Vector2d(std::cos(yaw) * n.x() - std::sin(yaw) * n.y(),
                          std::sin(yaw) * n.x() + std::cos(yaw) * n.y());
      b(i) *= std::cos(tilt);
    }
    a.row(i) << n.x(), n.y(), p[i].x() * n.y() - p[i].y() * n.x();
  }
  return a.jacobiSvd(Eigen::ComputeThinU | Eigen::ComputeThinV).solve(b);
}

TEST(SimRobots, MecanumDeformationsT1AndT2RealiseTheLeastSquaresTwist)
{
  const Twist2 command{0.3, 0.1, 0.4};
  const double w = 0.35 * command.omega_radps;
  // Surface speeds of the nominal inverse kinematics (the controller knows no deformation).
  const Eigen::Vector4d s(command.vx_mps - command.vy_mps - w, command.vx_mps + command.vy_mps + w,
                          command.vx_mps + command.vy_mps - w, command.vx_mps - command.vy_mps + w);
  for (int wheel = 0; wheel < 4; ++wheel) {
    const auto yawed = makeRobot(
        {"mecanum", {{"axis_yaw_deg", 6.0}, {"deformed_wheel", static_cast<double>(wheel)}}});
    Eigen::VectorXd joints = yawed->initialJoints();
    const Twist2 t1 = stepOnce(*yawed, command, &joints);
    const Eigen::Vector3d expected1 = leastSquaresTwist(s, wheel, 6.0 * M_PI / 180, 0.0);
    EXPECT_NEAR(t1.vx_mps, expected1(0), 1e-12);
    EXPECT_NEAR(t1.vy_mps, expected1(1), 1e-12);
    EXPECT_NEAR(t1.omega_radps, expected1(2), 1e-12);
    const auto tilted = makeRobot(
        {"mecanum", {{"wheel_tilt_deg", 20.0}, {"deformed_wheel", static_cast<double>(wheel)}}});
    joints = tilted->initialJoints();
    const Twist2 t2 = stepOnce(*tilted, command, &joints);
    const Eigen::Vector3d expected2 = leastSquaresTwist(s, wheel, 0.0, 20.0 * M_PI / 180);
    EXPECT_NEAR(t2.vx_mps, expected2(0), 1e-12);
    EXPECT_NEAR(t2.vy_mps, expected2(1), 1e-12);
    EXPECT_NEAR(t2.omega_radps, expected2(2), 1e-12);
    // The wheels turn as commanded: the deformation is in the motion, not in the encoders.
    EXPECT_NEAR(joints(wheel), 0.01 * s(wheel) / 0.05, 1e-12);
  }
  // The deformation matters: 6 deg of yaw moves the twist by more than 1 % of the speed ...
  const auto yawed = makeRobot({"mecanum", {{"axis_yaw_deg", 6.0}}});
  Eigen::VectorXd joints = yawed->initialJoints();
  const Twist2 t1 = stepOnce(*yawed, {0.3, 0.0, 0.0}, &joints);
  EXPECT_GT(std::abs(t1.vy_mps) + 0.35 * std::abs(t1.omega_radps), 0.003);
  // ... and a slower tilted front-left wheel turns the robot to the left, drifting left.
  const auto tilted = makeRobot({"mecanum", {{"wheel_tilt_deg", 20.0}}});
  joints = tilted->initialJoints();
  const Twist2 t2 = stepOnce(*tilted, {0.3, 0.0, 0.0}, &joints);
  EXPECT_GT(t2.omega_radps, 0.01);
  EXPECT_GT(t2.vy_mps, 0.0);
  // Vanishing deformations give the undeformed robot's twist.
  const auto ideal = makeRobot({"mecanum", {}});
  const auto tiny = makeRobot({"mecanum", {{"axis_yaw_deg", 1e-9}}});
  Eigen::VectorXd a = ideal->initialJoints(), b = tiny->initialJoints();
  const Twist2 ta = stepOnce(*ideal, command, &a), tb = stepOnce(*tiny, command, &b);
  EXPECT_NEAR(ta.vx_mps, tb.vx_mps, 1e-9);
  EXPECT_NEAR(ta.vy_mps, tb.vy_mps, 1e-9);
  EXPECT_NEAR(ta.omega_radps, tb.omega_radps, 1e-9);
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
  EXPECT_NE(message({"mecanum", {{"deformed_wheel", 4.0}}}).find("deformed_wheel"),
            std::string::npos);
  EXPECT_NE(message({"mecanum", {{"axis_yaw_deg", 50.0}}}).find("axis_yaw_deg"), std::string::npos);
  EXPECT_NE(message({"mecanum", {{"axis_misalignment_rad", 0.1}}}).find("axis_yaw_deg"),
            std::string::npos);
  EXPECT_NE(message({"diff_drive", {{"turn_slip_per_radps", -0.1}}}).find("turn_slip_per_radps"),
            std::string::npos);
  EXPECT_NE(message({"tricycle", {{"turn_slip_per_radps", 1.5}}}).find("in [0, 1] s/rad, got 1.5"),
            std::string::npos);
}

}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
