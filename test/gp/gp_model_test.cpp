// GaussianProcessModel on simulated keyframe pairs with known truth and noise: options, errors,
// save/load, outlier rejection, sparse against exact, and the acceptance of issue 12 (held-out
// RMSE at the noise floor for 0.1, 0.3 and 0.5 s keyframe intervals).
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "odometry_calibration/gp/gp_model.h"
#include "odometry_calibration/gp/gp_outliers.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

constexpr double kSigma = 0.002;  // the generator's noise on x, y [m] and theta [rad]

sim::GeneratedPairs generate(double interval_s, double duration_s, unsigned seed,
                             double slip_per_speed = 0.0)
{
  sim::PairGeneratorOptions options;
  options.interval_s = interval_s;
  options.duration_s = duration_s;
  options.seed = seed;
  options.translation_noise_m = kSigma;
  options.rotation_noise_rad = kSigma;
  if (slip_per_speed > 0.0) {
    options.robot.parameters["slip_per_speed"] = slip_per_speed;
  }
  return sim::generatePairs(options);
}

/// Whether the wheels turned at a constant rate over the pair (the drive plan did not switch
/// motions inside it): every encoder step within 2 ticks of the mean step.
bool isSteady(const MotionPair& pair)
{
  const auto& s = pair.encoder_samples;
  const auto steps = static_cast<double>(s.size() - 1);
  const Eigen::VectorXd mean_step = (s.back().values - s.front().values) / steps;
  for (std::size_t k = 1; k < s.size(); ++k) {
    if (((s[k].values - s[k - 1].values) - mean_step).cwiseAbs().maxCoeff() > 2.0) {
      return false;
    }
  }
  return true;
}

/// Per-axis RMS of (prediction - reference) over the selected pairs.
template <typename Predict>
Eigen::Vector3d rmse(const sim::GeneratedPairs& data, const Predict& predict, bool against_truth,
                     bool steady_only = false)
{
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  int count = 0;
  for (std::size_t i = 0; i < data.pairs.size(); ++i) {
    if (steady_only && !isSteady(data.pairs[i])) {
      continue;
    }
    const Eigen::Vector3d reference =
        against_truth ? data.true_motions[i].vector() : data.pairs[i].sensor_motion.vector();
    Eigen::Vector3d error = predict(data.pairs[i]) - reference;
    error(2) = normalizeAngle(error(2));
    sum += error.cwiseAbs2();
    ++count;
  }
  return (sum / std::max(count, 1)).cwiseSqrt();
}

Eigen::Vector3d modelRmse(const GaussianProcessModel& model, const sim::GeneratedPairs& data,
                          bool against_truth, bool steady_only = false)
{
  return rmse(
      data,
      [&](const MotionPair& pair) { return model.predict(pair.encoder_samples).mean.vector(); },
      against_truth, steady_only);
}

TEST(GpOptions, ValidationNamesTheOption)
{
  const auto message = [](const GpOptions& options) {
    try {
      validate(options);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  GpOptions options;
  EXPECT_EQ(message(options), "");
  options.starts = 0;
  EXPECT_NE(message(options).find("starts"), std::string::npos);
  options = GpOptions();
  options.likelihood_subset = 5;
  EXPECT_NE(message(options).find("likelihood_subset"), std::string::npos);
  options = GpOptions();
  options.refine_subset = 100;
  EXPECT_NE(message(options).find("refine_subset"), std::string::npos);
  options = GpOptions();
  options.outlier_threshold = std::nan("");
  EXPECT_NE(message(options).find("outlier_threshold"), std::string::npos);
  options = GpOptions();
  options.num_threads = -1;
  EXPECT_NE(message(options).find("num_threads"), std::string::npos);
  EXPECT_EQ(parseGpKernelType(toString(GpKernelType::kRbfPlusLinear)),
            GpKernelType::kRbfPlusLinear);
  EXPECT_THROW(parseGpKernelType("matern"), std::invalid_argument);
  EXPECT_THROW(GaussianProcessModel(GpOptions(), JointLayout()), std::invalid_argument);
}

TEST(GpModel, FailsFastWithActionableErrors)
{
  const sim::GeneratedPairs data = generate(0.3, 20.0, 1);
  GaussianProcessModel model(GpOptions(), data.joints);
  EXPECT_THROW(model.predict(data.pairs.front().encoder_samples), std::logic_error);
  const std::vector<MotionPair> few(data.pairs.begin(), data.pairs.begin() + 5);
  EXPECT_THROW(model.fit(few), std::invalid_argument);
  std::vector<MotionPair> parked = data.pairs;
  for (MotionPair& pair : parked) {
    for (EncoderSample& sample : pair.encoder_samples) {
      sample.values = pair.encoder_samples.front().values;  // the wheels never turn
    }
  }
  EXPECT_THROW(model.fit(parked), std::invalid_argument);
  std::vector<MotionPair> broken = data.pairs;
  broken[3].encoder_samples.resize(1);
  try {
    model.fit(broken);
    FAIL() << "a pair with one sample must be rejected";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("pair 3"), std::string::npos);
  }
}

TEST(GpModel, ReportDescribesTheFit)
{
  const sim::GeneratedPairs data = generate(0.3, 60.0, 2);
  GaussianProcessModel model(GpOptions(), data.joints);
  const ModelReport report = model.fit(data.pairs);
  EXPECT_EQ(report.model, "gp");
  EXPECT_EQ(report.pairs_used, data.pairs.size());
  EXPECT_LE(report.outliers, data.pairs.size() / 50);
  EXPECT_TRUE(report.converged) << report.termination;
  EXPECT_GT(report.iterations, 0);
  EXPECT_GT(report.fit_time_s, 0.0);
  EXPECT_NE(report.termination.find("exact GP"), std::string::npos);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_GT(report.residual_rms_xytheta(axis), 0.7 * kSigma);
    EXPECT_LT(report.residual_rms_xytheta(axis), 1.3 * kSigma);
  }
  EXPECT_EQ(report.after.count, data.pairs.size());
  bool has_length_scale = false;
  for (const ParameterEstimate& p : report.parameters) {
    EXPECT_TRUE(std::isnan(p.sigma));
    has_length_scale |= p.name == "y.length_scale." + data.joints.names[0];
  }
  EXPECT_TRUE(has_length_scale);
  // The noise sigma is a pair's: its own covariance plus the learned extra, so never below the
  // pairs' measurement noise (the extra alone can be ~0 when the covariance explains the
  // scatter); the extra is reported beside it.
  for (int axis = 0; axis < 3; ++axis) {
    const std::string name = std::string(axis == 0 ? "x" : axis == 1 ? "y" : "theta");
    double total = -1.0, extra = -1.0;
    for (const ParameterEstimate& p : report.parameters) {
      if (p.name == name + ".noise_sigma")
        total = p.value;
      if (p.name == name + ".extra_noise_sigma")
        extra = p.value;
    }
    double known = 0.0;
    for (const MotionPair& pair : data.pairs)
      known += pair.covariance(axis, axis);
    known /= static_cast<double>(data.pairs.size());
    EXPECT_NEAR(extra, std::sqrt(model.output(axis).noise_variance), 1e-15) << name;
    EXPECT_NEAR(total * total, known + extra * extra, 1e-9 * (known + extra * extra)) << name;
    EXPECT_GE(total, std::sqrt(known)) << name;
  }
}

TEST(GpModel, SaveLoadPredictsIdentically)
{
  const sim::GeneratedPairs train = generate(0.3, 60.0, 3);
  const sim::GeneratedPairs test = generate(0.3, 20.0, 4);
  GpOptions sparse_options;
  sparse_options.kernel = GpKernelType::kRbfPlusLinear;
  sparse_options.max_exact_pairs = 20;
  sparse_options.inducing_points = 24;
  for (const GpOptions& options : {GpOptions(), sparse_options}) {
    GaussianProcessModel model(options, train.joints);
    model.fit(train.pairs);
    const std::string yaml = model.toYaml();
    const std::unique_ptr<GaussianProcessModel> loaded = GaussianProcessModel::fromYaml(yaml);
    EXPECT_EQ(loaded->toYaml(), yaml);
    EXPECT_EQ(loaded->output(1).posterior.kind(), model.output(1).posterior.kind());
    for (const MotionPair& pair : test.pairs) {
      const MotionPrediction a = model.predict(pair.encoder_samples);
      const MotionPrediction b = loaded->predict(pair.encoder_samples);
      EXPECT_NEAR((a.mean.vector() - b.mean.vector()).norm(), 0.0, 1e-9);
      EXPECT_NEAR((a.covariance - b.covariance).norm(), 0.0, 1e-9);
    }
  }
  EXPECT_THROW(GaussianProcessModel::fromYaml("model: linear\n"), std::runtime_error);
  EXPECT_THROW(GaussianProcessModel::fromYaml("model: gp\njoints: []\n"), std::runtime_error);
}

TEST(GpModel, ThreadsDoNotChangeTheResult)
{
  const sim::GeneratedPairs train = generate(0.5, 60.0, 5);
  GpOptions one;
  one.num_threads = 1;
  GpOptions three;
  three.num_threads = 3;
  GaussianProcessModel a(one, train.joints);
  GaussianProcessModel b(three, train.joints);
  a.fit(train.pairs);
  b.fit(train.pairs);
  const auto without_threads = [](std::string yaml) {
    const auto begin = yaml.find("num_threads");
    return yaml.erase(begin, yaml.find('\n', begin) - begin);
  };
  EXPECT_EQ(without_threads(a.toYaml()), without_threads(b.toYaml()));
}

TEST(GpModel, RejectsGrossOutliersItself)
{
  const sim::GeneratedPairs clean = generate(0.3, 150.0, 6);
  const sim::GeneratedPairs test = generate(0.3, 120.0, 7);
  // 3 % scan-matching failures: displacements off by 2-30 cm / 0.05-0.5 rad.
  std::vector<MotionPair> dirty = clean.pairs;
  std::mt19937 rng(8);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::size_t injected = 0;
  for (MotionPair& pair : dirty) {
    if (unit(rng) > 0.03) {
      continue;
    }
    const double sign = unit(rng) < 0.5 ? -1.0 : 1.0;
    const Eigen::Vector3d offset(sign * (0.02 + 0.28 * unit(rng)), 0.1 * (unit(rng) - 0.5),
                                 sign * (0.05 + 0.45 * unit(rng)));
    pair.sensor_motion = Pose2::fromVector(pair.sensor_motion.vector() + offset);
    ++injected;
  }
  ASSERT_GE(injected, 10u);
  GaussianProcessModel clean_model(GpOptions(), clean.joints);
  clean_model.fit(clean.pairs);
  GaussianProcessModel robust_model(GpOptions(), clean.joints);
  const ModelReport report = robust_model.fit(dirty);
  EXPECT_GE(report.outliers, injected);
  EXPECT_LE(report.outliers, injected + dirty.size() / 50);
  EXPECT_EQ(report.rejected, report.outliers);
  EXPECT_EQ(report.down_weighted, 0u);
  const Eigen::Vector3d clean_rmse = modelRmse(clean_model, test, false);
  const Eigen::Vector3d robust_rmse = modelRmse(robust_model, test, false);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(robust_rmse(axis), 1.2 * clean_rmse(axis)) << "axis " << axis;
  }
  // Without rejection the same data give a visibly worse model (the test can fail).
  GpOptions naive;
  naive.outlier_threshold = 0.0;
  GaussianProcessModel naive_model(naive, clean.joints);
  EXPECT_EQ(naive_model.fit(dirty).outliers, 0u);
  const Eigen::Vector3d naive_rmse = modelRmse(naive_model, test, false);
  EXPECT_GT(naive_rmse.maxCoeff(), 1.2 * clean_rmse.maxCoeff());
  std::printf(
      "%zu injected, %zu rejected; held-out RMSE / sigma x y theta: clean %.3f %.3f "
      "%.3f, robust %.3f %.3f %.3f, no rejection %.3f %.3f %.3f\n",
      injected, report.outliers, clean_rmse(0) / kSigma, clean_rmse(1) / kSigma,
      clean_rmse(2) / kSigma, robust_rmse(0) / kSigma, robust_rmse(1) / kSigma,
      robust_rmse(2) / kSigma, naive_rmse(0) / kSigma, naive_rmse(1) / kSigma,
      naive_rmse(2) / kSigma);
}

TEST(GpModel, SparseMatchesExactOnHeldOutPairs)
{
  const sim::GeneratedPairs train = generate(0.3, 300.0, 9);
  const sim::GeneratedPairs test = generate(0.3, 120.0, 10);
  GpOptions exact_options;
  exact_options.kernel = GpKernelType::kRbfPlusLinear;
  GpOptions sparse_options = exact_options;
  sparse_options.max_exact_pairs = 100;
  sparse_options.inducing_points = 64;
  GaussianProcessModel exact(exact_options, train.joints);
  GaussianProcessModel sparse(sparse_options, train.joints);
  exact.fit(train.pairs);
  const ModelReport report = sparse.fit(train.pairs);
  ASSERT_NE(report.termination.find("sparse GP"), std::string::npos);
  const Eigen::Vector3d exact_rmse = modelRmse(exact, test, false);
  const Eigen::Vector3d sparse_rmse = modelRmse(sparse, test, false);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(sparse_rmse(axis), 1.02 * exact_rmse(axis)) << "axis " << axis;
  }
  std::printf(
      "held-out RMSE / sigma x y theta: exact %.4f %.4f %.4f, sparse (64 inducing) "
      "%.4f %.4f %.4f\n",
      exact_rmse(0) / kSigma, exact_rmse(1) / kSigma, exact_rmse(2) / kSigma,
      sparse_rmse(0) / kSigma, sparse_rmse(1) / kSigma, sparse_rmse(2) / kSigma);
}

/// The model-free floor of a test set: RMS error against the truth of the best function of the
/// encoder features, approximated by least squares of a degree-5 polynomial in the features on
/// the noise-free motions of a long run. Pairs in which the drive switched motions have a
/// displacement that depends on the path, not only on the wheel increments.
Eigen::Vector3d modelFreeFloor(double interval_s, const sim::GeneratedPairs& test)
{
  const sim::GeneratedPairs reference = generate(interval_s, 900.0, 99);
  const auto features = [&](const sim::GeneratedPairs& data) {
    Eigen::MatrixXd f(2, static_cast<Eigen::Index>(data.pairs.size()));
    for (std::size_t i = 0; i < data.pairs.size(); ++i) {
      f.col(static_cast<Eigen::Index>(i)) =
          pairFeatures(data.pairs[i].encoder_samples, data.joints);
    }
    return f;
  };
  const Eigen::MatrixXd reference_features = features(reference);
  const Eigen::VectorXd scale =
      (reference_features.rowwise().squaredNorm() / reference_features.cols()).cwiseSqrt();
  const Eigen::MatrixXd basis =
      polynomialFeatures(scale.cwiseInverse().asDiagonal() * reference_features, 5);
  Eigen::MatrixXd truth(reference.pairs.size(), 3);
  for (std::size_t i = 0; i < reference.pairs.size(); ++i) {
    truth.row(static_cast<Eigen::Index>(i)) = reference.true_motions[i].vector().transpose();
  }
  const Eigen::MatrixXd coefficients = basis.transpose().colPivHouseholderQr().solve(truth);
  const Eigen::MatrixXd test_basis =
      polynomialFeatures(scale.cwiseInverse().asDiagonal() * features(test), 5);
  std::size_t index = 0;
  return rmse(
      test,
      [&](const MotionPair&) {
        return Eigen::Vector3d(test_basis.col(static_cast<Eigen::Index>(index++)).transpose() *
                               coefficients);
      },
      true);
}

class GpAcceptance : public ::testing::TestWithParam<double>
{
};

// Issue 12: the GP with linear mean and RBF kernel predicts held-out displacements with RMSE
// within 20 % of the noise floor on every axis at 0.1, 0.3 and 0.5 s. The floor of a pair is the
// added noise sigma plus what no function of the wheel increments can know: inside a keyframe
// interval in which the drive switched motions, the displacement depends on the path.
TEST_P(GpAcceptance, HeldOutRmseAtTheNoiseFloor)
{
  const double interval_s = GetParam();
  const sim::GeneratedPairs train = generate(interval_s, 180.0, 21);
  const sim::GeneratedPairs test = generate(interval_s, 120.0, 22);
  GpOptions options;
  options.mean = GpMeanFunction::kLinear;
  options.kernel = GpKernelType::kRbf;
  GaussianProcessModel model(options, train.joints);
  const ModelReport report = model.fit(train.pairs);

  const Eigen::Vector3d steady = modelRmse(model, test, false, true) / kSigma;
  const Eigen::Vector3d all = modelRmse(model, test, false) / kSigma;
  const Eigen::Vector3d floor = modelFreeFloor(interval_s, test) / kSigma;
  const Eigen::Vector3d all_floor = (Eigen::Vector3d::Ones() + floor.cwiseAbs2()).cwiseSqrt();
  std::printf("interval %.1f s, %zu train pairs, %zu outliers, fit %.2f s\n", interval_s,
              train.pairs.size(), report.outliers, report.fit_time_s);
  std::printf("  RMSE / sigma, steady test pairs:  x %.3f  y %.3f  theta %.3f\n", steady(0),
              steady(1), steady(2));
  std::printf("  RMSE / sigma, all test pairs:     x %.3f  y %.3f  theta %.3f\n", all(0), all(1),
              all(2));
  std::printf("  floor / sigma, all test pairs:    x %.3f  y %.3f  theta %.3f\n", all_floor(0),
              all_floor(1), all_floor(2));
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(steady(axis), 1.2) << "axis " << axis;
    EXPECT_LE(all(axis), 1.2 * all_floor(axis)) << "axis " << axis;
  }
}

INSTANTIATE_TEST_SUITE_P(KeyframeIntervals, GpAcceptance, ::testing::Values(0.1, 0.3, 0.5));

TEST(GpModel, LearnsSpeedDependentSlip)
{
  // Effective wheel radius 10 % smaller at 0.6 m/s: not a fixed kinematic model, still a
  // function of the increments.
  const sim::GeneratedPairs train = generate(0.3, 180.0, 23, 0.1667);
  const sim::GeneratedPairs test = generate(0.3, 120.0, 24, 0.1667);
  GaussianProcessModel model(GpOptions(), train.joints);
  model.fit(train.pairs);
  const Eigen::Vector3d steady = modelRmse(model, test, false, true) / kSigma;
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_LE(steady(axis), 1.2) << "axis " << axis;
  }
}

TEST(GpModel, RadiansFromAJointStateMergeLikeTicks)
{
  // The same drive as JointState positions in radians (ticks * 2 pi / 4096): increments that are
  // the same number of ticks differ in their last bits, yet must merge as the ticks do.
  const sim::GeneratedPairs ticks = generate(0.3, 240.0, 8);
  sim::GeneratedPairs radians = ticks;
  const double radians_per_tick = 2.0 * M_PI / 4096.0;
  for (MotionPair& pair : radians.pairs) {
    for (EncoderSample& sample : pair.encoder_samples)
      sample.values *= radians_per_tick;
  }
  GpOptions options;
  options.num_threads = 1;
  GaussianProcessModel in_ticks(options, ticks.joints);
  GaussianProcessModel in_radians(options, radians.joints);
  in_ticks.fit(ticks.pairs);
  in_radians.fit(radians.pairs);
  ASSERT_FALSE(in_ticks.output(0).sparse);
  EXPECT_EQ(in_radians.output(0).posterior.basis().cols(),
            in_ticks.output(0).posterior.basis().cols());
  for (std::size_t i = 0; i < ticks.pairs.size(); i += 37) {
    const MotionPrediction a = in_ticks.predict(ticks.pairs[i].encoder_samples);
    const MotionPrediction b = in_radians.predict(radians.pairs[i].encoder_samples);
    EXPECT_NEAR(a.mean.x(), b.mean.x(), 1e-6);
    EXPECT_NEAR(a.mean.theta(), b.mean.theta(), 1e-6);
  }
}

TEST(GpModel, ReportsTheRefinementBudgetAsABudget)
{
  // More distinct inputs than likelihood_subset: the best start is refined for a fixed budget.
  // Using that budget up is its normal end and must say so, after the search's own ending.
  const sim::GeneratedPairs data = generate(0.3, 240.0, 9);
  GpOptions options;
  options.likelihood_subset = 100;
  options.refine_iterations = 2;
  GaussianProcessModel model(options, data.joints);
  const ModelReport report = model.fit(data.pairs);
  for (int axis = 0; axis < 3; ++axis) {
    const std::string& termination = model.output(axis).termination;
    EXPECT_NE(termination.find("search: "), std::string::npos) << termination;
    EXPECT_NE(termination.find("refinement: "), std::string::npos) << termination;
    EXPECT_EQ(termination.find("refinement: Maximum number of iterations"), std::string::npos)
        << termination;
  }
  EXPECT_NE(report.termination.find("used its budget of 2 iterations"), std::string::npos)
      << report.termination;
}

}  // namespace
}  // namespace odometry_calibration
