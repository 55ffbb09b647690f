#include <cmath>
#include <memory>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/models/diff_drive_model.h"

namespace odometry_calibration {
namespace {

constexpr double kRadius = 0.08, kSeparation = 0.4, kTicksPerTurn = 2000.0;

std::shared_ptr<DiffDriveModel> diffDrive(const Pose2& T_base_sensor)
{
  DiffDriveOptions options;
  options.initial_left_radius_m = kRadius;
  options.initial_right_radius_m = kRadius;
  options.initial_separation_m = kSeparation;
  options.initial_T_base_sensor = T_base_sensor;
  return std::make_shared<DiffDriveModel>(options);
}

/// Encoder samples at 50 Hz for constant wheel speeds v_left, v_right [m/s].
std::vector<EncoderSample> constantWheelSpeeds(double v_left, double v_right, double duration_s)
{
  const double ticks_per_m = kTicksPerTurn / (2.0 * M_PI * kRadius);
  std::vector<EncoderSample> samples;
  for (int i = 0; i * 0.02 <= duration_s + 1e-9; ++i) {
    const double t = i * 0.02;
    samples.push_back(
        {100.0 + t, Eigen::Vector2d(v_left * t * ticks_per_m, v_right * t * ticks_per_m)});
  }
  return samples;
}

/// Base pose after driving an arc of speed v and turn rate omega for t seconds.
Pose2 arc(double v, double omega, double t)
{
  return Pose2(v / omega * std::sin(omega * t), v / omega * (1.0 - std::cos(omega * t)),
               normalizeAngle(omega * t));
}

TEST(OdometryIntegrator, FollowsAnArcThroughManySegments)
{
  const Pose2 T_base_sensor(0.2, 0.1, 0.3);
  OdometryIntegrator odometry(diffDrive(T_base_sensor), T_base_sensor, 0.5);
  const double v_left = 0.4, v_right = 0.6;  // v = 0.5 m/s, omega = 0.5 rad/s
  for (const EncoderSample& sample : constantWheelSpeeds(v_left, v_right, 7.3))
    ASSERT_TRUE(odometry.add(sample));
  const Pose2 expected = arc(0.5, 0.5, 7.3);
  ASSERT_TRUE(odometry.tracksBase());
  EXPECT_NEAR(odometry.pose().x(), expected.x(), 1e-6);
  EXPECT_NEAR(odometry.pose().y(), expected.y(), 1e-6);
  EXPECT_NEAR(odometry.pose().theta(), expected.theta(), 1e-6);
  const Pose2 sensor = expected * T_base_sensor;
  EXPECT_NEAR(odometry.sensorPose().x(), sensor.x(), 1e-6);
  EXPECT_NEAR(odometry.sensorPose().y(), sensor.y(), 1e-6);
  EXPECT_NEAR(odometry.velocity()(0), 0.5, 1e-6);
  EXPECT_NEAR(odometry.velocity()(1), 0.0, 1e-6);
  EXPECT_NEAR(odometry.velocity()(2), 0.5, 1e-6);
  EXPECT_NEAR(odometry.stamp(), 107.3, 1e-9);
}

TEST(OdometryIntegrator, WithoutExtrinsicTracksTheSensorFromTheOrigin)
{
  const Pose2 T_base_sensor(0.2, 0.1, 0.3);
  OdometryIntegrator odometry(diffDrive(T_base_sensor), std::nullopt, 0.5);
  for (const EncoderSample& sample : constantWheelSpeeds(0.4, 0.6, 3.0))
    odometry.add(sample);
  EXPECT_FALSE(odometry.tracksBase());
  // The sensor's own motion, starting at the identity: T_bs^-1 * arc * T_bs.
  const Pose2 expected = T_base_sensor.inverse() * arc(0.5, 0.5, 3.0) * T_base_sensor;
  EXPECT_NEAR(odometry.pose().x(), expected.x(), 1e-6);
  EXPECT_NEAR(odometry.pose().y(), expected.y(), 1e-6);
  EXPECT_NEAR(odometry.pose().theta(), expected.theta(), 1e-6);
}

TEST(OdometryIntegrator, IgnoresSamplesThatDoNotAdvanceAndRestartsWithoutAJump)
{
  OdometryIntegrator odometry(diffDrive(Pose2()), Pose2(), 0.5);
  const auto samples = constantWheelSpeeds(0.5, 0.5, 2.0);
  for (std::size_t i = 0; i < 50; ++i)
    odometry.add(samples[i]);
  const Pose2 before = odometry.pose();
  EXPECT_FALSE(odometry.add(samples[10]));  // older
  EXPECT_FALSE(odometry.add(samples[49]));  // same stamp
  EXPECT_DOUBLE_EQ(odometry.pose().x(), before.x());
  odometry.restartAt(before);
  for (std::size_t i = 50; i < samples.size(); ++i)
    odometry.add(samples[i]);
  // 2 s at 0.5 m/s straight, nothing lost across the restart.
  EXPECT_NEAR(odometry.pose().x(), 1.0, 1e-6);
  EXPECT_NEAR(odometry.pose().y(), 0.0, 1e-9);
  EXPECT_TRUE(std::isnan(OdometryIntegrator(diffDrive(Pose2()), Pose2(), 0.5).stamp()));
}

/// A model that predicts 1 m forward per unit of joint 0 with a fixed covariance per window.
class StepModel : public MotionModel
{
public:
  explicit StepModel(Eigen::Matrix3d covariance) : covariance_(covariance) {}
  std::string name() const override { return "step"; }
  ModelReport fit(const std::vector<MotionPair>&) override { return {}; }
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override
  {
    MotionPrediction prediction;
    prediction.mean = Pose2(samples.back().values(0) - samples.front().values(0), 0.0, 0.0);
    prediction.covariance = covariance_;
    return prediction;
  }
  std::string toYaml() const override { return ""; }

private:
  Eigen::Matrix3d covariance_;
};

TEST(OdometryIntegrator, PropagatesTheCovarianceThroughEachSegment)
{
  const double var_x = 1e-4, var_y = 2e-4, var_theta = 3e-4;
  auto model = std::make_shared<StepModel>(Eigen::Vector3d(var_x, var_y, var_theta).asDiagonal());
  // Segments of one sample interval: every sample closes a segment of 1 m.
  OdometryIntegrator odometry(model, Pose2(), 0.5);
  for (int i = 0; i <= 2; ++i)
    odometry.add({static_cast<double>(i), Eigen::VectorXd::Constant(1, i)});
  const Eigen::Matrix3d covariance = odometry.covariance();
  // Two straight 1 m steps: var(x) = 2 var_x, var(y) = 2 var_y + 1 m^2 var_theta (the first
  // step's heading error swings the second step), var(theta) = 2 var_theta.
  EXPECT_NEAR(covariance(0, 0), 2 * var_x, 1e-12);
  EXPECT_NEAR(covariance(1, 1), 2 * var_y + var_theta, 1e-12);
  EXPECT_NEAR(covariance(2, 2), 2 * var_theta, 1e-12);
  EXPECT_NEAR(covariance(1, 2), var_theta, 1e-12);
  EXPECT_NEAR(covariance(0, 1), 0.0, 1e-12);

  // A floor adds to each window: as if the model reported it.
  OdometryIntegrator floored(std::make_shared<StepModel>(Eigen::Matrix3d::Zero()), Pose2(), 0.5);
  floored.setWindowCovarianceFloor(Eigen::Vector3d(var_x, var_y, var_theta).asDiagonal());
  for (int i = 0; i <= 2; ++i)
    floored.add({static_cast<double>(i), Eigen::VectorXd::Constant(1, i)});
  EXPECT_LT((floored.covariance() - covariance).cwiseAbs().maxCoeff(), 1e-15);
}

TEST(OdometryIntegrator, ComposedCovarianceMatchesFiniteDifferences)
{
  const Pose2 a(1.0, -2.0, 0.7), d(0.3, 0.2, -0.4);
  const Eigen::Matrix3d unit = Eigen::Matrix3d::Identity();
  // With unit covariances, J_a J_a^T + J_d J_d^T; rebuild J_a and J_d numerically.
  Eigen::Matrix3d J_a, J_d;
  const double h = 1e-7;
  for (int k = 0; k < 3; ++k) {
    Eigen::Vector3d step = Eigen::Vector3d::Zero();
    step(k) = h;
    J_a.col(k) = ((Pose2::fromVector(a.vector() + step) * d).vector() - (a * d).vector()) / h;
    J_d.col(k) = ((a * Pose2::fromVector(d.vector() + step)).vector() - (a * d).vector()) / h;
  }
  const Eigen::Matrix3d expected = J_a * J_a.transpose() + J_d * J_d.transpose();
  EXPECT_LT((composeCovariance(a, unit, d, unit) - expected).cwiseAbs().maxCoeff(), 1e-5);
}

TEST(OdometryIntegrator, RejectsBadConstruction)
{
  EXPECT_THROW(OdometryIntegrator(nullptr, Pose2(), 0.5), std::invalid_argument);
  EXPECT_THROW(OdometryIntegrator(diffDrive(Pose2()), Pose2(), 0.0), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
