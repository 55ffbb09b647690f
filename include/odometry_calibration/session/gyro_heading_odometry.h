// ~odom with its heading from the calibrated gyro (gyro.odom_heading): the wheels' odometry
// (session_odometry.h) gives the translation, the gyro the rotation.
//
// The gyro's readings r (the base's yaw rate after the mounting, gyro_fit.h's gyroYawRate) are
// integrated with the trapezoid rule over the IMU's stamps into R(s) = int r ds. With the gyro's
// fit (reading = scale w + bias, its clock shifted by d: the reading of laser instant t carries
// the stamp t + d) the heading change between two odometry states at laser stamps t0 < t1 is
//   dpsi = (R(t1 + d) - R(t0 + d) - bias (t1 - t0)) / scale.
// The wheels' step between the two states, D = W0^-1 W1 = (dx, dy, dtheta_w) in the tracked
// frame at t0, moves the position along the chord of the gyro's arc rather than the wheels':
//   p1 = p0 + R(psi0 + (dpsi - dtheta_w) / 2) (dx, dy),   psi1 = psi0 + dpsi
// (an arc turning by a makes its chord a / 2 off its start heading). R(s) beyond the newest
// reading is extrapolated with that reading's rate for at most max_gap_s; a step the readings
// do not cover (none yet, silent longer than max_gap_s, a gap inside it) turns by the wheels'
// dtheta_w. The heading's variance is the fit's: psi's error from the scale's and the bias's
// sigma over the heading turned and the time elapsed since the gyro took over,
//   var(psi) = (sigma_scale / scale * (psi - psi_start))^2 + (sigma_bias / scale * (t -
//   t_start))^2,
// in place of the wheels' (their x, y variances kept, the heading's correlations dropped).
// Thread-safe: readings, odometry states and a new fit come from different threads.
#pragma once

#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>
#include <string>

#include "odometry_calibration/calibration/gyro_fit.h"
#include "odometry_calibration/session/session_odometry.h"

namespace odometry_calibration {

class GyroHeadingOdometry
{
public:
  /// `max_gap_s` (gyro.max_gap_s, > 0): readings further apart are a gap; the newest reading is
  /// extrapolated at most this far [s]. Throws std::invalid_argument otherwise.
  explicit GyroHeadingOdometry(double max_gap_s);

  /// The gyro's fit to use from now on (the heading goes on from where it is). Returns "" when
  /// taken, else why not (not fitted; a scale that is not finite and positive; a bias or shift
  /// that is not finite): the previous fit stays in use.
  std::string setCalibration(const GyroFit& fit);
  bool calibrated() const;

  /// One kept reading of the base's yaw rate `yaw_rate_rad_s` [rad/s] at the IMU's stamp
  /// `stamp_s` [s]. Returns "" when kept, else why not (not finite, a stamp not after the last).
  /// The readings of the last 2 s are kept (a wheel state later than that turns by the wheels).
  std::string addReading(double stamp_s, double yaw_rate_rad_s);

  /// The wheels' odometry state `wheels` with its heading (and pose) from the gyro, as above.
  /// Before the first fit: `wheels` unchanged. The first state after a fit and after a change
  /// of `wheels.continuity` (a restart, another model's odometry taking over) is taken as the
  /// new reference without moving the output; the first state ever, after reset() and after
  /// time went backwards places the output at the wheels' pose.
  OdometryState apply(const OdometryState& wheels);

  /// Steps that turned by the gyro, and by the wheels (readings missing), since the start.
  std::size_t gyroSteps() const;
  std::size_t wheelSteps() const;

  /// Drops the readings and the pose (the session's reset); the fit stays.
  void reset();

private:
  struct Reading
  {
    double stamp_s;
    double rate_rad_s;  ///< raw reading [rad/s]
    double integral;    ///< R(stamp_s) [rad]
  };
  /// R(s) from the readings: interpolated, or extrapolated within max_gap_s of the newest.
  std::optional<double> integralAt(double stamp_s) const;
  /// The corrected yaw rate at gyro stamp `stamp_s` (the nearest reading at or before it).
  std::optional<double> rateAt(double stamp_s) const;
  /// Takes `wheels` as the reference without moving the output pose.
  void rebase(const OdometryState& wheels);
  /// Whether readings more than max_gap_s apart lie across a part of (from_s, to_s].
  bool gapBetween(double from_s, double to_s) const;
  void dropReadingsBefore(double stamp_s);

  double max_gap_s_;
  mutable std::mutex mutex_;
  std::optional<GyroFit> fit_;
  std::deque<Reading> readings_;
  /// The reference: the wheels' last state, the gyro's integral at its stamp (none: not
  /// covered), the output's pose and heading there.
  std::optional<OdometryState> last_wheels_;
  std::optional<double> last_integral_;
  Pose2 pose_;
  bool at_wheels_ = true;     ///< the next reference places the output at the wheels' pose
  double heading_rad_ = 0.0;  ///< unwrapped
  double start_heading_rad_ = 0.0, start_stamp_s_ = 0.0;
  std::size_t gyro_steps_ = 0, wheel_steps_ = 0;
};

}  // namespace odometry_calibration
