// Fit of one GP output (one of x, y, theta; the paper's diagonal kernel makes them independent):
// hyperparameters by multi-start L-BFGS on the log marginal likelihood, then the posterior
// (paper Algorithm 1, lines 2-5).
//
// Cost control: the starts run on the exact likelihood of at most `likelihood_subset` distinct
// inputs (all of them when there are fewer); with more, the best start is refined on the VFE
// bound over all inputs (O(n M^2) per step). The posterior is exact up to `max_exact_pairs`
// distinct inputs and sparse (VFE/DTC) above, so the fit time grows linearly in n beyond it.
#pragma once

#include <string>

#include <Eigen/Core>

#include "odometry_calibration/gp/gp_hyperparameters.h"
#include "odometry_calibration/gp/gp_options.h"
#include "odometry_calibration/gp/gp_posterior.h"

namespace odometry_calibration {

/// One fitted output.
struct GpOutputModel
{
  Eigen::VectorXd hyperparameters;    ///< [kernel log-parameters, log sigma_n]
  double noise_variance = 0.0;        ///< learned noise variance eta [output unit^2]
  Eigen::VectorXd mean_coefficients;  ///< C of mu(x) = C x in scaled inputs (empty: zero mean)
  GpPosterior posterior;              ///< f | data
  /// Of the objective last optimised: exact on the (subset of) inputs, or the VFE bound.
  double log_likelihood = 0.0;
  int iterations = 0;       ///< L-BFGS iterations over all starts and the refinement
  bool converged = false;   ///< the chosen start stopped before its iteration limit
  bool sparse = false;      ///< the posterior is the sparse one
  std::string termination;  ///< how the hyperparameters were found, in words

  /// Mean mu(x) + E[f(x)] and variance Var[f(x)] (+ eta if `with_noise`) at a scaled input.
  void predict(const Eigen::VectorXd& x, bool with_noise, double* mean, double* variance) const;
  /// Means at the columns of `inputs` (scaled).
  Eigen::VectorXd means(const Eigen::MatrixXd& inputs) const;
};

/// Fits one output. `problem.groups` holds all distinct training inputs (its inducing_inputs are
/// ignored); `inducing_inputs` (m x M) serve the VFE refinement and the sparse posterior. With
/// `warm_start`, a single run starts there (no multi-start), or, if `optimise` is false, the
/// hyperparameters are kept and only the posterior is computed. Throws std::runtime_error if the
/// likelihood cannot be evaluated at any start.
GpOutputModel fitGpOutput(const GpOutputProblem& problem, const GpOptions& options,
                          const Eigen::MatrixXd& inducing_inputs, unsigned seed,
                          const Eigen::VectorXd* warm_start = nullptr, bool optimise = true);

}  // namespace odometry_calibration
