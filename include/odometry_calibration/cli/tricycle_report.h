// The text calibrate_tricycle prints, made from the session's fit and the common scores
// (model_comparison.h's rows of the calibrated model and the nominal robot on a stretch of the
// log): the keyframe interval, the held-out errors and the calibration report.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/models/tricycle_calibration.h"
#include "odometry_calibration/session/session_fit.h"

namespace odometry_calibration {

/// The keyframe interval's lines: T chosen by time-blocked cross-validation (fit.choice's
/// validation curve, its evaluation pairs `evaluation_interval_s` long), not chosen
/// (fit.interval_problem, the interval then used) or set by hand.
std::string formatTricycleInterval(const SessionFit& fit, double evaluation_interval_s);

/// The last part of the log, never seen by the fit, and the scores of its keyframe pairs.
struct TricycleHeldOut
{
  double fraction = 0.0;         ///< the part of the samples held out, in (0, 1)
  std::size_t samples = 0;       ///< the log's rows in it
  double duration_s = 0.0;       ///< their span [s]
  std::vector<ModelScore> rows;  ///< scoreHeldOut's rows: the calibrated model first, nominal
};

/// The held-out lines: the part held out, then the ATE and RPE (paper eqs. 11, 10) of the
/// nominal and the calibrated model's chained predictions.
std::string formatTricycleHeldOut(const TricycleHeldOut& held_out);

/// The report: pairs, inliers and outliers, solver, parameters with sigma, the residual RMS per
/// keyframe pair before and after, the ATE and RPE of the sensor trajectory dead-reckoned over
/// the fitted keyframe pairs (`fitted`: scoreHeldOut's rows on them, the calibrated model first,
/// the nominal robot's as "initial"), warnings and notes.
std::string formatTricycleReport(const TricycleCalibrationResult& result,
                                 const std::vector<ModelScore>& fitted);

}  // namespace odometry_calibration
