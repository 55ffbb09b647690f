// The evidence behind a calibration, pair by pair: the scan-matched displacements, the nominal
// model's and the calibrated model's predictions over the same keyframe intervals, chained
// into trajectories (for the report's trajectory plot), and the per-pair prediction errors
// (for its residual histograms).
#pragma once

#include <cstddef>
#include <vector>

#include "odometry_calibration/common/median.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// Three chained trajectories of the sensor over the same keyframe intervals, and the
/// per-interval errors of the two predictions against the measurement.
struct TrajectoryComparison
{
  /// Keyframe times [s]: the first pair's start, then every pair's end.
  std::vector<double> stamps_s;
  /// Sensor poses in the sensor frame of the first keyframe [m, m, rad], one per stamp: the
  /// composition of the measured displacements (scan matching), of the nominal model's
  /// predictions (empty without a nominal model) and of the calibrated model's predictions.
  std::vector<Pose2> matched, nominal, calibrated;
  /// Per pair: the prediction's error against the measurement, between(measured, predicted)
  /// (empty for the nominal without a nominal model).
  std::vector<Pose2> nominal_errors, calibrated_errors;
  /// Pairs that do not start where the previous one ended (a rejected interval lies between):
  /// the trajectories are chained across the gap, which all three skip alike.
  std::size_t gaps = 0;
};

/// Chains the pairs and the models' predictions. `calibrated_pairs` carry the encoder windows
/// the calibrated model was fitted on (at the estimated time offset); `nominal_pairs` those of
/// the nominal model (at its offset), matched to them by keyframe times: pairs missing from
/// either list are left out. Pass nominal == nullptr when there is no nominal model. Throws
/// std::invalid_argument when no pair remains.
TrajectoryComparison compareTrajectories(const std::vector<MotionPair>& calibrated_pairs,
                                         const MotionModel& calibrated,
                                         const std::vector<MotionPair>& nominal_pairs,
                                         const MotionModel* nominal);

/// Translation length of each error [m].
std::vector<double> translationErrors(const std::vector<Pose2>& errors);

/// |rotation| of each error [rad].
std::vector<double> rotationErrors(const std::vector<Pose2>& errors);

}  // namespace odometry_calibration
