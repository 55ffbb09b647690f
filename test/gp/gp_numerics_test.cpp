// GP numerics against closed forms: kernels, the linear kernel as Bayesian linear regression,
// log marginal likelihood gradients against finite differences, posterior variance, the sparse
// GP with inducing inputs at the training inputs, and exact merging of repeated inputs.
#include <cmath>
#include <iostream>
#include <limits>
#include <random>

#include <gtest/gtest.h>
#include <Eigen/Dense>

#include "odometry_calibration/gp/gp_denormals.h"
#include "odometry_calibration/gp/gp_hyperparameters.h"
#include "odometry_calibration/gp/gp_inducing.h"
#include "odometry_calibration/gp/gp_inputs.h"
#include "odometry_calibration/gp/gp_kernel.h"
#include "odometry_calibration/gp/gp_likelihood.h"
#include "odometry_calibration/gp/gp_posterior.h"

namespace odometry_calibration {
namespace {

constexpr double kLog2Pi = 1.8378770664093453;

/// n pairs of a smooth 2-D function on a coarse integer grid (so inputs repeat), with per-pair
/// noise variances in [0.01, 0.05].
struct TestData
{
  Eigen::MatrixXd inputs;
  Eigen::VectorXd targets;
  Eigen::VectorXd variances;
};

TestData makeData(int n, unsigned seed, int grid = 4)
{
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> cell(-grid, grid);
  std::uniform_real_distribution<double> variance(0.01, 0.05);
  std::normal_distribution<double> normal(0.0, 1.0);
  TestData data;
  data.inputs.resize(2, n);
  data.targets.resize(n);
  data.variances.resize(n);
  for (int i = 0; i < n; ++i) {
    data.inputs(0, i) = 0.5 * cell(rng);
    data.inputs(1, i) = 0.4 * cell(rng);
    data.variances(i) = variance(rng);
    const double f = std::sin(data.inputs(0, i)) + 0.3 * data.inputs(1, i) * data.inputs(1, i) +
                     0.8 * data.inputs(1, i);
    data.targets(i) = f + std::sqrt(data.variances(i)) * normal(rng);
  }
  return data;
}

/// log N(y | mean, covariance), straight from the definition.
double logNormal(const Eigen::VectorXd& y, const Eigen::VectorXd& mean,
                 const Eigen::MatrixXd& covariance)
{
  const Eigen::LLT<Eigen::MatrixXd> llt(covariance);
  const Eigen::VectorXd r = y - mean;
  return -0.5 * r.dot(llt.solve(r)) - llt.matrixLLT().diagonal().array().log().sum() -
         0.5 * static_cast<double>(y.size()) * kLog2Pi;
}

GpOutputProblem makeProblem(const TestData& data, GpKernelType type, bool linear_mean, bool merge)
{
  GpOutputProblem problem;
  problem.kernel = GpKernel(type, 2);
  problem.groups = merge ? groupDuplicateInputs(data.inputs) : singletonGroups(data.inputs);
  problem.targets = data.targets;
  problem.known_variance = data.variances;
  problem.linear_mean = linear_mean;
  problem.learn_noise = true;
  problem.noise_floor = 1e-6;
  return problem;
}

Eigen::VectorXd someHyperparameters(const GpOutputProblem& problem)
{
  Eigen::VectorXd theta = initialHyperparameters(problem);
  // Move away from the heuristic start so that every gradient component is sizeable.
  for (Eigen::Index p = 0; p < theta.size(); ++p) {
    theta(p) += 0.1 * static_cast<double>(p % 3) - 0.05;
  }
  return theta;
}

TEST(GpKernel, MatricesFollowTheFormulas)
{
  const GpKernel kernel(GpKernelType::kRbfPlusLinear, 2);
  ASSERT_EQ(kernel.parameterCount(), 4);
  Eigen::VectorXd theta(4);
  theta << std::log(1.5), std::log(0.7), std::log(2.0), std::log(0.3);
  Eigen::MatrixXd a(2, 2), b(2, 1);
  a << 0.1, -1.0, 0.4, 2.0;
  b << 0.5, -0.3;
  const Eigen::MatrixXd k = kernel.cross(theta, a, b);
  for (int i = 0; i < 2; ++i) {
    const double d0 = (a(0, i) - b(0, 0)) / 0.7;
    const double d1 = (a(1, i) - b(1, 0)) / 2.0;
    const double expected =
        2.25 * std::exp(-0.5 * (d0 * d0 + d1 * d1)) + 0.09 * a.col(i).dot(b.col(0));
    EXPECT_NEAR(k(i, 0), expected, 1e-14);
  }
  const Eigen::MatrixXd gram = kernel.gram(theta, a);
  EXPECT_NEAR((gram - kernel.cross(theta, a, a)).norm(), 0.0, 1e-14);
  EXPECT_NEAR((kernel.diagonal(theta, a) - gram.diagonal()).norm(), 0.0, 1e-14);
}

TEST(GpExact, LinearKernelWithZeroMeanIsBayesianLinearRegression)
{
  const TestData data = makeData(25, 3);
  const GpKernel kernel(GpKernelType::kLinear, 2);
  const double prior_variance = 0.8;  // w ~ N(0, sigma_l^2 I)
  const Eigen::VectorXd theta = Eigen::VectorXd::Constant(1, 0.5 * std::log(prior_variance));
  const GpPosterior gp =
      GpPosterior::exact(kernel, theta, data.inputs, data.targets, data.variances);
  // Weight-space posterior: A = X S^-1 X^T + I / sigma_l^2, w_mean = A^-1 X S^-1 y.
  const Eigen::MatrixXd x = data.inputs;
  const Eigen::VectorXd precision = data.variances.cwiseInverse();
  Eigen::MatrixXd a = x * precision.asDiagonal() * x.transpose();
  a.diagonal().array() += 1.0 / prior_variance;
  const Eigen::MatrixXd a_inverse = a.inverse();
  const Eigen::VectorXd w_mean = a_inverse * x * precision.cwiseProduct(data.targets);
  for (const Eigen::Vector2d& test : {Eigen::Vector2d(0.3, -0.7), Eigen::Vector2d(2.5, 1.5)}) {
    double mean = 0.0;
    double variance = 0.0;
    gp.predict(test, &mean, &variance);
    EXPECT_NEAR(mean, test.dot(w_mean), 1e-10);
    EXPECT_NEAR(variance, test.dot(a_inverse * test), 1e-10);
  }
  // Marginal likelihood: y ~ N(0, sigma_l^2 X^T X + S).
  GpRegressionData regression{data.inputs, data.targets, data.variances, Eigen::MatrixXd(0, 25)};
  GpLikelihood likelihood;
  ASSERT_TRUE(exactLogMarginalLikelihood(kernel, theta, regression, false, &likelihood));
  Eigen::MatrixXd covariance = prior_variance * x.transpose() * x;
  covariance.diagonal() += data.variances;
  EXPECT_NEAR(likelihood.value, logNormal(data.targets, Eigen::VectorXd::Zero(25), covariance),
              1e-9);
}

TEST(GpExact, ProfiledLinearMeanIsGeneralisedLeastSquares)
{
  const TestData data = makeData(30, 4);
  const GpKernel kernel(GpKernelType::kRbf, 2);
  const Eigen::Vector3d theta(std::log(0.5), std::log(1.2), std::log(0.8));
  GpRegressionData regression{data.inputs, data.targets, data.variances, data.inputs};
  GpLikelihood likelihood;
  ASSERT_TRUE(exactLogMarginalLikelihood(kernel, theta, regression, false, &likelihood));
  Eigen::MatrixXd covariance = kernel.gram(theta, data.inputs);
  covariance.diagonal() += data.variances;
  // The profiled C maximises the likelihood: any other C gives less.
  const Eigen::VectorXd mean = data.inputs.transpose() * likelihood.mean_coefficients;
  EXPECT_NEAR(likelihood.value, logNormal(data.targets, mean, covariance), 1e-9);
  for (int k = 0; k < 2; ++k) {
    Eigen::VectorXd other = likelihood.mean_coefficients;
    other(k) += 1e-3;
    EXPECT_LT(logNormal(data.targets, data.inputs.transpose() * other, covariance),
              likelihood.value);
  }
}

struct GradientCase
{
  GpKernelType kernel;
  bool linear_mean;
  bool sparse;
};

class GpGradient : public ::testing::TestWithParam<GradientCase>
{
};

TEST_P(GpGradient, MatchesCentralDifferencesForEveryHyperparameter)
{
  const GradientCase c = GetParam();
  const TestData data = makeData(40, 5);
  GpOutputProblem problem = makeProblem(data, c.kernel, c.linear_mean, true);
  ASSERT_LT(problem.groups.size(), 40);  // the data do repeat inputs
  if (c.sparse) {
    problem.inducing_inputs = selectInducingInputs(problem.groups.inputs, 6, 1);
  }
  const GpOutputObjective objective(problem);
  const Eigen::VectorXd theta = someHyperparameters(problem);
  double value = 0.0;
  Eigen::VectorXd gradient;
  ASSERT_TRUE(objective.evaluate(theta, &value, &gradient));
  ASSERT_EQ(gradient.size(), objective.parameterCount());
  const double h = 1e-5;
  for (Eigen::Index p = 0; p < theta.size(); ++p) {
    Eigen::VectorXd plus = theta;
    Eigen::VectorXd minus = theta;
    plus(p) += h;
    minus(p) -= h;
    double f_plus = 0.0;
    double f_minus = 0.0;
    ASSERT_TRUE(objective.evaluate(plus, &f_plus, nullptr));
    ASSERT_TRUE(objective.evaluate(minus, &f_minus, nullptr));
    const double numeric = (f_plus - f_minus) / (2.0 * h);
    EXPECT_NEAR(gradient(p), numeric, 1e-5 * std::max(1.0, std::abs(numeric)))
        << "parameter " << p << " of " << toString(c.kernel)
        << (c.linear_mean ? ", linear mean" : ", zero mean") << (c.sparse ? ", VFE" : ", exact");
  }
}

INSTANTIATE_TEST_SUITE_P(AllKernels, GpGradient,
                         ::testing::Values(GradientCase{GpKernelType::kRbf, false, false},
                                           GradientCase{GpKernelType::kRbf, true, false},
                                           GradientCase{GpKernelType::kLinear, false, false},
                                           GradientCase{GpKernelType::kLinear, true, false},
                                           GradientCase{GpKernelType::kRbfPlusLinear, false, false},
                                           GradientCase{GpKernelType::kRbfPlusLinear, true, false},
                                           GradientCase{GpKernelType::kRbf, false, true},
                                           GradientCase{GpKernelType::kRbf, true, true},
                                           GradientCase{GpKernelType::kLinear, true, true},
                                           GradientCase{GpKernelType::kRbfPlusLinear, false, true},
                                           GradientCase{GpKernelType::kRbfPlusLinear, true, true}));

TEST(GpGradientLarge, MatchesCentralDifferencesWithBlockedInverse)
{
  // 150 distinct inputs: the blocked triangular inverse recurses several levels.
  const TestData data = makeData(150, 11, 200);
  const GpOutputProblem problem = makeProblem(data, GpKernelType::kRbfPlusLinear, true, true);
  ASSERT_GT(problem.groups.size(), 140);
  const GpOutputObjective objective(problem);
  const Eigen::VectorXd theta = someHyperparameters(problem);
  double value = 0.0;
  Eigen::VectorXd gradient;
  ASSERT_TRUE(objective.evaluate(theta, &value, &gradient));
  for (Eigen::Index p = 0; p < theta.size(); ++p) {
    Eigen::VectorXd plus = theta;
    Eigen::VectorXd minus = theta;
    plus(p) += 1e-5;
    minus(p) -= 1e-5;
    double f_plus = 0.0;
    double f_minus = 0.0;
    ASSERT_TRUE(objective.evaluate(plus, &f_plus, nullptr));
    ASSERT_TRUE(objective.evaluate(minus, &f_minus, nullptr));
    const double numeric = (f_plus - f_minus) / 2e-5;
    EXPECT_NEAR(gradient(p), numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << "parameter " << p;
  }
}

TEST(GpExact, PosteriorVarianceShrinksAtTrainingInputs)
{
  const TestData data = makeData(30, 6);
  const GpKernel kernel(GpKernelType::kRbf, 2);
  const Eigen::Vector3d theta(std::log(1.0), std::log(0.6), std::log(0.6));
  const GpPosterior gp =
      GpPosterior::exact(kernel, theta, data.inputs, data.targets, data.variances);
  for (Eigen::Index i = 0; i < data.inputs.cols(); ++i) {
    double mean = 0.0;
    double variance = 0.0;
    gp.predict(data.inputs.col(i), &mean, &variance);
    EXPECT_LT(variance, data.variances(i));  // below the noise of the pair at that input
    EXPECT_GE(variance, 0.0);
  }
  double mean = 0.0;
  double far_variance = 0.0;
  gp.predict(Eigen::Vector2d(40.0, -40.0), &mean, &far_variance);
  EXPECT_NEAR(far_variance, 1.0, 1e-12);  // back to the prior far from the data
  EXPECT_NEAR(mean, 0.0, 1e-12);
}

TEST(GpExact, LargePosteriorPredictsItsVarianceInLowRankCloseToTheExactOne)
{
  // 2000 distinct inputs (above kGpLowRankVarianceInputs): the variance comes from the
  // projection on kGpVarianceInducingInputs inducing inputs, O(M^2) per prediction.
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  const int n = 2000;
  TestData data;
  data.inputs.resize(2, n);
  data.targets.resize(n);
  data.variances = Eigen::VectorXd::Constant(n, 0.02);
  for (int i = 0; i < n; ++i) {
    data.inputs(0, i) = uniform(rng);
    data.inputs(1, i) = uniform(rng);
    data.targets(i) = std::sin(data.inputs(0, i)) + 0.5 * data.inputs(1, i);
  }
  const GpKernel kernel(GpKernelType::kRbf, 2);
  const Eigen::Vector3d theta(std::log(1.0), std::log(0.6), std::log(0.6));
  const GpPosterior gp =
      GpPosterior::exact(kernel, theta, data.inputs, data.targets, data.variances);
  ASSERT_TRUE(gp.lowRankVariance());
  EXPECT_TRUE(gp.projectedMean());
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d x(1.2 * uniform(rng), 1.2 * uniform(rng));  // inside and around
    double mean = 0.0, variance = 0.0;
    gp.predict(x, &mean, &variance);
    const double exact = gp.exactVariance(x);
    // The projected mean is checked against the exact one at construction (1 % of the noise
    // sigma on the training inputs); here it must hold where the data are.
    if (x.cwiseAbs().maxCoeff() < 1.8) {
      EXPECT_NEAR(mean, gp.means(x).coeff(0), 0.01 * std::sqrt(0.02)) << x.transpose();
    }
    // Where the data are, the projection is exact to 1e-4 of the prior variance (1); beyond
    // their edge it errs on the safe side, by at most 10 %.
    EXPECT_GE(variance, exact - 1e-4) << x.transpose();
    EXPECT_LE(variance, 1.1 * exact + 1e-4) << x.transpose();
    if (x.cwiseAbs().maxCoeff() < 1.8) {
      EXPECT_NEAR(variance, exact, 1e-4) << x.transpose();
    }
  }
  // A small posterior keeps the exact variance.
  const TestData small = makeData(30, 6);
  EXPECT_FALSE(GpPosterior::exact(kernel, theta, small.inputs, small.targets, small.variances)
                   .lowRankVariance());
}

TEST(GpExact, MidSizePosteriorPredictsInLowRankLikeLargeOnes)
{
  // 900 distinct inputs (issue 33: one fast path above M = 200 inputs): the variance through the
  // projection and the mean projected as on large sets, the mean within 1 % of the noise sigma
  // of the exact one (the check at construction) where the data are.
  std::mt19937 rng(12);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  const int n = 900;
  TestData data;
  data.inputs.resize(2, n);
  data.targets.resize(n);
  data.variances = Eigen::VectorXd::Constant(n, 0.02);
  for (int i = 0; i < n; ++i) {
    data.inputs(0, i) = uniform(rng);
    data.inputs(1, i) = uniform(rng);
    data.targets(i) = std::sin(data.inputs(0, i)) + 0.5 * data.inputs(1, i);
  }
  const GpKernel kernel(GpKernelType::kRbf, 2);
  const Eigen::Vector3d theta(std::log(1.0), std::log(0.6), std::log(0.6));
  const GpPosterior gp =
      GpPosterior::exact(kernel, theta, data.inputs, data.targets, data.variances);
  ASSERT_TRUE(gp.lowRankVariance());
  EXPECT_TRUE(gp.projectedMean());
  for (int i = 0; i < 300; ++i) {
    const Eigen::Vector2d x(1.2 * uniform(rng), 1.2 * uniform(rng));
    double mean = 0.0, variance = 0.0;
    gp.predict(x, &mean, &variance);
    const double exact_mean = kernel.cross(theta, data.inputs, x).col(0).dot(gp.weights());
    if (x.cwiseAbs().maxCoeff() < 1.8) {
      EXPECT_NEAR(mean, exact_mean, 0.01 * std::sqrt(0.02)) << x.transpose();
    }
    // Where the data are, exact to 1e-4 of the prior variance; beyond their edge (up to 0.4
    // beyond, where M = 200 of 900 inputs cover less) on the safe side by at most 15 %.
    const double exact = gp.exactVariance(x);
    EXPECT_GE(variance, exact - 1e-4) << x.transpose();
    EXPECT_LE(variance, 1.15 * exact + 1e-4) << x.transpose();
    if (x.cwiseAbs().maxCoeff() < 1.8) {
      EXPECT_NEAR(variance, exact, 1e-4) << x.transpose();
    }
  }
}

TEST(GpDenormals, FlushedInScopeRestoredAfterAndPredictionsUnchanged)
{
  // Kernel values far from the data underflow into denormals (exp(-q/2), q ~ 1416-1490): within
  // DenormalsAsZero they are flushed, which moves a prediction by less than 1e-9 relative.
  volatile double tiny = 1e-310;  // a denormal
  volatile double one = 1.0;
  EXPECT_EQ(tiny * one, 1e-310);
  const TestData data = makeData(300, 9, 40);  // inputs on a wide grid (+-20, +-16)
  const GpKernel kernel(GpKernelType::kRbfPlusLinear, 2);
  // Length scale 0.5: kernel values between inputs 19 apart are exp(-722), denormal.
  const Eigen::Vector4d theta(std::log(1.0), std::log(0.5), std::log(0.5), std::log(0.3));
  const GpPosterior gp =
      GpPosterior::exact(kernel, theta, data.inputs, data.targets, data.variances);
  const GpKernel rbf(GpKernelType::kRbf, 2);  // the term that underflows
  int denormal_columns = 0;
  for (int i = 0; i < 200; ++i) {
    const Eigen::Vector2d x = data.inputs.col(i) + Eigen::Vector2d(0.013 * i, -0.007 * i);
    const Eigen::VectorXd k = rbf.cross(theta.head<3>(), data.inputs, x).col(0);
    denormal_columns +=
        (k.array().abs() < std::numeric_limits<double>::min() && k.array() != 0.0).any() ? 1 : 0;
    double mean = 0.0, variance = 0.0, flushed_mean = 0.0, flushed_variance = 0.0;
    gp.predict(x, &mean, &variance);
    {
      const DenormalsAsZero denormals_as_zero;
      EXPECT_EQ(tiny * one, 0.0);
      gp.predict(x, &flushed_mean, &flushed_variance);
    }
    EXPECT_NEAR(flushed_mean, mean, 1e-9 * std::abs(mean));
    EXPECT_NEAR(flushed_variance, variance, 1e-9 * std::abs(variance));
  }
  EXPECT_GT(denormal_columns, 0);  // the case is exercised
  EXPECT_EQ(tiny * one, 1e-310);   // the mode was restored
}

TEST(GpSparse, EqualsTheExactGpWhenInducingInputsAreTheTrainingInputs)
{
  const TestData data = makeData(30, 7, 20);  // fine grid: distinct inputs
  for (const GpKernelType type : {GpKernelType::kRbf, GpKernelType::kRbfPlusLinear}) {
    GpOutputProblem problem = makeProblem(data, type, true, true);
    const Eigen::VectorXd theta = someHyperparameters(problem);
    const GpOutputObjective exact(problem);
    GpOutputProblem sparse_problem = problem;
    sparse_problem.inducing_inputs = problem.groups.inputs;
    const GpOutputObjective sparse(sparse_problem);
    double exact_value = 0.0;
    double sparse_value = 0.0;
    Eigen::VectorXd exact_gradient;
    Eigen::VectorXd sparse_gradient;
    ASSERT_TRUE(exact.evaluate(theta, &exact_value, &exact_gradient));
    ASSERT_TRUE(sparse.evaluate(theta, &sparse_value, &sparse_gradient));
    EXPECT_NEAR(sparse_value, exact_value, 1e-6 * std::abs(exact_value));
    EXPECT_LT((sparse_gradient - exact_gradient).norm(), 1e-5 * (1.0 + exact_gradient.norm()));

    const GpRegressionData regression = exact.regressionData(theta);
    const Eigen::VectorXd kernel_theta = theta.head(problem.kernel.parameterCount());
    const GpPosterior a = GpPosterior::exact(problem.kernel, kernel_theta, regression.inputs,
                                             regression.targets, regression.noise_variance);
    const GpPosterior b =
        GpPosterior::sparse(problem.kernel, kernel_theta, regression.inputs, regression.targets,
                            regression.noise_variance, regression.inputs);
    for (const Eigen::Vector2d& x : {Eigen::Vector2d(0.2, 0.1), Eigen::Vector2d(-1.7, 0.9)}) {
      double mean_a = 0.0, var_a = 0.0, mean_b = 0.0, var_b = 0.0;
      a.predict(x, &mean_a, &var_a);
      b.predict(x, &mean_b, &var_b);
      EXPECT_NEAR(mean_b, mean_a, 1e-6);
      EXPECT_NEAR(var_b, var_a, 1e-6);
    }
  }
}

TEST(GpSparse, BoundIsBelowTheExactLikelihoodWithFewInducingInputs)
{
  const TestData data = makeData(40, 8, 20);
  GpOutputProblem problem = makeProblem(data, GpKernelType::kRbf, true, true);
  const Eigen::VectorXd theta = someHyperparameters(problem);
  double exact_value = 0.0;
  ASSERT_TRUE(GpOutputObjective(problem).evaluate(theta, &exact_value, nullptr));
  problem.inducing_inputs = selectInducingInputs(problem.groups.inputs, 5, 2);
  double bound = 0.0;
  ASSERT_TRUE(GpOutputObjective(problem).evaluate(theta, &bound, nullptr));
  EXPECT_LT(bound, exact_value);
}

TEST(GpOptimiser, AStartAtTheOptimumReportsItsIterationsAsTheyAre)
{
  // A warm start at the optimum: the node's refit logged "stopped after -1 of 15 iterations"
  // (Ceres keeps no iteration record when the start already meets its tolerance).
  const TestData data = makeData(40, 8, 20);
  const GpOutputProblem problem = makeProblem(data, GpKernelType::kRbf, true, true);
  const GpOutputObjective objective(problem);
  const GpOptimizationResult first =
      maximizeLogLikelihood(objective, someHyperparameters(problem), 200);
  ASSERT_GT(first.iterations, 0);
  GpOptimizationResult again = first;
  for (int run = 0; run < 5 && again.iterations > 0; ++run)
    again = maximizeLogLikelihood(objective, again.hyperparameters, 15);
  EXPECT_GE(again.iterations, 0);
  EXPECT_LE(again.iterations, 15);
  EXPECT_FALSE(again.termination.empty());
  EXPECT_EQ(again.termination.find("-1"), std::string::npos) << again.termination;
  EXPECT_NEAR(again.log_likelihood, first.log_likelihood, 1e-6 * std::abs(first.log_likelihood));
  std::cout << "[ gp ] restart at the optimum: " << again.iterations
            << " iterations, termination: " << again.termination << "\n";
}

TEST(GpInputs, MergeConstantIsTheExactLikelihoodRatio)
{
  Eigen::VectorXd y(3), s(3);
  y << 0.3, 0.5, 0.1;
  s << 0.01, 0.04, 0.02;
  const GpInputGroups groups = groupDuplicateInputs(Eigen::MatrixXd::Zero(1, 3));
  ASSERT_EQ(groups.size(), 1);
  const double eta = 0.005;
  const GpMergedTargets merged = mergeGroupTargets(groups, y, s, eta);
  for (const double f : {-0.2, 0.25, 1.0}) {
    double separate = 0.0;
    for (int i = 0; i < 3; ++i) {
      const double lambda = s(i) + eta;
      separate += -0.5 * (y(i) - f) * (y(i) - f) / lambda - 0.5 * std::log(2 * M_PI * lambda);
    }
    const double v = merged.variance(0);
    const double joint =
        -0.5 * (merged.targets(0) - f) * (merged.targets(0) - f) / v - 0.5 * std::log(2 * M_PI * v);
    EXPECT_NEAR(separate, joint + merged.log_constant, 1e-12);
  }
}

TEST(GpInputs, MergingDuplicatesEqualsTheUnmergedExactGp)
{
  const TestData data = makeData(60, 9, 2);  // 25 cells for 60 pairs
  for (const bool linear_mean : {false, true}) {
    const GpOutputProblem merged_problem =
        makeProblem(data, GpKernelType::kRbfPlusLinear, linear_mean, true);
    const GpOutputProblem plain_problem =
        makeProblem(data, GpKernelType::kRbfPlusLinear, linear_mean, false);
    ASSERT_LT(merged_problem.groups.size(), 30);
    ASSERT_EQ(plain_problem.groups.size(), 60);
    const Eigen::VectorXd theta = someHyperparameters(plain_problem);
    const GpOutputObjective merged(merged_problem);
    const GpOutputObjective plain(plain_problem);
    double merged_value = 0.0, plain_value = 0.0;
    Eigen::VectorXd merged_gradient, plain_gradient, merged_c, plain_c;
    ASSERT_TRUE(merged.evaluate(theta, &merged_value, &merged_gradient, &merged_c));
    ASSERT_TRUE(plain.evaluate(theta, &plain_value, &plain_gradient, &plain_c));
    EXPECT_NEAR(merged_value, plain_value, 1e-9 * std::abs(plain_value));
    EXPECT_LT((merged_gradient - plain_gradient).norm(), 1e-8 * (1.0 + plain_gradient.norm()));
    if (linear_mean) {
      EXPECT_LT((merged_c - plain_c).norm(), 1e-9 * (1.0 + plain_c.norm()));
    }

    const Eigen::VectorXd kernel_theta = theta.head(merged_problem.kernel.parameterCount());
    const auto posterior = [&](const GpOutputObjective& objective, const Eigen::VectorXd& c) {
      const GpRegressionData d = objective.regressionData(theta);
      Eigen::VectorXd residual = d.targets;
      if (c.size() > 0) {
        residual -= d.inputs.transpose() * c;
      }
      return GpPosterior::exact(merged_problem.kernel, kernel_theta, d.inputs, residual,
                                d.noise_variance);
    };
    const GpPosterior a = posterior(merged, merged_c);
    const GpPosterior b = posterior(plain, plain_c);
    for (const Eigen::Vector2d& x : {Eigen::Vector2d(0.5, 0.4), Eigen::Vector2d(-0.3, 1.1)}) {
      double mean_a = 0.0, var_a = 0.0, mean_b = 0.0, var_b = 0.0;
      a.predict(x, &mean_a, &var_a);
      b.predict(x, &mean_b, &var_b);
      EXPECT_NEAR(mean_a, mean_b, 1e-9);
      EXPECT_NEAR(var_a, var_b, 1e-9);
    }
  }
}

TEST(GpInducing, SelectionIsDeterministicAndCoversTheInputs)
{
  const TestData data = makeData(300, 10, 50);
  const GpInputGroups groups = groupDuplicateInputs(data.inputs);
  const Eigen::MatrixXd z1 = selectInducingInputs(groups.inputs, 20, 3);
  const Eigen::MatrixXd z2 = selectInducingInputs(groups.inputs, 20, 3);
  ASSERT_EQ(z1.cols(), 20);
  EXPECT_EQ((z1 - z2).norm(), 0.0);
  // Every input has an inducing input nearby (the grid spans [-25, 25] x [-20, 20]).
  for (Eigen::Index i = 0; i < groups.size(); ++i) {
    EXPECT_LT((z1.colwise() - groups.inputs.col(i)).colwise().norm().minCoeff(), 12.0);
  }
  EXPECT_EQ(selectInducingInputs(groups.inputs.leftCols(5), 20, 3).cols(), 5);
}

}  // namespace
}  // namespace odometry_calibration
