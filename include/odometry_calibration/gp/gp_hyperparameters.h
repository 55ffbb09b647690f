// Hyperparameters of one GP output by maximising the log marginal likelihood (paper Sec. III-A,
// "we infer the hyper-parameters by optimizing the corresponding log marginal likelihood") with
// its analytic gradient, by L-BFGS (Ceres' gradient solver), from several starts.
//
// Hyperparameter vector: [kernel log-parameters (GpKernel), log sigma_n] where the learned noise
// variance eta = noise_floor + sigma_n^2 is added to every pair's known variance (paper eq. 2's
// Sigma_jk). The linear mean's C is profiled in closed form (gp_likelihood.h). Pairs with equal
// inputs are merged exactly (gp_inputs.h), so the cost depends on distinct inputs only.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/gp/gp_inputs.h"
#include "odometry_calibration/gp/gp_kernel.h"
#include "odometry_calibration/gp/gp_likelihood.h"

namespace odometry_calibration {

/// One output's likelihood problem.
struct GpOutputProblem
{
  GpKernel kernel;                 ///< kernel of this output
  GpInputGroups groups;            ///< distinct inputs; members index the per-pair arrays
  Eigen::VectorXd targets;         ///< per pair: the measured displacement component
  Eigen::VectorXd known_variance;  ///< per pair: its variance from the pair's covariance
  bool linear_mean = true;         ///< mu = C x (paper eq. 6) or zero
  bool learn_noise = true;         ///< with the log sigma_n parameter
  double noise_floor = 0.0;        ///< eta's lower bound (keeps K + S positive definite)
  /// Empty: exact likelihood; otherwise the VFE bound with these inducing inputs (m x M).
  Eigen::MatrixXd inducing_inputs;
};

/// The log marginal likelihood of a problem (kept by reference: it must outlive this) as a
/// function of the hyperparameter vector.
class GpOutputObjective
{
public:
  explicit GpOutputObjective(const GpOutputProblem& problem);

  /// Kernel parameters plus one for the noise if learned.
  int parameterCount() const;
  /// log p(all pairs) (exact, or its VFE bound) and, if `gradient` is not null, its gradient.
  /// Also returns the profiled mean coefficients if asked. False if a factorisation fails.
  bool evaluate(const Eigen::VectorXd& hyperparameters, double* log_likelihood,
                Eigen::VectorXd* gradient, Eigen::VectorXd* mean_coefficients = nullptr) const;
  /// The learned noise variance eta of a hyperparameter vector.
  double noiseVariance(const Eigen::VectorXd& hyperparameters) const;
  /// The merged regression problem (one row per distinct input) at these hyperparameters.
  GpRegressionData regressionData(const Eigen::VectorXd& hyperparameters) const;
  const GpOutputProblem& problem() const { return problem_; }

private:
  const GpOutputProblem& problem_;
};

/// A start from data statistics: ordinary least squares of the targets on the inputs splits
/// their mean square into a linear part and a residual; the residual beyond the known noise
/// sets the RBF variance, length scales 1 (inputs are scaled to unit RMS), noise 0.1 of the
/// known variance.
Eigen::VectorXd initialHyperparameters(const GpOutputProblem& problem);

/// `count` starts: the first initialHyperparameters, then length scales /3, x3, /10, x10, ... with
/// fixed-seed random perturbations (standard deviation 0.5 in log space) of all parameters.
std::vector<Eigen::VectorXd> startingHyperparameters(const GpOutputProblem& problem, int count,
                                                     unsigned seed);

/// Result of one L-BFGS run.
struct GpOptimizationResult
{
  Eigen::VectorXd hyperparameters;  ///< the maximiser found
  double log_likelihood = 0.0;      ///< its value
  int iterations = 0;               ///< L-BFGS iterations
  bool converged = false;           ///< stopped before the iteration limit
  std::string termination;          ///< the solver's message
};

/// Maximises the objective from `start` with L-BFGS, at most `max_iterations` iterations.
/// Steps that leave a box of +-25 around the start (log space) or break a factorisation are
/// rejected by the line search. Throws std::runtime_error if the start cannot be evaluated.
GpOptimizationResult maximizeLogLikelihood(const GpOutputObjective& objective,
                                           const Eigen::VectorXd& start, int max_iterations);

}  // namespace odometry_calibration
