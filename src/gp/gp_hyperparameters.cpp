#include "odometry_calibration/gp/gp_hyperparameters.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include <ceres/ceres.h>
#include <Eigen/Dense>

namespace odometry_calibration {

GpOutputObjective::GpOutputObjective(const GpOutputProblem& problem) : problem_(problem) {}

int GpOutputObjective::parameterCount() const
{
  return problem_.kernel.parameterCount() + (problem_.learn_noise ? 1 : 0);
}

double GpOutputObjective::noiseVariance(const Eigen::VectorXd& hyperparameters) const
{
  if (!problem_.learn_noise) {
    return problem_.noise_floor;
  }
  return problem_.noise_floor + std::exp(2.0 * hyperparameters(hyperparameters.size() - 1));
}

GpRegressionData GpOutputObjective::regressionData(const Eigen::VectorXd& hyperparameters) const
{
  const GpMergedTargets merged = mergeGroupTargets(
      problem_.groups, problem_.targets, problem_.known_variance, noiseVariance(hyperparameters));
  GpRegressionData data;
  data.inputs = problem_.groups.inputs;
  data.targets = merged.targets;
  data.noise_variance = merged.variance;
  data.mean_basis =
      problem_.linear_mean ? problem_.groups.inputs : Eigen::MatrixXd(0, problem_.groups.size());
  return data;
}

bool GpOutputObjective::evaluate(const Eigen::VectorXd& hyperparameters, double* log_likelihood,
                                 Eigen::VectorXd* gradient,
                                 Eigen::VectorXd* mean_coefficients) const
{
  const int kernel_count = problem_.kernel.parameterCount();
  const Eigen::VectorXd kernel_parameters = hyperparameters.head(kernel_count);
  const double eta = noiseVariance(hyperparameters);
  const GpMergedTargets merged =
      mergeGroupTargets(problem_.groups, problem_.targets, problem_.known_variance, eta);
  GpRegressionData data;
  data.inputs = problem_.groups.inputs;
  data.targets = merged.targets;
  data.noise_variance = merged.variance;
  if (problem_.linear_mean) {
    data.mean_basis = problem_.groups.inputs;
  } else {
    data.mean_basis.resize(0, problem_.groups.size());
  }

  GpLikelihood likelihood;
  const bool with_gradient = gradient != nullptr;
  const bool ok = problem_.inducing_inputs.cols() == 0
                      ? exactLogMarginalLikelihood(problem_.kernel, kernel_parameters, data,
                                                   with_gradient, &likelihood)
                      : vfeLogLikelihoodBound(problem_.kernel, kernel_parameters, data,
                                              problem_.inducing_inputs, with_gradient, &likelihood);
  if (!ok) {
    return false;
  }
  *log_likelihood = likelihood.value + merged.log_constant;
  if (mean_coefficients != nullptr) {
    *mean_coefficients = likelihood.mean_coefficients;
  }
  if (with_gradient) {
    gradient->resize(parameterCount());
    gradient->head(kernel_count) = likelihood.d_kernel;
    if (problem_.learn_noise) {
      // Chain rule through the merge (gp_inputs.h): d/d eta, then d eta / d log sigma_n.
      const double d_eta = likelihood.d_noise.dot(merged.d_variance_d_noise) +
                           likelihood.d_targets.dot(merged.d_targets_d_noise) +
                           merged.d_log_constant_d_noise;
      (*gradient)(kernel_count) = d_eta * 2.0 * (eta - problem_.noise_floor);
    }
  }
  return std::isfinite(*log_likelihood);
}

Eigen::VectorXd initialHyperparameters(const GpOutputProblem& problem)
{
  const GpInputGroups& groups = problem.groups;
  const Eigen::Index n = groups.pairCount();
  const Eigen::Index m = groups.inputs.rows();
  Eigen::MatrixXd x(m, n);
  Eigen::VectorXd y(n);
  double known = 0.0;
  for (Eigen::Index g = 0, k = 0; g < groups.size(); ++g) {
    for (auto i = groups.offsets[static_cast<std::size_t>(g)];
         i < groups.offsets[static_cast<std::size_t>(g) + 1]; ++i, ++k) {
      const Eigen::Index pair = groups.members[static_cast<std::size_t>(i)];
      x.col(k) = groups.inputs.col(g);
      y(k) = problem.targets(pair);
      known += problem.known_variance(pair);
    }
  }
  known /= static_cast<double>(std::max<Eigen::Index>(n, 1));
  const double mean_square = y.squaredNorm() / static_cast<double>(std::max<Eigen::Index>(n, 1));
  Eigen::MatrixXd normal = x * x.transpose();
  normal.diagonal().array() += 1e-12 * std::max(normal.trace(), 1e-300);
  const Eigen::VectorXd ols = normal.ldlt().solve(x * y);
  const double residual_square =
      (y - x.transpose() * ols).squaredNorm() / static_cast<double>(std::max<Eigen::Index>(n, 1));
  const double tiny = 1e-12 * std::max(mean_square, known) + 1e-300;
  const double linear_part = std::max(mean_square - residual_square, tiny);
  // What the kernel has to explain beyond the mean function and the known noise.
  const double unexplained =
      std::max((problem.linear_mean ? residual_square : mean_square) - known,
               0.01 * (problem.linear_mean ? residual_square : mean_square) + tiny);

  Eigen::VectorXd start(problem.kernel.parameterCount() + (problem.learn_noise ? 1 : 0));
  int index = 0;
  const GpKernelType type = problem.kernel.type();
  if (type != GpKernelType::kLinear) {
    const double rbf_variance = problem.linear_mean || type == GpKernelType::kRbf
                                    ? unexplained
                                    : std::max(residual_square, tiny);
    start(index++) = 0.5 * std::log(rbf_variance);
    for (Eigen::Index p = 0; p < m; ++p) {
      start(index++) = 0.0;
    }
  }
  if (type != GpKernelType::kRbf) {
    const double variance = problem.linear_mean ? 0.1 * unexplained : linear_part;
    start(index++) = 0.5 * std::log(variance / static_cast<double>(m));
  }
  if (problem.learn_noise) {
    const double noise = known > 0.0 ? 0.1 * known : 0.1 * unexplained;
    start(index++) = 0.5 * std::log(std::max(noise, tiny));
  }
  return start;
}

std::vector<Eigen::VectorXd> startingHyperparameters(const GpOutputProblem& problem, int count,
                                                     unsigned seed)
{
  std::vector<Eigen::VectorXd> starts;
  const Eigen::VectorXd base = initialHyperparameters(problem);
  starts.push_back(base);
  std::mt19937_64 rng(seed);
  // Box-Muller on our own uniforms: reproducible across standard libraries.
  const auto normal = [&rng]() {
    const double u1 = (static_cast<double>(rng() >> 11) + 0.5) * 0x1.0p-53;
    const double u2 = static_cast<double>(rng() >> 11) * 0x1.0p-53;
    return std::sqrt(-2.0 * std::log(u1)) * std::cos(6.283185307179586 * u2);
  };
  // Length scales over two decades around the unit input spread: real data often hold a
  // smooth optimum with a large noise and a wiggly one with a small noise.
  const double ladder[] = {-std::log(3.0), std::log(3.0), -std::log(10.0), std::log(10.0)};
  const bool has_rbf = problem.kernel.type() != GpKernelType::kLinear;
  const int m = problem.kernel.inputDimension();
  for (int k = 1; k < count; ++k) {
    Eigen::VectorXd start = base;
    for (Eigen::Index p = 0; p < start.size(); ++p) {
      start(p) += 0.5 * normal();
    }
    if (has_rbf) {
      start.segment(1, m).array() += ladder[(k - 1) % 4];
    }
    starts.push_back(start);
  }
  return starts;
}

namespace {

/// -log p / n for Ceres (minimisation, scaled so the tolerances do not depend on n).
class NegativeLogLikelihood : public ceres::FirstOrderFunction
{
public:
  NegativeLogLikelihood(const GpOutputObjective& objective, Eigen::VectorXd center)
      : objective_(objective),
        center_(std::move(center)),
        scale_(1.0 / static_cast<double>(
                         std::max<Eigen::Index>(objective.problem().groups.pairCount(), 1)))
  {
  }

  bool Evaluate(const double* parameters, double* cost, double* gradient) const override
  {
    const Eigen::Map<const Eigen::VectorXd> x(parameters, center_.size());
    if (((x - center_).array().abs() > 25.0).any()) {
      return false;
    }
    double value = 0.0;
    Eigen::VectorXd g;
    if (!objective_.evaluate(x, &value, gradient != nullptr ? &g : nullptr)) {
      return false;
    }
    *cost = -value * scale_;
    if (gradient != nullptr) {
      if (!g.allFinite()) {
        return false;
      }
      Eigen::Map<Eigen::VectorXd>(gradient, center_.size()) = -g * scale_;
    }
    return true;
  }

  int NumParameters() const override { return static_cast<int>(center_.size()); }

private:
  const GpOutputObjective& objective_;
  Eigen::VectorXd center_;
  double scale_;
};

}  // namespace

GpOptimizationResult maximizeLogLikelihood(const GpOutputObjective& objective,
                                           const Eigen::VectorXd& start, int max_iterations)
{
  GpOptimizationResult result;
  result.hyperparameters = start;
  double value = 0.0;
  if (!objective.evaluate(start, &value, nullptr)) {
    throw std::runtime_error("gp: the marginal likelihood cannot be evaluated at the start");
  }
  ceres::GradientProblem problem(new NegativeLogLikelihood(objective, start));
  ceres::GradientProblemSolver::Options options;
  options.line_search_direction_type = ceres::LBFGS;
  options.max_num_iterations = max_iterations;
  options.function_tolerance = 1e-9;
  options.gradient_tolerance = 1e-6;
  options.parameter_tolerance = 1e-8;
  options.logging_type = ceres::SILENT;
  options.minimizer_progress_to_stdout = false;
  ceres::GradientProblemSolver::Summary summary;
  ceres::Solve(options, problem, result.hyperparameters.data(), &summary);
  if (!objective.evaluate(result.hyperparameters, &result.log_likelihood, nullptr)) {
    result.hyperparameters = start;
    result.log_likelihood = value;
  }
  // Ceres records iteration 0 (the start) only once it is past its first checks: a start that
  // already meets the gradient tolerance (a warm start at the optimum) ends with no record.
  result.iterations = std::max(0, static_cast<int>(summary.iterations.size()) - 1);
  // A line-search failure near the optimum still returns the best point found; only the
  // iteration limit means the search was cut short.
  result.converged = summary.termination_type != ceres::NO_CONVERGENCE;
  result.termination = summary.message;
  if (summary.iterations.empty())
    result.termination = "ended at its start (" +
                         std::string(ceres::TerminationTypeToString(summary.termination_type)) +
                         "): " + summary.message;
  return result;
}

}  // namespace odometry_calibration
