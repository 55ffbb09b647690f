// The gyro as a further source of the joint fit: it sees rotation only. Its readings of the
// base's yaw rate (after the mounting, gyroYawRate) are integrated with the trapezoid rule over
// the IMU's own stamps into a heading track g(t) = int w dt. Over each keyframe pair [t0, t1] of
// the lasers (their measured rotation dtheta, which does not depend on where a laser sits) the
// gyro reads, with its clock shifted by d (the gyro's reading of instant t carries stamp t + d),
//   g(t1 + d) - g(t0 + d) = scale * dtheta + bias * (t1 - t0)           (reading = scale w + bias)
// so that dtheta = a (g(t1 + d) - g(t0 + d)) + c (t1 - t0) with a = 1 / scale, c = -bias / scale,
// linear in (a, c) for a given d. d is found by the project's one time-offset mechanism: the
// coarse search by heading correlation (coarse_time_offset.h, the gyro's heading change in place
// of the nominal robot's), then the fine one by refitting (time_offset.h, the linear fit above as
// the model). The wheels' parameters and the lasers' poses are those of the joint fit; the gyro
// adds three unknowns of its own and no information to them (its scale is free), so their values
// and σ are those of the fit without it.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/calibration/coarse_time_offset.h"
#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// One gyro reading of the base's yaw rate.
struct GyroSample
{
  double stamp_s = 0.0;         ///< the IMU's stamp [s]
  double yaw_rate_rad_s = 0.0;  ///< about base_link's z, after the mounting [rad/s]
};

/// The base's yaw rate from an IMU reading `angular_velocity_imu` [rad/s] in the IMU frame,
/// mounted with roll `roll_rad` about x, then pitch `pitch_rad` about y
/// (R_base_imu = R_y(pitch) R_x(roll)): the z row of R_base_imu times the reading.
double gyroYawRate(const Eigen::Vector3d& angular_velocity_imu, double roll_rad, double pitch_rad);

/// The search and the track.
struct GyroFitOptions
{
  double search_min_s = -0.4;  ///< the coarse search's range of d [s]
  double search_max_s = 0.4;
  double fine_half_width_s = 0.1;  ///< the fine search refits within this of the coarse d [s]
  double fine_step_s = 0.01;       ///< its grid step [s]
  /// Readings further apart than this are a gap: a pair whose searched window spans one is
  /// left out [s].
  double max_gap_s = 0.1;
  std::size_t min_pairs = 10;  ///< fewer usable pairs: no fit
};

/// What the gyro's fit gives. Offsets: `shift_s` is d above (relative to the pairs' stamps);
/// `time_offset_s` is in the project's convention of a source's offset (the encoders' values
/// at the gyro's stamp + tau): tau = pairs_time_offset_s - d.
struct GyroFit
{
  bool fitted = false;
  std::string problem;  ///< why not, when not fitted
  ParameterEstimate scale{"gyro_scale", "-"};
  ParameterEstimate bias{"gyro_bias", "rad/s"};
  ParameterEstimate time_offset{"gyro_time_offset", "s"};
  double shift_s = 0.0;           ///< d [s]
  std::size_t pairs = 0;          ///< pairs in the final fit
  double residual_rms_rad = 0.0;  ///< of dtheta at the fit [rad]
  std::optional<CoarseTimeOffset> coarse;
  TimeOffsetResult fine;
};

/// The gyro's heading track: the cumulative trapezoid integral of the yaw rate over the
/// readings' stamps (values(0) [rad]), and the gaps (start, end) [s] between readings more than
/// max_gap_s apart. Readings whose stamp does not increase are left out. NaN rates are left out.
struct GyroTrack
{
  std::vector<EncoderSample> heading;
  std::vector<std::pair<double, double>> gaps;
};
GyroTrack integrateGyro(const std::vector<GyroSample>& samples, double max_gap_s);

/// Fits the gyro's scale, bias and shift against `pairs` (their sensor_motion's rotation and
/// its variance; keyframe stamps on the clock of a source whose own offset is
/// `pairs_time_offset_s`). Not fitted (and `problem` naming the count, the turn or the
/// correlation) with too few pairs inside the readings, a robot that does not turn, or no peak.
GyroFit fitGyro(const std::vector<MotionPair>& pairs, double pairs_time_offset_s,
                const std::vector<GyroSample>& samples, const GyroFitOptions& options);

/// The fit in words, one line: scale, bias and time offset with σ, the pairs.
std::string gyroFitText(const GyroFit& fit);

/// result.yaml's `gyro:` block (appended to the file): `topic`, then `scale`, `bias_rad_s`,
/// `time_offset_s` each with its `_sigma`, `pairs`, `rotation_residual_rms_rad`; not fitted:
/// `fitted: false` and `problem`.
std::string gyroResultYaml(const GyroFit& fit, const std::string& topic);

}  // namespace odometry_calibration
