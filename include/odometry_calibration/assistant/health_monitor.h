// Health monitor of an active calibration: scores each new pair against the model's
// prediction and raises an alarm when the calibration no longer fits the robot (tyre wear, a new
// load, a knocked laser), and names what changed.
//
// Per pair, the residual r = measured - predicted sensor motion is standardised per output by the
// predictive covariance (model covariance + the pair's own), z_k = r_k / sqrt(S_kk). A
// calibration error shifts r in a direction that follows the motion (a shrunk wheel shortens the
// rotation of a left and a right spot turn alike, but with opposite signs of r_theta), so each
// monitored signal multiplies z by the sign of the predicted motion it scales:
//   travel:          sign(dx) z_x          (pairs that travel)
//   sideways:        sign(dx) z_y          (pairs that travel: a yawed sensor)
//   rotation:        sign(dtheta) z_theta  (pairs that turn)
//   heading drift:   sign(dx) z_theta      (pairs that travel straight: unequal wheel radii)
//   turn sideways:   sign(dtheta) z_y      (pairs that turn: the sensor moved along base x)
//   turn along:      sign(dtheta) z_x      (pairs that turn: the sensor moved along base y)
// The monitor first learns the noise on its first burn_in_pairs pairs that move: per output the
// robust spread of z (1.4826 MAD, so a mis-scaled covariance does not matter), which every
// signal of that output uses, so that all charts are ready together (the heading chart, fed
// only by straight runs, used to wait for 100 values of its own: minutes). A signal's centre is
// self-starting (Hawkins, "Self-starting CUSUM charts for location and scale", The
// Statistician 1987): the mean of all its earlier values (clipped), shrunk towards 0 as if
// chart_burn_in_pairs more had read 0 (a calibration fits its own robot without bias), each
// new value's difference from it scaled by its spread sqrt(1 + n / (n + n0)^2); a centre fixed
// from a few dozen burn-in values would be off by a quarter sigma, enough to drift a CUSUM into
// a false alarm within minutes. The centre stops learning at the alarm. Each signal is then
// standardised, clipped, and fed to a two-sided tabular CUSUM (Page 1954; Montgomery,
// "Introduction to Statistical Quality Control", 9.1):
//   U = max(0, U + z - k),  L = max(0, L - z - k),  alarm when U or L exceeds h,
// with k = delta / 2 for a design shift delta and h chosen so that Siegmund's approximation of
// the in-control average run length, ARL0 = (exp(2 k b) - 2 k b - 1) / (2 k^2), b = h + 1.166,
// meets the configured false-alarm rate. The change point is where the firing side of the chart
// last stood at zero (the CUSUM's maximum-likelihood estimate); the pairs from there on are
// regressed on each candidate change (change_attribution.h, change_hypotheses.h) to name the
// cause, again at every status() while the alarm stands (more pairs, a surer verdict).
//
// Several sensors (a front and a rear laser calibrated jointly, one set of wheels and a
// pose per laser): one monitor watches them all, each pair tagged with its sensor. Each sensor
// has its own six charts and learns its own noise (its model predicts its motion: the joint
// calibration's wheels with its pose); the false alarms are shared by all the charts; the
// attribution's candidates are the wheel quantities, regressed on every sensor's pairs, and each
// sensor's mounting x, y, yaw, regressed on its own (change_hypotheses.h), so a knocked laser
// is named as that laser and a wheel change, seen by every laser, as the wheels. With one
// sensor the monitor is the one-source monitor it always was (same charts, same numbers).
#pragma once

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/assistant/change_attribution.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// Options of the monitor.
struct HealthMonitorOptions
{
  /// Mean number of scored pairs between false alarms, over all signals together [pairs]
  /// (at 2 pairs/s, 1e6 pairs is about 140 h of driving).
  double false_alarm_pairs = 1e6;
  double design_shift_sigma = 1.0;    ///< shift the CUSUM is tuned for, delta [sigma]; k = delta/2
  int burn_in_pairs = 100;            ///< pairs that move, for each output's robust spread
  int chart_burn_in_pairs = 20;       ///< per signal: values for its robust centre
  double clip_sigma = 4.0;            ///< standardised values are clipped to +-this [sigma]
  double min_travel_m = 0.02;         ///< a pair "travels" beyond this predicted |x| [m]
  double min_rotation_rad = 0.02;     ///< a pair "turns" beyond this predicted |theta| [rad]
  std::string sensor_name = "laser";  ///< the ego-motion source, in the causes' names
  std::vector<std::string> joint_names;  ///< encoder joints in sample order (causes; may be empty)
  ChangeAttributionOptions attribution;  ///< naming the cause
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const HealthMonitorOptions& options);

/// The CUSUM threshold h for a one-sided chart with reference k whose in-control average run
/// length is `arl0` (Siegmund's approximation, solved by bisection).
double cusumThreshold(double k, double arl0);

/// The monitored signals.
enum HealthSignal
{
  kTravelSignal = 0,
  kSidewaysSignal,
  kRotationSignal,
  kHeadingDriftSignal,
  kTurnSidewaysSignal,
  kTurnAlongSignal,
  kHealthSignalCount
};

/// One watched sensor: the model predicting its motion, and its name in the messages.
struct WatchedSensor
{
  std::shared_ptr<const MotionModel> model;
  std::string name;  ///< e.g. "laser_rear" (its frame or topic); "laser" with one sensor
};

/// One signal's state.
struct HealthChart
{
  /// "travel", "sideways", "rotation", "heading drift", "turn sideways", "turn along"
  std::string name;
  std::string output;             ///< the output it watches: "x", "y" or "theta"
  std::size_t sensor = 0;         ///< the sensor whose pairs feed it (WatchedSensor index)
  std::string sensor_name;        ///< its name
  std::size_t count = 0;          ///< pairs that fed it
  bool calibrated = false;        ///< burn-in done
  double centre = 0.0;            ///< robust centre of the burn-in values [sigma]
  double scale = 1.0;             ///< robust spread of the burn-in values [sigma]
  double upper = 0.0;             ///< CUSUM of upward shifts, U
  double lower = 0.0;             ///< CUSUM of downward shifts, L
  double mean_recent = 0.0;       ///< exponential mean of the standardised values (20 pairs)
  double centre_sum = 0.0;        ///< sum of its clipped standardised values (the centre)
  std::size_t centre_count = 0;   ///< values in centre_sum
  std::size_t upper_zero_at = 0;  ///< pairs scored when U last stood at 0
  std::size_t lower_zero_at = 0;  ///< pairs scored when L last stood at 0
};

/// The monitor's verdict at one moment.
struct HealthStatus
{
  bool active = false;     ///< a model is being watched
  bool alarm = false;      ///< a sustained shift was found (latched until reset)
  std::size_t pairs = 0;   ///< pairs scored
  double threshold = 0.0;  ///< h [sigma]
  /// max over the charts of max(U, L) / h: the published statistic (alarm at 1).
  double statistic = 0.0;
  std::vector<HealthChart> charts;  ///< sensor 0's six signals, then sensor 1's, ...
  std::size_t sensors = 1;          ///< sensors watched
  std::string alarm_output;         ///< "x", "y" or "theta" of the chart that fired
  std::size_t alarm_sensor = 0;     ///< the sensor of the chart that fired
  double alarm_stamp_s = 0.0;       ///< end stamp of the pair that raised the alarm [s]
  /// With the alarm: what changed, from the pairs since the change point (now).
  ChangeVerdict cause;
  /// In words: "ok" or what drifted, the cause and "refit (call ~calibrate)".
  std::string message;
};

/// Watches one fitted model. Not thread-safe.
class HealthMonitor
{
public:
  /// One sensor, named by options.sensor_name. Throws std::invalid_argument for a null model
  /// or invalid options.
  HealthMonitor(std::shared_ptr<const MotionModel> model, HealthMonitorOptions options);
  /// Several sensors of one robot (each model the joint calibration's wheels with that
  /// sensor's pose; options.sensor_name unused). One sensor: as the constructor above with its
  /// name. Throws std::invalid_argument for no sensor, a null model, a name empty or repeated,
  /// or invalid options.
  HealthMonitor(std::vector<WatchedSensor> sensors, HealthMonitorOptions options);

  /// Scores one pair of sensor `sensor` (index of the sensors given; 0 with one); returns true
  /// when this pair raised the alarm. Pairs the model cannot predict (too few samples, bad
  /// joints) or with a non-finite residual are skipped. Throws std::invalid_argument for a
  /// sensor beyond those watched.
  bool addPair(const MotionPair& pair, std::size_t sensor = 0);
  HealthStatus status() const;
  std::size_t skipped() const { return skipped_; }
  std::size_t sensors() const { return sensors_.size(); }

private:
  /// One sensor's model, charts and noise.
  struct SensorState
  {
    WatchedSensor watched;
    std::array<HealthChart, kHealthSignalCount> charts;
    std::array<std::vector<double>, kHealthSignalCount> burn_in;
    std::array<std::vector<double>, 3> noise_burn_in;  ///< z per output of pairs that move
    bool noise_learnt = false;
    Eigen::Vector3d output_scale = Eigen::Vector3d::Ones();  ///< robust spread of z per output
  };
  void makeAttribution(const MotionPair& pair);
  void learnNoise(SensorState& sensor, const Eigen::Vector3d& z);
  void feed(SensorState& sensor, HealthSignal signal, double value, double stamp_s);

  std::vector<SensorState> sensors_;
  HealthMonitorOptions options_;
  double k_ = 0.5, h_ = 0.0;
  std::unique_ptr<ChangeAttribution> attribution_;  ///< made on the first pair
  std::size_t pairs_ = 0, skipped_ = 0;
  bool alarm_ = false;
  std::string alarm_where_, alarm_output_;
  std::size_t alarm_sensor_ = 0;
  std::size_t change_at_ = 0;  ///< pairs scored before the estimated change point
  double alarm_stamp_s_ = 0.0;
};

}  // namespace odometry_calibration
