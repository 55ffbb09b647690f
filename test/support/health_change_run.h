// One simulated drive for the health monitor (issue 34): a differential drive driving at random,
// a diff_drive calibration fitted at one moment, one change of the robot or its laser mid-run
// (or none: the unchanged twin, same seed), and the monitor scoring every pair after the fit.
// Records when the alarm came, what it named then and 30 s after the change, and when the
// heading chart was ready. Used by test/assistant/health_monitor_changes_test.cpp (a few seeds)
// and bench/health_change_study.cpp (the seed sweep quoted in docs/live_assistant.md).
#pragma once

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace health_runs {

constexpr double kRadiusM = 0.077;
constexpr double kSeparationM = 0.33;

/// The changes of the acceptance.
enum class Change
{
  kNone,         ///< the unchanged twin
  kRightRadius,  ///< right wheel radius +2 %
  kSeparation,   ///< wheel separation +3 %
  kLaserYaw,     ///< laser mounting yaw +1.5 deg
  kLaserX,       ///< laser mounting x +3 cm
};

inline const char* changeName(Change change)
{
  switch (change) {
    case Change::kNone:
      return "unchanged";
    case Change::kRightRadius:
      return "right radius +2 %";
    case Change::kSeparation:
      return "separation +3 %";
    case Change::kLaserYaw:
      return "laser yaw +1.5 deg";
    default:
      return "laser x +3 cm";
  }
}

/// The hypothesis (change_hypotheses.h) that names `change`, and its kind.
inline std::string expectedQuantity(Change change)
{
  switch (change) {
    case Change::kRightRadius:
      return "right wheel radius";
    case Change::kSeparation:
      return "wheel separation";
    case Change::kLaserYaw:
      return "laser mounting yaw";
    case Change::kLaserX:
      return "laser mounting x";
    default:
      return "";
  }
}

inline ChangeKind expectedKind(Change change)
{
  return change == Change::kLaserYaw || change == Change::kLaserX ? ChangeKind::kMounting
                                                                  : ChangeKind::kWheel;
}

struct RunOptions
{
  Change change = Change::kNone;
  unsigned seed = 1;
  double duration_s = 600.0;  ///< simulated drive [s]
  double fit_at_s = 124.0;    ///< the calibration is fitted on the pairs before [s]
  double change_at_s = 300.0;
  double verdict_after_s = 30.0;  ///< the verdict is read this long after the change [s]
};

struct RunResult
{
  bool alarm = false;
  double alarm_delay_s = NAN;    ///< alarm stamp - change time (negative: before the change)
  std::string message;           ///< the monitor's message at the alarm
  ChangeVerdict at_alarm;        ///< the cause named with the alarm
  ChangeVerdict later;           ///< the cause verdict_after_s after the change (alarm by then)
  bool later_valid = false;      ///< the alarm came before verdict_after_s
  double heading_ready_s = NAN;  ///< after the fit, when the heading-drift chart was ready [s]
  double statistic = 0.0;        ///< the monitor's statistic at the end (or at the alarm)
};

/// Whether `verdict` names `change` rightly: the kind told and right; the quantity, if told,
/// right. `strict`: also a told kind is required (false: "cannot tell" passes).
inline bool namedRightly(const ChangeVerdict& verdict, Change change, bool strict)
{
  if (!verdict.kind_told)
    return !strict;
  if (verdict.kind != expectedKind(change))
    return false;
  return !verdict.quantity_told ||
         verdict.candidates.front().hypothesis.name == expectedQuantity(change);
}

inline sim::PairGeneratorOptions pairOptions(const RunOptions& run)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", kRadiusM},
                    {"wheel_radius_right_m", kRadiusM},
                    {"wheel_separation_m", kSeparationM}}};
  options.T_base_sensor = Pose2(0.15, 0.02, 0.05);
  options.motion.max_speed_mps = 0.4;
  options.duration_s = run.duration_s;
  options.interval_s = 0.5;
  options.translation_noise_m = 0.002;
  options.rotation_noise_rad = 0.0015;
  options.seed = run.seed;
  sim::ParameterChange change;
  change.at_s = run.change_at_s;
  switch (run.change) {
    case Change::kRightRadius:
      change.robot_parameters["wheel_radius_right_m"] = 1.02 * kRadiusM;
      break;
    case Change::kSeparation:
      change.robot_parameters["wheel_separation_m"] = 1.03 * kSeparationM;
      break;
    case Change::kLaserYaw:
      change.laser_yaw_change_rad = 1.5 * M_PI / 180.0;
      break;
    case Change::kLaserX:
      change.laser_x_change_m = 0.03;
      break;
    default:
      return options;
  }
  options.changes = {change};
  return options;
}

/// The diff_drive calibration of the pairs that end by fit_at_s.
inline std::shared_ptr<DiffDriveModel> fitBefore(const std::vector<MotionPair>& pairs,
                                                 double fit_at_s)
{
  std::vector<MotionPair> calibration;
  for (const MotionPair& pair : pairs) {
    if (pair.end_stamp_s <= fit_at_s)
      calibration.push_back(pair);
  }
  DiffDriveOptions nominal;
  nominal.initial_left_radius_m = 0.075;
  nominal.initial_right_radius_m = 0.079;
  nominal.initial_separation_m = 0.32;
  nominal.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  auto model = std::make_shared<DiffDriveModel>(nominal);
  model->fit(calibration);
  return model;
}

/// The run: fit, change, monitor. Stops at the end of the drive or verdict_after_s after the
/// change once the alarm has come.
inline RunResult runChange(const RunOptions& run, HealthMonitorOptions options = {})
{
  const sim::GeneratedPairs data = sim::generatePairs(pairOptions(run));
  HealthMonitor monitor(fitBefore(data.pairs, run.fit_at_s), options);
  RunResult result;
  for (const MotionPair& pair : data.pairs) {
    if (pair.start_stamp_s < run.fit_at_s)
      continue;
    if (monitor.addPair(pair)) {
      const HealthStatus status = monitor.status();
      result.alarm = true;
      result.alarm_delay_s = status.alarm_stamp_s - run.change_at_s;
      result.message = status.message;
      result.at_alarm = status.cause;
      result.statistic = status.statistic;
    }
    if (std::isnan(result.heading_ready_s) &&
        monitor.status().charts[kHeadingDriftSignal].calibrated)
      result.heading_ready_s = pair.end_stamp_s - run.fit_at_s;
    if (result.alarm && pair.end_stamp_s >= run.change_at_s + run.verdict_after_s) {
      result.later = monitor.status().cause;
      result.later_valid = true;
      break;
    }
  }
  if (!result.alarm)
    result.statistic = monitor.status().statistic;
  return result;
}

}  // namespace health_runs
}  // namespace odometry_calibration
