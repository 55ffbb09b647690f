#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/models/linear_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

sim::GeneratedPairs pairs(double interval_s, unsigned seed, double duration_s = 150.0)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive", {}};
  options.interval_s = interval_s;
  options.duration_s = duration_s;
  options.seed = seed;
  return sim::generatePairs(options);
}

/// Held-out RMSE per axis of the model's mean against the noise-free displacements.
Eigen::Vector3d heldOutRmse(const MotionModel& model, const sim::GeneratedPairs& test)
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (std::size_t i = 0; i < test.pairs.size(); ++i) {
    const Pose2 predicted = model.predict(test.pairs[i].encoder_samples).mean;
    const Eigen::Vector3d e = predicted.vector() - test.true_motions[i].vector();
    sum += e.cwiseAbs2();
  }
  return (sum / static_cast<double>(test.pairs.size())).cwiseSqrt();
}

TEST(LinearModel, ExactOnNoiseFreeLinearData)
{
  // Synthetic pairs where s = W delta exactly: the fit must return W.
  Eigen::Matrix<double, 3, 2> W;
  W << 1e-4, 2e-4, 3e-6, -1e-6, -5e-4, 5e-4;
  std::vector<MotionPair> data;
  for (int i = 0; i < 40; ++i) {
    MotionPair pair;
    const Eigen::Vector2d delta(100.0 * std::sin(i), 80.0 * std::cos(0.7 * i));
    pair.encoder_samples = {{0.0, Eigen::Vector2d::Zero()}, {0.1, delta}};
    const Eigen::Vector3d s = W * delta;
    pair.sensor_motion = Pose2(s(0), s(1), s(2));
    pair.covariance = Eigen::Vector3d(1e-6, 1e-6, 1e-6).asDiagonal();
    data.push_back(pair);
  }
  LinearModel model({{{"l", "r"}, {EncoderKind::kIncremental, EncoderKind::kIncremental}}});
  const ModelReport report = model.fit(data);
  EXPECT_TRUE(model.weights().isApprox(W, 1e-9)) << model.weights();
  EXPECT_EQ(report.outliers, 0u);
}

TEST(LinearModel, ReachesTheNoiseFloorForSmallMotionsAndWarnsForLargeOnes)
{
  // 0.1 s pairs: at most ~6 cm and 0.12 rad; the first-order model is enough.
  const auto train = pairs(0.1, 1), test = pairs(0.1, 2);
  LinearModel model({train.joints});
  const ModelReport report = model.fit(train.pairs);
  const Eigen::Vector3d rmse = heldOutRmse(model, test);
  EXPECT_LT(rmse(0), 1.2 * 0.002);
  EXPECT_LT(rmse(1), 1.2 * 0.002);
  EXPECT_LT(rmse(2), 1.2 * 0.002);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();

  // 0.5 s pairs: the sideways displacement is quadratic in the increments.
  const auto long_train = pairs(0.5, 1, 300.0), long_test = pairs(0.5, 2, 300.0);
  LinearModel long_model({long_train.joints});
  const ModelReport long_report = long_model.fit(long_train.pairs);
  EXPECT_GT(heldOutRmse(long_model, long_test)(1), 3.0 * 0.002);
  bool warned = false;
  for (const auto& warning : long_report.warnings) {
    warned |= warning.find("residual on y") != std::string::npos &&
              warning.find("GP") != std::string::npos;
  }
  EXPECT_TRUE(warned);
}

TEST(LinearModel, RejectsGrossOutliersItself)
{
  auto train = pairs(0.1, 3);
  const auto test = pairs(0.1, 4);
  for (std::size_t i = 0; i < train.pairs.size(); i += 33) {  // 3 % gross outliers
    train.pairs[i].sensor_motion = train.pairs[i].sensor_motion * Pose2(0.3, -0.2, 0.4);
  }
  LinearModel model({train.joints});
  const ModelReport report = model.fit(train.pairs);
  const std::size_t injected = (train.pairs.size() + 32) / 33;
  EXPECT_GE(report.outliers, injected);
  EXPECT_EQ(report.rejected, report.outliers);  // left out; down-weighted ones counted apart
  // Huber at 1.345 sigma down-weights ~18 % of Gaussian errors per axis (~45 % of the pairs on
  // some axis): counted, but apart from the rejected ones.
  EXPECT_GT(report.down_weighted, 0u);
  EXPECT_LE(report.rejected + report.down_weighted, train.pairs.size());
  EXPECT_LT(heldOutRmse(model, test).maxCoeff(), 1.3 * 0.002);
}

TEST(LinearModel, SaveLoadPredictsTheSame)
{
  const auto train = pairs(0.2, 5);
  LinearModel model({train.joints});
  model.fit(train.pairs);
  const LinearModel loaded = LinearModel::fromYaml(model.toYaml());
  const auto& samples = train.pairs[10].encoder_samples;
  EXPECT_NEAR(model.predict(samples).mean.y(), loaded.predict(samples).mean.y(), 1e-15);
  EXPECT_TRUE(model.predict(samples).covariance.isApprox(loaded.predict(samples).covariance));
}

TEST(LinearModel, RefusesDegenerateInput)
{
  const auto train = pairs(0.2, 6);
  LinearModel model({train.joints});
  EXPECT_THROW(model.fit({train.pairs.begin(), train.pairs.begin() + 4}), std::invalid_argument);
  std::vector<MotionPair> frozen = train.pairs;  // the right wheel never reports
  for (auto& pair : frozen) {
    for (auto& sample : pair.encoder_samples)
      sample.values(1) = 0.0;
  }
  EXPECT_THROW(model.fit(frozen), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
