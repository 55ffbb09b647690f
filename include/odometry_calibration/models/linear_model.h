// The approximate linear motion model of the GP calibration paper (Sec. III-B, eq. 9):
// s_hat = W delta, W in R^{3 x m}, fitted by Huber-robust regression with each residual
// scaled by its sigma from the pair's covariance.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// Options of the linear model.
struct LinearModelOptions
{
  JointLayout joints;              ///< the joints of EncoderSample::values
  double huber_threshold = 1.345;  ///< Huber threshold on scaled residuals [robust sigma]
  double outlier_threshold = 5.0;  ///< pairs beyond this many robust sigma are rejected
  int max_iterations = 50;         ///< iteratively reweighted least-squares iterations
  /// The report warns when an axis' residual RMS exceeds the pairs' own noise by this factor
  /// (the first-order model no longer fits the motion per pair).
  double structure_warning_ratio = 1.5;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const LinearModelOptions& options);

/// s_hat = W delta with a per-axis predictive covariance.
class LinearModel : public MotionModel
{
public:
  explicit LinearModel(LinearModelOptions options);

  std::string name() const override { return "linear"; }
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  /// Mean W delta; covariance: the inlier residual spread per axis plus the uncertainty of W.
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  std::string toYaml() const override;

  /// Loads a model written by toYaml(); throws std::runtime_error naming a missing key.
  static LinearModel fromYaml(const std::string& text);

  /// The 3 x m weight matrix (rows x, y, theta; columns the features of pairFeatures).
  const Eigen::MatrixXd& weights() const { return weights_; }

private:
  LinearModelOptions options_;
  Eigen::MatrixXd weights_;                                      ///< 3 x m
  Eigen::Vector3d residual_variance_ = Eigen::Vector3d::Zero();  ///< per axis, inliers
  std::vector<Eigen::MatrixXd> weight_covariance_;               ///< per axis, m x m
};

}  // namespace odometry_calibration
