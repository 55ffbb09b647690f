#include <cmath>
#include <fstream>

#include <ceres/ceres.h>
#include <gtest/gtest.h>

#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "odometry_calibration/models/tricycle_kinematics.h"
#include "odometry_calibration/models/tricycle_residual.h"

namespace odometry_calibration {
namespace {

const TricycleEncoderLayout kLayout;  // steering index 0 (8192/turn), traction index 1 (5000/turn)

/// Samples with a constant steering reading and `ticks_per_step` traction ticks per step.
std::vector<EncoderSample> constantSteering(double steering_ticks, double ticks_per_step, int steps)
{
  std::vector<EncoderSample> samples;
  for (int k = 0; k <= steps; ++k) {
    samples.push_back({0.04 * k, Eigen::Vector2d(steering_ticks, ticks_per_step * k)});
  }
  return samples;
}

TEST(TricycleKinematics, StraightDriveMovesByTheTractionDistance)
{
  const double kinematic[4] = {0.5, 0.01, 1.5, 0.0};  // Ks, Kt [m/turn], a [m], offset
  const Pose2 motion = integrateTricycleMotion(kinematic, kLayout, constantSteering(0, 250, 4));
  // 1000 ticks of 5000 per turn at 0.01 m per turn: 2 mm.
  EXPECT_NEAR(motion.x(), 0.002, 1e-15);
  EXPECT_NEAR(motion.y(), 0.0, 1e-15);
  EXPECT_NEAR(motion.theta(), 0.0, 1e-15);
}

TEST(TricycleKinematics, ArcIsExactSoStepSizeDoesNotMatter)
{
  // Constant steering: one big step and 50 small ones must land on the same arc point.
  const double kinematic[4] = {0.5, 2.0, 1.5, 0.05};
  const Pose2 one = integrateTricycleMotion(kinematic, kLayout, constantSteering(600, 5000, 1));
  const Pose2 many = integrateTricycleMotion(kinematic, kLayout, constantSteering(600, 100, 50));
  EXPECT_NEAR(one.x(), many.x(), 1e-12);
  EXPECT_NEAR(one.y(), many.y(), 1e-12);
  EXPECT_NEAR(one.theta(), many.theta(), 1e-12);
  EXPECT_GT(one.y(), 0.1);  // a real left turn, not a trivial case
}

TEST(TricycleKinematics, FullCircleReturnsToTheStart)
{
  // Steering angle alpha = Ks * s * 2 pi / 8192 + offset; heading rate sin(alpha) / a per metre.
  const double ks = 0.5, a = 1.5, steering_ticks = 800.0;
  const double alpha = ks * steering_ticks * 2.0 * M_PI / 8192.0;
  const double travel_for_circle = 2.0 * M_PI * a / std::sin(alpha);
  const double kinematic[4] = {ks, travel_for_circle, a, 0.0};  // one wheel turn = one circle
  const Pose2 motion =
      integrateTricycleMotion(kinematic, kLayout, constantSteering(steering_ticks, 50, 100));
  EXPECT_NEAR(motion.x(), 0.0, 1e-9);
  EXPECT_NEAR(motion.y(), 0.0, 1e-9);
  EXPECT_NEAR(normalizeAngle(motion.theta()), 0.0, 1e-9);
  // Half way round, the rear axle is 2 R = 2 a / tan(alpha) to the left.
  const Pose2 half =
      integrateTricycleMotion(kinematic, kLayout, constantSteering(steering_ticks, 50, 50));
  EXPECT_NEAR(half.y(), 2.0 * a / std::tan(alpha), 1e-9);
}

TEST(TricycleKinematics, NominalModelReproducesTheRobotsOwnOdometry)
{
  // The log's model_pose is the robot's odometry with the nominal parameters: integrating
  // our model over the decoded encoders must give the same path (the log prints ~6 digits and
  // uses a midpoint chord, < 1e-4 m per step from the exact arc).
  const std::string path =
      std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/tricycle/dataset.txt";
  if (!std::ifstream(path)) {
    GTEST_SKIP() << "real dataset not found at " << path;
  }
  const TricycleDataset dataset = loadTricycleDataset(path);
  const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
  const Eigen::Vector4d nominal = tricycleNominalFromHeader(dataset.header).kinematicVector();
  const auto samples = decodeTricycleEncoders(dataset, layout);
  Pose2 T_odom_base;
  double worst_m = 0.0;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    T_odom_base =
        T_odom_base * integrateTricycleMotion(nominal.data(), layout, {samples[k - 1], samples[k]});
    const Pose2 error = between(dataset.rows[k].T_odom_base_model, T_odom_base);
    worst_m = std::max(worst_m, std::hypot(error.x(), error.y()));
  }
  EXPECT_LT(worst_m, 0.01);  // over 37 m of driving back and forth
}

TEST(TricyclePairResidual, AutodiffJacobianMatchesFiniteDifferences)
{
  // A curved window with varying steering and a reversal.
  MotionPair pair;
  const double steering[] = {300, 350, 420, 500, 480, 7900, 7800, 7850};
  const double traction[] = {0, 3000, 6500, 9000, 12000, 11000, 9500, 7000};
  for (int k = 0; k < 8; ++k) {
    pair.encoder_samples.push_back({0.05 * k, Eigen::Vector2d(steering[k], traction[k])});
  }
  pair.sensor_motion = Pose2(0.05, 0.01, 0.02);
  pair.covariance = Eigen::Vector3d(1e-4, 2e-4, 5e-5).asDiagonal();
  TricyclePairResidual functor(pair, kLayout);
  ceres::AutoDiffCostFunction<TricyclePairResidual, 3, 4, 3> cost(
      new TricyclePairResidual(pair, kLayout));

  double kinematic[4] = {0.56, 0.0106, 1.54, -0.06};
  double sensor[3] = {1.8, -0.02, 0.01};
  double* parameters[2] = {kinematic, sensor};
  double residual[3];
  Eigen::Matrix<double, 3, 4, Eigen::RowMajor> jacobian_kinematic;
  Eigen::Matrix<double, 3, 3, Eigen::RowMajor> jacobian_sensor;
  double* jacobians[2] = {jacobian_kinematic.data(), jacobian_sensor.data()};
  ASSERT_TRUE(cost.Evaluate(parameters, residual, jacobians));
  EXPECT_GT(Eigen::Vector3d(residual[0], residual[1], residual[2]).norm(), 0.1);

  auto numeric = [&](double* block, int index) {
    const double original = block[index];
    const double step = 1e-6 * std::max(1.0, std::abs(original));
    Eigen::Vector3d plus, minus;
    block[index] = original + step;
    functor(kinematic, sensor, plus.data());
    block[index] = original - step;
    functor(kinematic, sensor, minus.data());
    block[index] = original;
    return Eigen::Vector3d((plus - minus) / (2.0 * step));
  };
  for (int i = 0; i < 4; ++i) {
    const Eigen::Vector3d expected = numeric(kinematic, i);
    EXPECT_GT(expected.norm(), 1e-6) << "kinematic parameter " << i << " has no effect";
    EXPECT_TRUE(jacobian_kinematic.col(i).isApprox(expected, 1e-6))
        << "kinematic " << i << ": autodiff " << jacobian_kinematic.col(i).transpose()
        << " vs numeric " << expected.transpose();
  }
  for (int i = 0; i < 3; ++i) {
    const Eigen::Vector3d expected = numeric(sensor, i);
    EXPECT_TRUE(jacobian_sensor.col(i).isApprox(expected, 1e-6))
        << "sensor " << i << ": autodiff " << jacobian_sensor.col(i).transpose() << " vs numeric "
        << expected.transpose();
  }
}

}  // namespace
}  // namespace odometry_calibration
