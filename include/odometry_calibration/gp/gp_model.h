// Model-free calibration by Gaussian-process regression (CGP, paper Sec. III-A, eqs. 2-8,
// Algorithm 1): learn the sensor motion f(delta) directly from keyframe pairs (delta, s_hat,
// Sigma), with no kinematic model.
//
//  - Inputs: pairFeatures (increments of incremental joints, mean of absolute joints), divided
//    by their RMS over the training pairs for conditioning (the stored scale is applied again
//    at prediction; length scales are reported in raw units).
//  - One independent GP per output x, y, theta (the paper's diagonal kernel), with mean zero or
//    C delta (eq. 6) and kernel rbf (eq. 7, one length scale per input), linear (eq. 8) or their
//    sum; noise: each pair's own variance (diagonal of its covariance) plus a learned variance.
//  - Hyperparameters maximise the log marginal likelihood (analytic gradients, L-BFGS, several
//    starts); pairs with equal features are merged exactly first (gp_inputs.h). The starts use
//    the exact likelihood of at most GpOptions::likelihood_subset distinct inputs; with more,
//    the best is refined on the sparse VFE bound (gp_output_fit.h), so the cost of the search
//    does not grow with the number of pairs.
//  - Posterior: exact with the Cholesky factor and alpha = (K + Sigma)^-1 (s_hat - mu_bar)
//    precomputed (mean O(n), variance O(n^2) per prediction), or sparse (VFE/DTC, inducing
//    inputs; O(n M^2) once, O(M^2) per prediction) above GpOptions::max_exact_pairs distinct
//    inputs.
//  - theta is regressed as a number: keyframe intervals must keep the rotation per pair well
//    below pi. A displacement that depends on the path inside the interval (the drive changed
//    motion between the keyframes) cannot be predicted from the increments by any model.
//  - Outliers: a Huber-robust polynomial pre-fit flags gross outliers (gp_outliers.h); after the
//    fit every pair is re-checked against the GP's predictive distribution and the GP refitted
//    if the inlier set changed. ModelReport::outliers counts the pairs left out.
//  - predict(): mean (eq. 5's mu_e) and a diagonal covariance: the posterior variance of f
//    (eq. 5's Sigma_e) plus the learned noise if GpOptions::predict_learned_noise.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/gp/gp_inputs.h"
#include "odometry_calibration/gp/gp_options.h"
#include "odometry_calibration/gp/gp_output_fit.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// The GP motion model (name "gp").
class GaussianProcessModel : public MotionModel
{
public:
  /// Throws std::invalid_argument for invalid options or an empty / inconsistent joint layout.
  GaussianProcessModel(GpOptions options, JointLayout joints);

  std::string name() const override { return "gp"; }

  /// Fits the three outputs (see the file comment). Throws std::invalid_argument naming the
  /// problem for fewer than 10 pairs or 5 distinct feature vectors, pairs whose samples do not
  /// match the joints, non-finite values or negative variances, or fewer than 10 pairs left
  /// after outlier rejection; std::runtime_error if the likelihood cannot be evaluated (e.g.
  /// pairs with zero variance and learn_noise false).
  ModelReport fit(const std::vector<MotionPair>& pairs) override;

  /// Predicted sensor motion over the samples (paper eq. 5). Throws std::logic_error before
  /// fit() and std::invalid_argument for samples that do not match the joints.
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;

  /// The same from a feature vector of pairFeatures (raw units).
  MotionPrediction predictFeatures(const Eigen::VectorXd& features) const;

  /// Options, joints, input scale and the three fitted outputs as YAML (doubles with 17
  /// significant digits, so a loaded model predicts identically).
  std::string toYaml() const override;

  /// Loads a model written by toYaml(). Throws std::runtime_error naming what is missing.
  static std::unique_ptr<GaussianProcessModel> fromYaml(const std::string& text);

  bool fitted() const { return fitted_; }
  const GpOptions& options() const { return options_; }
  const JointLayout& joints() const { return joints_; }
  /// Divisors of the raw features (their RMS over the training pairs).
  const Eigen::VectorXd& inputScale() const { return input_scale_; }
  /// Output 0 = x, 1 = y, 2 = theta.
  const GpOutputModel& output(int axis) const
  {
    return outputs_.at(static_cast<std::size_t>(axis));
  }

private:
  /// Fits the outputs on the pairs flagged in `inlier`: warm-started from the current
  /// hyperparameters if `warm`, which are kept (posterior only) unless `optimise`.
  void fitOutputs(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
                  const Eigen::MatrixXd& variances, const std::vector<bool>& inlier, bool warm,
                  bool optimise);

  /// Re-checks every pair against the GP's predictive distribution (recheckInliers), up to
  /// outlier_passes times while the inliers change, and fits again on the new inliers (the
  /// posterior only when at most 1 % changed). Returns the means of the last fit (3 x pairs).
  Eigen::MatrixXd refitWithoutOutliers(const GpInputGroups& all_groups,
                                       const Eigen::MatrixXd& inputs,
                                       const Eigen::MatrixXd& targets,
                                       const Eigen::MatrixXd& variances, std::vector<bool>* inlier);

  /// Means of the fitted outputs (3 x pairs) for the pairs of `groups`.
  Eigen::MatrixXd pairMeans(const GpInputGroups& groups) const;
  /// Pairs within outlier_threshold standard deviations of the GP's prediction on every axis:
  /// noise (the pair's and the learned) plus, for inputs left out of the fit, the posterior
  /// variance of f.
  std::vector<bool> recheckInliers(const GpInputGroups& groups, const Eigen::MatrixXd& means,
                                   const Eigen::MatrixXd& targets, const Eigen::MatrixXd& variances,
                                   const std::vector<bool>& inlier) const;
  /// The fit report (gp_model_report.cpp): residual RMS, hyperparameters, warnings.
  ModelReport makeReport(const std::vector<MotionPair>& pairs, const Eigen::MatrixXd& targets,
                         const Eigen::MatrixXd& variances, const Eigen::MatrixXd& means,
                         const std::vector<bool>& inlier) const;

  GpOptions options_;
  JointLayout joints_;
  Eigen::VectorXd input_scale_;
  std::array<GpOutputModel, 3> outputs_;
  bool fitted_ = false;
};

}  // namespace odometry_calibration
