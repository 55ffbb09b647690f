#include <cmath>

#include <gtest/gtest.h>
#include <Eigen/LU>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {
namespace {

void expectPoseNear(const Pose2& a, const Pose2& b, double tolerance = 1e-12)
{
  EXPECT_NEAR(a.x(), b.x(), tolerance);
  EXPECT_NEAR(a.y(), b.y(), tolerance);
  EXPECT_NEAR(normalizeAngle(a.theta() - b.theta()), 0.0, tolerance);
}

TEST(Se2, ComposeMatchesTheRotoTranslationOperator)
{
  // Paper Table I: a ⊕ b = (ax + bx cos at - by sin at, ay + bx sin at + by cos at, at + bt).
  const Pose2 a(1.0, 2.0, M_PI / 2);
  const Pose2 b(0.5, 0.25, 0.1);
  expectPoseNear(a * b, Pose2(1.0 - 0.25, 2.0 + 0.5, M_PI / 2 + 0.1));
}

TEST(Se2, CompositionOrderFollowsTheFrames)
{
  // T_w_b then T_b_c: c sits 1 m ahead of b, b is turned left by 90 degrees at (2, 0).
  const Pose2 T_w_b(2.0, 0.0, M_PI / 2);
  const Pose2 T_b_c(1.0, 0.0, 0.0);
  expectPoseNear(T_w_b * T_b_c, Pose2(2.0, 1.0, M_PI / 2));
  // The other order is a different motion.
  expectPoseNear(T_b_c * T_w_b, Pose2(3.0, 0.0, M_PI / 2));
}

TEST(Se2, CompositionMatchesHomogeneousMatrices)
{
  const Pose2 a(0.3, -1.2, 2.9);
  const Pose2 b(-0.7, 0.4, 1.1);
  const Eigen::Matrix3d product = a.matrix() * b.matrix();
  EXPECT_TRUE(product.isApprox((a * b).matrix(), 1e-12));
}

TEST(Se2, InverseUndoesTheMotion)
{
  const Pose2 a(0.3, -1.2, 2.9);
  expectPoseNear(a * a.inverse(), Pose2());
  expectPoseNear(a.inverse() * a, Pose2());
  // Paper Table I: ⊖a = (-ax cos at - ay sin at, ax sin at - ay cos at, -at).
  const double c = std::cos(2.9), s = std::sin(2.9);
  expectPoseNear(a.inverse(), Pose2(-0.3 * c + 1.2 * s, 0.3 * s + 1.2 * c, -2.9));
}

TEST(Se2, BetweenIsTheRelativeMotion)
{
  const Pose2 T_w_a(1.0, 1.0, 0.5);
  const Pose2 T_a_b(0.2, -0.1, 0.3);
  expectPoseNear(between(T_w_a, T_w_a * T_a_b), T_a_b);
}

TEST(Se2, AnglesWrapIntoMinusPiPi)
{
  const Pose2 a(0.0, 0.0, 3.0);
  const Pose2 b = a * a;  // 6 rad
  EXPECT_NEAR(b.theta(), 6.0 - 2.0 * M_PI, 1e-12);
  EXPECT_LE(std::abs(normalizeAngle(7.5)), M_PI);
  EXPECT_NEAR(normalizeAngle(-3.5), -3.5 + 2.0 * M_PI, 1e-12);
}

TEST(Se2, PlainDoubleWrapAgreesWithTheTrigonometricOne)
{
  // The double overload (no trigonometry) against the template every scalar type uses.
  for (double angle = -40.0; angle <= 40.0; angle += 0.0137) {
    const double fast = normalizeAngle(angle);
    const double trig = normalizeAngle<double>(angle);
    EXPECT_GT(fast, -M_PI);
    EXPECT_LE(fast, M_PI);
    EXPECT_NEAR(std::remainder(fast - trig, 2.0 * M_PI), 0.0, 1e-12) << angle;
  }
  EXPECT_DOUBLE_EQ(normalizeAngle(0.25), 0.25);  // in range: untouched
  EXPECT_NEAR(normalizeAngle(3.0 * M_PI), M_PI, 1e-12);
  EXPECT_NEAR(normalizeAngle(-3.0 * M_PI), M_PI, 1e-12);
  EXPECT_TRUE(std::isnan(normalizeAngle(std::nan(""))));
  EXPECT_TRUE(std::isnan(normalizeAngle(INFINITY)));
}

TEST(Se2, SensorMotionIsTheConjugatedBodyMotion)
{
  // A body turning on the spot by 90 degrees: a sensor 1 m ahead moves on a circle,
  // from (1, 0) to (0, 1) in the body's start frame.
  const Pose2 T_body_sensor(1.0, 0.0, 0.0);
  const Pose2 turn(0.0, 0.0, M_PI / 2);
  const Pose2 h = sensorMotionFromBodyMotion(T_body_sensor, turn);
  // In the sensor's start frame: moved by (-1, 1) in x/y, and turned by 90 degrees.
  expectPoseNear(h, Pose2(-1.0, 1.0, M_PI / 2));
  // Same as T_s^-1 * Delta * T_s written out with matrices.
  const Eigen::Matrix3d expected =
      T_body_sensor.matrix().inverse() * turn.matrix() * T_body_sensor.matrix();
  EXPECT_TRUE(expected.isApprox(h.matrix(), 1e-12));
}

TEST(Se2, SensorMotionOfAStraightDriveWithARotatedSensor)
{
  // Driving 1 m forward seen by a sensor that looks left: it moves to its right (-y).
  const Pose2 T_body_sensor(0.5, 0.2, M_PI / 2);
  const Pose2 h = sensorMotionFromBodyMotion(T_body_sensor, Pose2(1.0, 0.0, 0.0));
  expectPoseNear(h, Pose2(0.0, -1.0, 0.0));
}

TEST(Se2, BoxMinusIsZeroForEqualMotionsAndSignedOtherwise)
{
  const Pose2 z(0.4, 0.1, 0.2);
  EXPECT_NEAR(boxMinus(z, z).norm(), 0.0, 1e-15);
  // A prediction 0.05 m further along the measured motion's own x axis.
  const Pose2 h = z * Pose2(0.05, 0.0, 0.01);
  const Eigen::Vector3d e = boxMinus(h, z);
  EXPECT_NEAR(e(0), 0.05, 1e-12);
  EXPECT_NEAR(e(1), 0.0, 1e-12);
  EXPECT_NEAR(e(2), 0.01, 1e-12);
}

TEST(Se2, TransformPointMapsChildToParent)
{
  const Pose2 T_w_s(1.0, 2.0, M_PI / 2);
  const Eigen::Vector2d p_w = T_w_s.transformPoint(Eigen::Vector2d(1.0, 0.0));
  EXPECT_NEAR(p_w(0), 1.0, 1e-12);
  EXPECT_NEAR(p_w(1), 3.0, 1e-12);
}

TEST(Se2, ExpFollowsTheArcAndInvertsLog)
{
  // A quarter circle of radius 2 m driven forward: ends at (2, 2) facing +y.
  const Pose2 quarter = se2Exp(Eigen::Vector3d(M_PI, 0.0, M_PI / 2));
  EXPECT_NEAR(quarter.x(), 2.0, 1e-12);
  EXPECT_NEAR(quarter.y(), 2.0, 1e-12);
  EXPECT_NEAR(quarter.theta(), M_PI / 2, 1e-12);
  // Straight and nearly straight motion: the first-order arc, no division by zero.
  const Pose2 straight = se2Exp(Eigen::Vector3d(1.0, 0.0, 0.0));
  EXPECT_NEAR(straight.x(), 1.0, 1e-15);
  EXPECT_NEAR(straight.y(), 0.0, 1e-15);
  const Pose2 tiny = se2Exp(Eigen::Vector3d(1.0, 0.0, 2e-10));
  EXPECT_NEAR(tiny.y(), 1e-10, 1e-16);
  // exp(log(T)) = T for motions with sideways components and turns both ways.
  for (const Pose2& step : {Pose2(0.3, -0.1, 0.7), Pose2(-0.2, 0.05, -1.2), Pose2(0.1, 0.0, 0.0)}) {
    const Pose2 back = se2Exp(se2Log(step));
    EXPECT_NEAR(back.x(), step.x(), 1e-12);
    EXPECT_NEAR(back.y(), step.y(), 1e-12);
    EXPECT_NEAR(back.theta(), step.theta(), 1e-12);
  }
}

}  // namespace
}  // namespace odometry_calibration
