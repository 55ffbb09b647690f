#include "odometry_calibration/models/skid_steer_model.h"

#include <cmath>
#include <iostream>
#include <stdexcept>

#include <gtest/gtest.h>

#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

constexpr double kTrackWidthM = 0.5;

/// Four wheels (front_left, rear_left, front_right, rear_right), right wheels 1 % larger,
/// turning as a diff drive of `factor` times the track width.
sim::GeneratedPairs skidSteerPairs(double factor, unsigned seed)
{
  sim::PairGeneratorOptions options;
  options.robot = {"skid_steer",
                   {{"wheel_radius_left_m", 0.1},
                    {"wheel_radius_right_m", 0.101},
                    {"wheel_separation_m", kTrackWidthM},
                    {"effective_separation_factor", factor}}};
  options.T_base_sensor = Pose2(0.25, 0.02, 0.03);
  options.duration_s = 180.0;
  options.interval_s = 0.5;
  options.seed = seed;
  return sim::generatePairs(options);
}

SkidSteerOptions geometric()
{
  SkidSteerOptions options;
  options.left_indices = {0, 1};
  options.right_indices = {2, 3};
  options.ticks_per_turn = 2000.0;
  options.wheel_radius_m = 0.1;
  options.wheel_separation_m = kTrackWidthM;
  options.initial_T_base_sensor = Pose2(0.2, 0.0, 0.0);
  return options;
}

double parameter(const ModelReport& report, const std::string& name, double* sigma = nullptr)
{
  for (const ParameterEstimate& p : report.parameters) {
    if (p.name == name) {
      if (sigma)
        *sigma = p.sigma;
      return p.value;
    }
  }
  ADD_FAILURE() << "no parameter " << name;
  return NAN;
}

// Issue 17 acceptance: effective separation 1.3-1.6 times the geometric one, the fitted
// multiplier within 2 % of the truth.
TEST(SkidSteerModel, RecoversTheEffectiveSeparationAsAMultiplier)
{
  for (double factor : {1.3, 1.6}) {
    const sim::GeneratedPairs data = skidSteerPairs(factor, 3);
    ASSERT_EQ(data.joints.names.size(), 4u);
    SkidSteerModel model(geometric());
    const ModelReport report = model.fit(data.pairs);
    ASSERT_TRUE(report.converged) << report.termination;
    EXPECT_EQ(report.model, "skid_steer");
    double sigma = 0.0;
    const double multiplier = parameter(report, "wheel_separation_multiplier", &sigma);
    EXPECT_NEAR(multiplier, factor, 0.02 * factor) << "factor " << factor;
    std::cout << "truth " << factor << ": wheel_separation_multiplier " << multiplier << " +- "
              << sigma << "\n";
    EXPECT_GT(sigma, 0.0);
    EXPECT_LT(std::abs(multiplier - factor), 4.0 * sigma + 1e-3) << "sigma " << sigma;
    EXPECT_NEAR(parameter(report, "wheel_separation"), factor * kTrackWidthM,
                0.02 * factor * kTrackWidthM);
    EXPECT_NEAR(parameter(report, "left_wheel_radius_multiplier"), 1.0, 0.005);
    EXPECT_NEAR(parameter(report, "right_wheel_radius_multiplier"), 1.01, 0.005);
    EXPECT_NEAR(model.T_base_sensor().x(), 0.25, 0.01);
    EXPECT_NEAR(model.T_base_sensor().y(), 0.02, 0.01);
    // The fitted model predicts far better than the geometric one.
    EXPECT_LT(report.after.rotation_rad, 0.2 * report.before.rotation_rad);
  }
}

TEST(SkidSteerModel, AveragesTheWheelsOfEachSide)
{
  const std::vector<EncoderSample> samples = {{0.0, Eigen::Vector4d(0, 10, 100, 300)},
                                              {0.1, Eigen::Vector4d(2, 4, 6, 8)}};
  const std::vector<EncoderSample> sides = averageSides(samples, {0, 1}, {2, 3});
  ASSERT_EQ(sides.size(), 2u);
  EXPECT_DOUBLE_EQ(sides[0].values(0), 5.0);
  EXPECT_DOUBLE_EQ(sides[0].values(1), 200.0);
  EXPECT_DOUBLE_EQ(sides[1].values(0), 3.0);
  EXPECT_DOUBLE_EQ(sides[1].stamp_s, 0.1);
  // A sample without the right side's second joint is named, not read out of bounds.
  EXPECT_THROW(averageSides(samples, {0}, {2, 4}), std::invalid_argument);
  SkidSteerOptions bad = geometric();
  bad.right_indices = {1, 3};  // joint 1 on both sides
  EXPECT_THROW(SkidSteerModel{bad}, std::invalid_argument);
  bad = geometric();
  bad.wheel_separation_m = 0.0;
  EXPECT_THROW(SkidSteerModel{bad}, std::invalid_argument);
  bad = geometric();
  bad.yaw_starts = 0;
  try {
    SkidSteerModel{bad};
    FAIL() << "yaw_starts 0 accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("skid_steer option 'yaw_starts'"), std::string::npos);
  }
}

TEST(SkidSteerModel, SavedModelPredictsTheSame)
{
  const sim::GeneratedPairs data = skidSteerPairs(1.45, 5);
  SkidSteerModel model(geometric());
  model.fit(data.pairs);
  const std::unique_ptr<MotionModel> loaded = loadModel(model.toYaml());
  ASSERT_EQ(loaded->name(), "skid_steer");
  for (int i : {3, 40}) {
    const auto& samples = data.pairs[i].encoder_samples;
    const MotionPrediction a = model.predict(samples), b = loaded->predict(samples);
    EXPECT_NEAR(a.mean.x(), b.mean.x(), 1e-12);
    EXPECT_NEAR(a.mean.theta(), b.mean.theta(), 1e-12);
    EXPECT_NEAR(a.covariance(0, 0), b.covariance(0, 0), 1e-15);
  }
  // Too few joints in the samples: a clear message.
  std::vector<EncoderSample> two = {{0.0, Eigen::Vector2d(0, 0)}, {0.1, Eigen::Vector2d(1, 1)}};
  EXPECT_THROW(loaded->predict(two), std::invalid_argument);
}

TEST(SkidSteerModel, FactoryKnowsItAndChecksTheJoints)
{
  ModelFactoryOptions options;
  options.skid_steer = geometric();
  options.joints.names = {"a", "b", "c", "d"};
  options.joints.kinds.assign(4, EncoderKind::kIncremental);
  EXPECT_TRUE(isKnownModel("skid_steer"));
  EXPECT_EQ(makeModel("skid_steer", options)->name(), "skid_steer");
  options.joints.names.resize(3);
  options.joints.kinds.resize(3);
  EXPECT_THROW(makeModel("skid_steer", options), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
