// The one interface of all calibration models: fit to keyframe pairs,
// predict the sensor's displacement with a covariance, save to YAML.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/data/pair_features.h"
#include "odometry_calibration/geometry/se2.h"

namespace YAML {
class Node;
}

namespace odometry_calibration {

/// One calibrated quantity for reports.
struct ParameterEstimate
{
  std::string name;      ///< e.g. "axis_length"
  std::string unit;      ///< e.g. "m"
  double initial = 0.0;  ///< start value
  double value = 0.0;    ///< estimate
  double sigma = 0.0;    ///< standard deviation; NaN when unavailable (unobservable)
};

/// RMS of the translation and rotation parts of SE(2) errors over `count` pairs.
struct ResidualRms
{
  double translation_m = 0.0;
  double rotation_rad = 0.0;
  std::size_t count = 0;
};

/// A predicted sensor displacement over a pair: the sensor's pose at the end in its frame at
/// the start, with the model's covariance of (x, y, theta) [m^2, rad^2].
struct MotionPrediction
{
  Pose2 mean;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// What a fit reports, for every model.
struct ModelReport
{
  std::string model;                          ///< model name
  std::vector<ParameterEstimate> parameters;  ///< parametric models: estimates with sigma
  ResidualRms before;                         ///< errors before the fit (initial guess), if any
  ResidualRms after;                          ///< errors of the fit on all pairs used
  Eigen::Vector3d residual_rms_xytheta = Eigen::Vector3d::Zero();  ///< per axis, inliers
  std::size_t pairs_used = 0;                                      ///< pairs given to the fit
  /// The model's own outlier count: parametric models the pairs beyond the
  /// Huber threshold (rejected + down_weighted), linear and GP the pairs left out (rejected).
  std::size_t outliers = 0;
  /// Pairs beyond the model's outlier cut: left out of the fit (linear, GP) or, under the
  /// parametric models' Huber loss, beyond its gross threshold (5 sigma: weight below 3/5).
  std::size_t rejected = 0;
  std::size_t down_weighted = 0;      ///< other pairs given a weight below one (robust loss)
  int iterations = 0;                 ///< optimiser iterations (0 if closed form)
  bool converged = true;              ///< the optimiser met its tolerance
  std::string termination;            ///< optimiser's reason, in words
  int starts = 1;                     ///< optimiser starts tried (global starts)
  int starts_agreed = 1;              ///< starts that reached the best minimum
  double fit_time_s = 0.0;            ///< wall time [s]
  bool has_extrinsic = false;         ///< whether T_base_sensor was estimated
  Pose2 T_base_sensor;                ///< the sensor's pose in base_link
  std::vector<std::string> warnings;  ///< a parameter not determined, a fit not to trust
  /// Information that is no warning, e.g. strongly correlated but well-determined parameters.
  std::vector<std::string> notes;
};

/// A calibration model.
class MotionModel
{
public:
  virtual ~MotionModel() = default;

  /// Short name, e.g. "linear", "gp", "diff_drive", "tricycle".
  virtual std::string name() const = 0;

  /// Fits the model to the pairs (the model rejects outliers itself). Throws
  /// std::invalid_argument with an actionable message for too few or degenerate pairs.
  virtual ModelReport fit(const std::vector<MotionPair>& pairs) = 0;

  /// Predicted sensor motion over encoder samples (at least two). Requires a fitted model.
  virtual MotionPrediction predict(const std::vector<EncoderSample>& samples) const = 0;

  /// The fitted model as YAML text (enough to predict again after loading).
  virtual std::string toYaml() const = 0;
};

}  // namespace odometry_calibration
