// Health monitor of a calibrated gyro: watches its scale and bias for drift as health_monitor.h
// watches the wheels, against the rotation the lasers measure.
//
// The gyro's readings (the base's yaw rate, stamps on the gyro's clock) are integrated with the
// trapezoid rule into a heading track g(t). Over each keyframe pair [t0, t1] of a laser (its
// measured rotation dtheta) the calibration (scale s, bias b, shift d: the gyro's reading of
// instant t carries stamp t + d; gyro_fit.h) predicts
//   g(t1 + d) - g(t0 + d) = s dtheta + b (t1 - t0),
// so the calibrated residual is
//   r = (g(t1 + d) - g(t0 + d) - b (t1 - t0)) / s - dtheta   [rad].
// A scale change ds gives r = (ds / s) dtheta, which follows the turn, and a bias change db gives
// r = (db / s) (t1 - t0), which does not, so two signals are watched (the scale one weighted
// by dtheta, the likelihood ratio's weight of a shift proportional to dtheta):
//   scale:  r dtheta              (pairs that turn, |dtheta| > min_rotation_rad) [rad^2]
//   bias:   r / (t1 - t0)         (pairs that do not turn) [rad/s]
// Each signal learns its noise on its first burn_in_pairs values (their spread, outliers beyond
// 4 robust sigmas left out), then
// is standardised, given a self-starting centre (the mean of its earlier clipped values shrunk
// towards 0 as if chart_burn_in_pairs more had read 0, the difference scaled by
// sqrt(1 + n / (n + n0)^2), as health_monitor.h does), clipped and fed to a two-sided tabular
// CUSUM (Page 1954): U = max(0, U + z - k), L = max(0, L - z - k), alarm when U or L exceeds h,
// with k = delta / 2 and h from cusumThreshold for the configured false-alarm rate. At the alarm,
// the pairs from the change point (where the firing side last stood at 0) on are fitted by least
// squares to g(t1 + d) - g(t0 + d) = s' dtheta + b' (t1 - t0), naming the gyro's scale and bias
// now beside the calibrated ones; the cause named is the one of the two whose change is the
// larger in units of its σ (a run of left turns makes a bias change look like a scale change to
// the scale chart alone).
#pragma once

#include <array>
#include <cstddef>
#include <deque>
#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// The gyro's calibration the monitor watches (gyro_fit.h's GyroFit values).
struct GyroCalibration
{
  double scale = 1.0;       ///< s: reading = s * rate + b [-]
  double bias_rad_s = 0.0;  ///< b [rad/s]
  double shift_s = 0.0;     ///< d: the reading of instant t carries stamp t + d [s]
};

/// Options of the gyro's monitor.
struct GyroHealthOptions
{
  /// Mean number of scored pairs between false alarms, both signals together [pairs].
  double false_alarm_pairs = 1e6;
  double design_shift_sigma = 1.0;  ///< shift the CUSUM is tuned for, delta [sigma]; k = delta/2
  int burn_in_pairs = 60;           ///< per signal: values for its robust spread
  int chart_burn_in_pairs = 20;     ///< per signal: pseudo-zeros of its self-starting centre
  double clip_sigma = 4.0;          ///< standardised values are clipped to +-this [sigma]
  double min_rotation_rad = 0.05;   ///< a pair "turns" beyond this measured |dtheta| [rad]
  double max_gap_s = 0.1;           ///< readings further apart: a pair spanning them is skipped
  double history_s = 30.0;          ///< readings kept behind the newest one [s]
  std::size_t max_pending_pairs = 200;  ///< pairs waiting for readings; older ones are skipped
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const GyroHealthOptions& options);

/// One signal's state.
struct GyroHealthChart
{
  std::string name;               ///< "gyro scale" or "gyro bias"
  std::size_t count = 0;          ///< values that fed it
  bool calibrated = false;        ///< burn-in done
  double spread = 1.0;            ///< robust spread of its burn-in values [rad^2 or rad/s]
  double upper = 0.0;             ///< CUSUM of upward shifts, U [sigma]
  double lower = 0.0;             ///< CUSUM of downward shifts, L [sigma]
  double centre_sum = 0.0;        ///< sum of its clipped standardised values (the centre)
  std::size_t centre_count = 0;   ///< values in centre_sum
  std::size_t upper_zero_at = 0;  ///< pairs scored when U last stood at 0
  std::size_t lower_zero_at = 0;  ///< pairs scored when L last stood at 0
  std::vector<double> burn_in;    ///< values until calibrated
};

/// The gyro monitor's verdict.
struct GyroHealthStatus
{
  bool alarm = false;       ///< a sustained shift was found (latched)
  std::size_t pairs = 0;    ///< pairs scored
  std::size_t skipped = 0;  ///< pairs not scored (no readings around them, a gap, too many waiting)
  double threshold = 0.0;   ///< h [sigma]
  double statistic = 0.0;   ///< max over the charts of max(U, L) / h (alarm at 1)
  std::array<GyroHealthChart, 2> charts;  ///< scale, bias
  std::string alarm_chart;                ///< the chart that fired
  double alarm_stamp_s = 0.0;             ///< end stamp of the pair that raised it [s]
  /// With the alarm: the scale and bias fitted to the pairs since the change point.
  double scale_now = 0.0, bias_now_rad_s = 0.0;
  std::size_t pairs_since_change = 0;
  /// "gyro scale" or "gyro bias": the one of the two whose change is the larger in units of its
  /// σ in that fit (the chart that fired when the fit is not determined).
  std::string cause;
  std::string message;  ///< "ok" or what drifted, its value now and "refit (call ~calibrate)"
};

/// Watches one calibrated gyro against one laser's pairs. Keeps history_s of readings and three
/// numbers per scored pair (the fit since the change point). Not thread-safe.
class GyroHealthMonitor
{
public:
  /// Throws std::invalid_argument for a scale that is not finite and > 0, a bias or shift that is
  /// not finite, or invalid options.
  GyroHealthMonitor(const GyroCalibration& calibration, GyroHealthOptions options);

  /// One reading of the base's yaw rate [rad/s] at the gyro's stamp [s]. Returns "" when kept,
  /// else why not (a stamp not after the last, a value that is not finite). Scores the pairs the
  /// readings now cover; returns the alarm through status().
  std::string addReading(double stamp_s, double yaw_rate_rad_s);
  /// One pair of the laser (its stamps on the pairs' clock); scored once readings cover
  /// [t0 + d, t1 + d]. Returns true when a pair scored by this call raised the alarm.
  bool addPair(const MotionPair& pair);
  GyroHealthStatus status() const;

private:
  struct Reading
  {
    double stamp_s;
    double rate_rad_s;
    double heading_rad;  ///< trapezoid integral from the first reading
    bool after_gap;      ///< more than max_gap_s after the previous reading
  };
  /// What the least squares at the alarm needs of a scored pair.
  struct Scored
  {
    double gyro_rad, dtheta_rad, duration_s;
  };
  bool scorePending();
  bool headingAt(double stamp_s, double* heading_rad) const;
  bool covered(double start_s, double end_s) const;
  bool score(const MotionPair& pair);
  bool feed(GyroHealthChart& chart, double value, double stamp_s);
  void fitSinceChange(GyroHealthStatus* status) const;

  GyroCalibration calibration_;
  GyroHealthOptions options_;
  double k_ = 0.5, h_ = 0.0;
  std::deque<Reading> readings_;
  std::deque<MotionPair> pending_;
  std::vector<Scored> scored_;
  std::array<GyroHealthChart, 2> charts_;
  std::size_t skipped_ = 0;
  bool alarm_ = false;
  std::size_t alarm_chart_ = 0, change_at_ = 0;
  double alarm_stamp_s_ = 0.0;
};

}  // namespace odometry_calibration
