#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/data/base_odometry_path.h"
#include "odometry_calibration/models/base_odometry_model.h"

namespace odometry_calibration {
namespace {

constexpr double kTranslationError = 0.03, kRotationError = 0.02;
const Pose2 kTrueSensor(0.145, 0.01, 0.02);

/// Pairs of a base driving curves for `duration_s`: the base publishes at 50 Hz a pose
/// integrated from the true motion with its translation times 1.03 and its rotation times 1.02
/// (made joints by BaseOdometryPath); the sensor's motion over each 0.5 s pair is the truth seen
/// from kTrueSensor, with 1 mm and 0.5 mrad of noise.
std::vector<MotionPair> drive(double duration_s, unsigned seed)
{
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, 1.0);
  const double dt = 0.02;
  Pose2 truth, reported;
  BaseOdometryPath path;
  std::vector<MotionPair> pairs;
  MotionPair pair;
  Pose2 pair_start;
  for (int k = 0; k * dt <= duration_s; ++k) {
    const double t = k * dt;
    if (k > 0) {
      const double v = 0.4 * std::sin(0.3 * t) + 0.1;
      const double omega = 0.8 * std::sin(0.17 * t + 1.0) + 0.3 * std::cos(0.9 * t);
      const Pose2 step(v * dt * std::cos(0.5 * omega * dt), v * dt * std::sin(0.5 * omega * dt),
                       omega * dt);
      truth = truth * step;
      reported = reported * Pose2((1.0 + kTranslationError) * step.x(),
                                  (1.0 + kTranslationError) * step.y(),
                                  (1.0 + kRotationError) * step.theta());
    }
    const EncoderSample sample{t, *path.add(t, reported)};
    pair.encoder_samples.push_back(sample);
    if (pair.encoder_samples.size() == 26) {  // 0.5 s
      pair.start_stamp_s = pair.encoder_samples.front().stamp_s;
      pair.end_stamp_s = t;
      const Pose2 motion = kTrueSensor.inverse() * pair_start.inverse() * truth * kTrueSensor;
      pair.sensor_motion =
          motion * Pose2(0.001 * noise(rng), 0.001 * noise(rng), 0.0005 * noise(rng));
      pair.covariance = Eigen::Vector3d(1e-6, 1e-6, 0.25e-6).asDiagonal();
      pairs.push_back(pair);
      pair.encoder_samples = {sample};
      pair_start = truth;
    }
  }
  return pairs;
}

TEST(BaseOdometryModel, RecoversBothScalesAndTheSensorPose)
{
  BaseOdometryOptions options;
  options.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  BaseOdometryModel model(options);
  const ModelReport report = model.fit(drive(120.0, 1));
  ASSERT_TRUE(report.converged) << report.termination;
  EXPECT_NEAR(model.scales()(kTranslationScale) * (1.0 + kTranslationError), 1.0, 5e-4);
  EXPECT_NEAR(model.scales()(kRotationScale) * (1.0 + kRotationError), 1.0, 5e-4);
  EXPECT_NEAR(model.T_base_sensor().x(), kTrueSensor.x(), 0.002);
  EXPECT_NEAR(model.T_base_sensor().y(), kTrueSensor.y(), 0.002);
  EXPECT_NEAR(model.T_base_sensor().theta(), kTrueSensor.theta(), 0.1 * M_PI / 180.0);
  ASSERT_EQ(report.parameters.size(), 5u);
  EXPECT_EQ(report.parameters[0].name, "translation_scale");
  EXPECT_EQ(report.parameters[1].name, "rotation_scale");
  // From the scale errors' 14 mm and 6 mrad per pair down to the noise (1.4 mm, 0.5 mrad).
  EXPECT_LT(report.after.translation_m, 0.0016);
  EXPECT_GT(report.before.translation_m, 0.01);
  EXPECT_LT(report.after.rotation_rad, 0.1 * report.before.rotation_rad);
}

TEST(BaseOdometryModel, AMirroredStartEndsOnThePhysicalSide)
{
  // Started with the sensor turned round (-x, -y, theta + pi), the fit may first land on
  // (-k_t, k_r): it is turned over, so the translation scale is positive.
  BaseOdometryOptions options;
  options.initial_T_base_sensor = Pose2(-0.145, -0.01, 0.02 + M_PI);
  options.yaw_starts = 1;
  BaseOdometryModel model(options);
  const ModelReport report = model.fit(drive(60.0, 2));
  EXPECT_NEAR(model.scales()(kTranslationScale) * (1.0 + kTranslationError), 1.0, 1e-3);
  EXPECT_NEAR(model.T_base_sensor().x(), kTrueSensor.x(), 0.003);
  EXPECT_NEAR(report.parameters[0].initial, 1.0, 1e-12);  // the start values reported
  EXPECT_NEAR(report.parameters[2].initial, -0.145, 1e-12);
}

TEST(BaseOdometryModel, PredictionsSurviveTheYamlRoundTrip)
{
  BaseOdometryModel model{BaseOdometryOptions{}};
  const std::vector<MotionPair> pairs = drive(60.0, 3);
  model.fit(pairs);
  const BaseOdometryModel loaded = BaseOdometryModel::fromYaml(model.toYaml());
  const MotionPrediction a = model.predict(pairs[7].encoder_samples);
  const MotionPrediction b = loaded.predict(pairs[7].encoder_samples);
  EXPECT_NEAR(a.mean.x(), b.mean.x(), 1e-9);
  EXPECT_NEAR(a.mean.y(), b.mean.y(), 1e-9);
  EXPECT_NEAR(a.mean.theta(), b.mean.theta(), 1e-9);
  EXPECT_NEAR(loaded.scales()(kRotationScale), model.scales()(kRotationScale), 1e-9);
}

TEST(BaseOdometryModel, WheelJointsAreRefusedNamingTheSource)
{
  JointLayout wheels{{"left_wheel", "right_wheel"},
                     {EncoderKind::kIncremental, EncoderKind::kIncremental}};
  try {
    baseOdometryLayoutForJoints(wheels);
    FAIL() << "no error";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("wheels.source odometry"), std::string::npos)
        << error.what();
  }
  BaseOdometryModel model{BaseOdometryOptions{}};
  EXPECT_THROW(model.fit(std::vector<MotionPair>(3)), std::invalid_argument);
}

TEST(BaseOdometryPath, IncrementsInTheBaseFrameRestartsAndRefusals)
{
  BaseOdometryPath path;
  EXPECT_TRUE(path.add(1.0, Pose2(5.0, 2.0, M_PI / 2)).has_value());
  // 1 m forward in the base frame (the odom frame's +y), turning 0.1 rad.
  const Eigen::Vector3d after = *path.add(1.1, Pose2(5.0, 3.0, M_PI / 2 + 0.1));
  EXPECT_NEAR(after(0), 1.0, 1e-12);
  EXPECT_NEAR(after(1), 0.0, 1e-12);
  EXPECT_NEAR(after(2), 0.1, 1e-12);
  EXPECT_FALSE(path.add(1.1, Pose2(9.0, 9.0, 0.0)).has_value());  // the same stamp
  std::string note;
  const Eigen::Vector3d restarted = *path.add(0.5, Pose2(0.0, 0.0, 0.0), &note);
  EXPECT_NE(note.find("went back in time by 0.6 s"), std::string::npos) << note;
  EXPECT_NEAR((restarted - after).norm(), 0.0, 1e-12);  // held
  EXPECT_THROW(path.add(0.6, Pose2(std::nan(""), 0.0, 0.0)), std::invalid_argument);
  EXPECT_THROW(path.add(0.7, Pose2(1e308, -1e308, 0.0)), std::invalid_argument);
  EXPECT_NEAR(path.add(0.8, Pose2(0.0, 0.5, 0.0))->x(), 1.0, 1e-12);  // 0.5 m sideways
}

}  // namespace
}  // namespace odometry_calibration
