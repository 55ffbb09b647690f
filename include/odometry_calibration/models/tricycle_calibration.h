// Least-squares calibration of the front-wheel-drive tricycle and of its sensor's pose
// (docs/models.md, "The tricycle"): state X = [Ks Kt a ds | T_base_sensor], measurement the
// sensor displacement over a keyframe window, prediction h = T_bs^-1 * Delta_r * T_bs, error
// e = Z^-1 * h on SE(2), Huber loss. Solved with Ceres (Levenberg-Marquardt, automatic
// derivatives, SE(2) manifold for the sensor pose).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/observability.h"
#include "odometry_calibration/models/tricycle_kinematics.h"

namespace odometry_calibration {

/// The tricycle's kinematic parameters and the sensor's pose on it.
struct TricycleParameters
{
  double steering_scale = 0.1;              ///< Ks [-]
  double traction_scale_m_per_turn = 0.01;  ///< Kt [m per wheel turn]
  double axis_length_m = 1.0;               ///< a [m]
  double steering_offset_rad = 0.0;         ///< ds [rad]
  Pose2 T_base_sensor;                      ///< sensor pose in base_link [m, m, rad]

  /// (Ks, Kt, a, ds), indexed by TricycleParameterIndex.
  Eigen::Vector4d kinematicVector() const;
  /// Builds parameters from (Ks, Kt, a, ds) and (x, y, theta) of the sensor.
  static TricycleParameters fromVectors(const Eigen::Vector4d& kinematic,
                                        const Eigen::Vector3d& sensor_pose);
};

/// Options of the fit. Defaults suit an external tracker of mm accuracy.
struct TricycleCalibrationOptions
{
  /// Assumed standard deviation of a measured displacement's x and y [m].
  double translation_sigma_m = 0.01;
  /// Assumed standard deviation of a measured displacement's heading [rad].
  double rotation_sigma_rad = 0.01;
  /// Huber loss threshold on a pair's whitened error norm [sigma]; pairs beyond it are counted
  /// as outliers and down-weighted. <= 0 disables the robust loss.
  double huber_threshold = 3.0;
  /// Iteration cap of the Levenberg-Marquardt solver (per solve).
  int max_iterations = 500;
  /// Global starts: sensor yaws tried, evenly spaced from the start value; 1 = only the start
  /// value (the default: on the real tricycle log other yaws reach a mirrored solution, negative
  /// Ks and the sensor turned by pi, with the same cost, which nothing maps back yet).
  int yaw_starts = 1;
};

/// Throws std::invalid_argument naming the first invalid option and the expected range.
void validate(const TricycleCalibrationOptions& options);

/// Everything a user needs to judge a fit.
struct TricycleCalibrationResult
{
  TricycleParameters initial;     ///< start values
  TricycleParameters calibrated;  ///< estimate
  /// Estimates in order Ks, Kt, a, ds, sensor x, y, theta, with sigma.
  std::vector<ParameterEstimate> estimates;
  /// 7x7 covariance in the same order, scaled by the residual spread (chi2_per_dof).
  Eigen::Matrix<double, 7, 7> covariance = Eigen::Matrix<double, 7, 7>::Zero();
  bool covariance_available = false;
  double chi2_per_dof = 0.0;       ///< inlier chi^2 / (inliers*3 - 7), at the solution
  ResidualRms before;              ///< errors of the initial parameters, all pairs
  ResidualRms after;               ///< errors of the estimate, all pairs
  ResidualRms after_inliers;       ///< errors of the estimate, inlier pairs
  std::size_t pair_count = 0;      ///< pairs used
  std::size_t outlier_count = 0;   ///< pairs beyond the Huber threshold at the solution
  std::size_t gross_outliers = 0;  ///< of those, pairs beyond 5 sigma
  int starts = 1;                  ///< global starts tried
  int starts_agreed = 1;           ///< starts that reached the best minimum
  /// Information that is no warning (strong correlations of well-determined parameters).
  std::vector<std::string> notes;
  int iterations = 0;         ///< solver iterations
  bool converged = false;     ///< the solver met a convergence tolerance
  std::string termination;    ///< solver's termination reason, in words
  double solve_time_s = 0.0;  ///< wall time of the solver [s]
  /// Observability and data warnings, each naming the missing motion or the poor parameter.
  std::vector<std::string> warnings;
};

/// Sensor motion predicted by the model over a pair's encoder samples (the seed's h(X, Delta_r)).
Pose2 predictTricycleSensorMotion(const TricycleParameters& parameters,
                                  const TricycleEncoderLayout& layout,
                                  const std::vector<EncoderSample>& samples);

/// Dead-reckoned sensor trajectory: the sensor's world pose at every encoder sample, starting
/// at `T_world_sensor_start` and composing the predicted sensor motion of each step.
std::vector<Pose2> tricycleSensorTrajectory(const TricycleParameters& parameters,
                                            const TricycleEncoderLayout& layout,
                                            const std::vector<EncoderSample>& samples,
                                            const Pose2& T_world_sensor_start);

/// SE(2) errors of all pairs under `parameters`, as RMS.
ResidualRms tricycleResidualRms(const std::vector<MotionPair>& pairs,
                                const TricycleEncoderLayout& layout,
                                const TricycleParameters& parameters);

/// Throws std::invalid_argument unless Ks, Kt and the axis length are > 0 and all are finite.
void validateStartValues(const TricycleParameters& parameters);

/// What the tricycle's observability verdict names: the parameters a run without turns leaves
/// undetermined, the confusion of turns one way only, which parameters are judged relatively.
ObservabilityHints tricycleObservabilityHints();

/// Fits the parameters to the pairs, starting from `initial`. Throws std::invalid_argument for
/// invalid options or start values, fewer than 7 pairs, or pairs with fewer than two encoder
/// samples.
TricycleCalibrationResult calibrateTricycle(const std::vector<MotionPair>& pairs,
                                            const TricycleEncoderLayout& layout,
                                            const TricycleParameters& initial,
                                            const TricycleCalibrationOptions& options);

}  // namespace odometry_calibration
