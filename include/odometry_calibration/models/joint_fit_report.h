// What a joint fit of several sensors reports (joint_parametric_fit.h fits it): the
// one set of wheel parameters, each sensor's pose, pairs, noise and observability, and each
// sensor's pairs fitted alone, whose agreement is a consistency figure.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// One sensor in a joint fit: its pose with σ, its pairs, residuals and noise.
struct JointSensorReport
{
  Pose2 T_base_sensor;                  ///< the jointly fitted pose [m, m, rad]
  std::vector<ParameterEstimate> pose;  ///< sensor_x, sensor_y [m], sensor_theta [rad] with σ
  std::size_t pairs = 0;                ///< the sensor's pairs in the fit
  std::size_t outliers = 0;             ///< of those, beyond the Huber threshold
  std::size_t rejected = 0;             ///< of those, beyond the gross threshold
  double noise_scale = 1.0;             ///< factor applied to the sensor's pair sigmas
  ResidualRms after;                    ///< the joint solution's errors on the sensor's pairs
  Eigen::Vector3d residual_rms_xytheta = Eigen::Vector3d::Zero();  ///< per axis, its inliers
  /// Observability verdict of the intrinsics and this sensor's pose from this sensor's pairs
  /// and the joint covariance's block of them.
  std::vector<std::string> warnings;
  std::vector<std::string> notes;
};

/// What a joint fit reports.
struct JointFitReport
{
  std::string model;
  std::vector<ParameterEstimate> intrinsics;  ///< the one set of wheel parameters, with σ
  /// Values derived from the intrinsics that a sensor's one-sensor report lists after its pose
  /// (skid_steer: the multipliers of the geometric values); empty for the other models.
  std::vector<ParameterEstimate> derived;
  std::vector<JointSensorReport> sensors;  ///< in the order of the pair sets
  /// Each sensor's pairs fitted alone (the usual one-sensor fit), in the same order.
  std::vector<ModelReport> alone;
  /// Covariance of (intrinsics, then x, y, theta of each sensor); empty when unavailable.
  Eigen::MatrixXd covariance;
  bool covariance_available = false;
  double chi2_per_dof = std::numeric_limits<double>::quiet_NaN();
  int iterations = 0;
  bool converged = false;
  std::string termination;
  double fit_time_s = 0.0;  ///< the joint solve and the fits alone [s]
};

/// The largest relative spread of the sensors' intrinsics fitted alone: max over the
/// intrinsics of (max - min) / |joint value| (0 with one sensor; NaN if a fit alone is
/// missing a value). A consistency figure: the sensors should imply the same wheels.
double aloneIntrinsicsSpread(const JointFitReport& report);

/// Sensor `index`'s view of a joint fit as a one-sensor report: the intrinsics and its pose
/// with σ (then the derived values), its pairs, outliers, residuals (before: at the start values of
/// its fit alone) and observability verdict, the joint solve's convergence. For each sensor's table
/// and result file. Throws std::out_of_range for an index beyond the sensors.
ModelReport sensorModelReport(const JointFitReport& report, std::size_t index);

}  // namespace odometry_calibration
