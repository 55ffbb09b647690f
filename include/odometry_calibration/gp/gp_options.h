// Options of the Gaussian-process motion model (GP calibration paper, Sec. III-A, eqs. 2-8 and
// Algorithm 1): mean function, kernel, hyperparameter search, exact / sparse regime, outliers.
#pragma once

#include <cstddef>
#include <string>

namespace odometry_calibration {

/// Prior mean of each output (paper eq. 4's mu).
enum class GpMeanFunction
{
  kZero,    ///< mu(x) = 0
  kLinear,  ///< mu(x) = C x (paper eq. 6); C maximises the marginal likelihood (closed form)
};

/// Covariance function of each output (the paper's diagonal kernel: one per output).
enum class GpKernelType
{
  kRbf,            ///< squared exponential with one length scale per input (paper eq. 7)
  kLinear,         ///< sigma_l^2 <x, x'> (paper eq. 8 with a learned variance)
  kRbfPlusLinear,  ///< the sum of both (paper Sec. IV-C, "kappa_rbf + kappa_lin")
};

/// Options of GaussianProcessModel. Sizes count distinct inputs: pairs with identical encoder
/// features (tick-quantised increments repeat) are merged exactly before any O(n^3) work.
struct GpOptions
{
  GpMeanFunction mean = GpMeanFunction::kLinear;  ///< prior mean (paper eq. 6 by default)
  GpKernelType kernel = GpKernelType::kRbf;       ///< kernel (paper eq. 7 by default)
  /// Learn an extra noise variance per output on top of each pair's covariance (pairs'
  /// covariances from scan matching are rarely exact).
  bool learn_noise = true;
  /// Optimiser starts per output: the first from data statistics, the others with length
  /// scales /3, x3, /10, x10 and random perturbations seeded by `seed` (single starts land in
  /// poor optima: the data often hold a smooth optimum and a wiggly one).
  int starts = 4;
  int max_iterations = 100;  ///< L-BFGS iterations per start
  unsigned seed = 1;         ///< seed of the starts, the subset and the inducing-point choice
  /// Up to this many distinct inputs the posterior is the exact GP (Cholesky once, O(n) mean
  /// prediction); above it the sparse VFE/DTC approximation with `inducing_points`.
  std::size_t max_exact_pairs = 3000;
  /// The multi-start search maximises the exact log marginal likelihood on at most this many
  /// distinct inputs (a fixed-seed random subset when there are more) [inputs].
  std::size_t likelihood_subset = 250;
  /// With more distinct inputs than `likelihood_subset`, the best start is refined for at most
  /// this many L-BFGS iterations on the VFE bound with `inducing_points` over at most
  /// `refine_subset` distinct inputs (0: keep the subset's hyperparameters).
  int refine_iterations = 15;
  /// Distinct inputs of the VFE refinement (a fixed-seed subset when there are more), which
  /// bounds its cost at O(refine_subset M^2) per iteration [inputs].
  std::size_t refine_subset = 2000;
  /// Inducing inputs M of the sparse posterior and of the VFE refinement, chosen by
  /// k-means++ (fixed seed) and Lloyd steps in the scaled input space.
  std::size_t inducing_points = 128;
  /// Pairs whose residual exceeds this many standard deviations on any axis are outliers and
  /// left out (first against a robust polynomial pre-fit, then against the GP) [sigma];
  /// <= 0 keeps every pair.
  double outlier_threshold = 5.0;
  /// Huber threshold of the iteratively reweighted pre-fit [robust sigma].
  double prefit_huber_threshold = 1.345;
  /// Re-checks of all pairs against the fitted GP's own prediction after the pre-fit. If the
  /// inlier set changed, the GP is refitted: hyperparameters and posterior when more than 1 %
  /// of the pairs changed, the posterior alone otherwise.
  int outlier_passes = 1;
  /// Predicted covariance: the posterior variance of f (paper eq. 5) plus, if true, the learned
  /// noise variance (the scatter of the true motion beyond the pairs' covariance, e.g. slip).
  bool predict_learned_noise = true;
  /// Threads fitting the three outputs in parallel; 0 = one per output up to the hardware.
  int num_threads = 0;
};

/// Throws std::invalid_argument naming the first invalid option and its valid range.
void validate(const GpOptions& options);

/// "zero" / "linear".
std::string toString(GpMeanFunction mean);
/// "rbf" / "linear" / "rbf+linear".
std::string toString(GpKernelType kernel);
/// Inverse of toString; throws std::invalid_argument naming the unknown value.
GpMeanFunction parseGpMeanFunction(const std::string& text);
/// Inverse of toString; throws std::invalid_argument naming the unknown value.
GpKernelType parseGpKernelType(const std::string& text);

}  // namespace odometry_calibration
