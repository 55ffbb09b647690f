// Repeated inputs of the GP motion model. Encoder increments are tick-quantised, so thousands of
// pairs hold only hundreds of distinct feature vectors. Pairs i in a group G share f(x_G); their
// Gaussian likelihood factorises exactly as
//   prod_i N(y_i | f, lambda_i) = N(ybar | f, v) * exp(c),
//   1/v = sum_i 1/lambda_i,  ybar = v sum_i y_i/lambda_i,
//   c = -1/2 sum_i (y_i - ybar)^2/lambda_i - 1/2 sum_i log(2 pi lambda_i) + 1/2 log(2 pi v),
// with c independent of f. So the GP on the merged inputs has the same posterior as on all pairs
// and a log marginal likelihood smaller by exactly sum_G c_G (paper eq. 3 with one row per
// distinct input). lambda_i = known variance + learned noise variance eta, so the merge is redone
// for every eta; the derivatives with respect to eta are returned for the likelihood gradient.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace odometry_calibration {

/// Distinct inputs and which pairs share each of them.
struct GpInputGroups
{
  Eigen::MatrixXd inputs;  ///< m x g distinct inputs (columns)
  std::vector<Eigen::Index>
      offsets;  ///< g + 1 entries; group k is members[offsets[k], offsets[k+1])
  std::vector<Eigen::Index> members;  ///< indices into the caller's per-pair arrays

  /// Number of distinct inputs g.
  Eigen::Index size() const { return inputs.cols(); }
  /// Number of pairs over all groups.
  Eigen::Index pairCount() const { return static_cast<Eigen::Index>(members.size()); }
};

/// Groups the columns of `inputs` (m x n) that are exactly equal (bitwise equal doubles). Groups
/// are in lexicographic order of their input; members in increasing index order.
GpInputGroups groupDuplicateInputs(const Eigen::MatrixXd& inputs);

/// Snaps each feature (row of `features`, m x n) whose values are all whole multiples of one
/// quantum, up to floating-point rounding (1e-6 of the quantum), exactly onto those multiples:
/// the quantum is the smallest gap between values larger than 1e-9 of the largest value. Encoder
/// increments are tick-quantised whatever their unit (ticks, or radians = ticks * 2 pi / N from a
/// JointState), so inputs that differ by less than one tick become bitwise equal and merge in
/// groupDuplicateInputs; continuous features are left alone. Returns how many were snapped.
int snapQuantisedFeatures(Eigen::MatrixXd* features);

/// Every column its own group (no merging), for comparisons.
GpInputGroups singletonGroups(const Eigen::MatrixXd& inputs);

/// A fixed-seed random selection of at most `max_groups` whole groups (all of them if there are
/// no more), in their original order.
GpInputGroups subsetGroups(const GpInputGroups& groups, Eigen::Index max_groups, unsigned seed);

/// The merged targets of one output for a given extra noise variance eta (file comment).
struct GpMergedTargets
{
  Eigen::VectorXd targets;              ///< ybar per group
  Eigen::VectorXd variance;             ///< v per group
  double log_constant = 0.0;            ///< sum_G c_G
  Eigen::VectorXd d_targets_d_noise;    ///< d ybar / d eta
  Eigen::VectorXd d_variance_d_noise;   ///< d v / d eta
  double d_log_constant_d_noise = 0.0;  ///< d sum_G c_G / d eta
};

/// Merges per-pair targets y and known variances s (indexed by GpInputGroups::members) with the
/// extra noise variance eta >= 0 (lambda_i = s_i + eta > 0 required).
GpMergedTargets mergeGroupTargets(const GpInputGroups& groups, const Eigen::VectorXd& targets,
                                  const Eigen::VectorXd& known_variance,
                                  double extra_noise_variance);

}  // namespace odometry_calibration
