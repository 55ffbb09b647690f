// One calibration from collected pairs, the same for the live node and calibrate_bag:
// pairs in, optional encoder-laser time offset, fit, report data out.
#pragma once

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/coarse_time_offset.h"
#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/eval/trajectory_comparison.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// What the job does besides the fit.
struct CalibrationJobOptions
{
  /// Estimate the time offset when the configuration asks for it (`estimate_time_offset`);
  /// needs the encoder history. The node has none yet and leaves it off.
  bool allow_time_offset = true;
  /// Chain the calibrated and nominal predictions against the matched displacements (the
  /// report's trajectories and per-pair errors; one prediction per pair and model).
  bool compare_trajectories = true;
  /// The time offset search already done on these same pairs and history (e.g. by
  /// CalibrationSession::calibrate when the pairs were not paired again): used instead of
  /// searching again.
  std::optional<TimeOffsetResult> time_offset_search;
  /// An estimate within this of the offset the pairs were made at keeps that offset: the pairs
  /// are fitted as made (the estimate is still reported) [s]. 0: any estimate is used.
  double keep_offset_within_s = 0.0;
};

/// The outcome of one calibration.
struct CalibrationJobResult
{
  std::shared_ptr<MotionModel> model;  ///< the fitted model (config.model)
  ModelReport report;                  ///< its report, time-offset warnings included
  /// How many of report.warnings are the time offset's (at the edge of its search range, not
  /// observable): the last ones.
  std::size_t time_offset_warnings = 0;
  std::vector<MotionPair> pairs;                ///< the pairs fitted (windows cut at time_offset_s)
  double time_offset_s = 0.0;                   ///< the offset the fit used [s]
  std::optional<TimeOffsetResult> time_offset;  ///< the offset search, when it ran
  /// The coarse search that placed the fine one (coarse_time_offset.h), when it ran.
  std::optional<CoarseTimeOffset> coarse_time_offset;
  /// Calibrated and nominal trajectories (with compare_trajectories); the nominal model is the
  /// configuration's prior at time offset 0, `nominal_description` says so (empty: none).
  TrajectoryComparison trajectories;
  std::string nominal_description;
  bool nominal_at_zero_offset = false;  ///< the nominal pairs were re-cut at time offset 0
  double fit_time_s = 0.0;              ///< wall time of the offset search and the fit [s]
};

/// Fits config.model to `pairs` (collected at config.collector.time_offset_s). With
/// `estimate_time_offset` in the configuration the offset tau is searched first on the pairs
/// re-cut from `encoder_history` (time_offset.h) and the fit uses the pairs at the estimate; a
/// flat cost curve keeps the configured offset and a minimum at the edge of the search range
/// warns. Throws std::runtime_error when the offset is asked for without a continuous encoder
/// history, std::invalid_argument from the model for too few or degenerate pairs.
CalibrationJobResult runCalibrationJob(const CalibrationConfig& config,
                                       const std::vector<MotionPair>& pairs,
                                       const std::vector<EncoderSample>& encoder_history,
                                       const CalibrationJobOptions& options = {});

/// The nominal robot's row (the configuration's prior, unfitted: scoreNominal, with its
/// configured sensor pose) on `pairs` made at `pairs_offset_s`, re-cut at time offset 0 from
/// `history` when that is given and the offset is not 0; none without a prior or with fewer than
/// two pairs left.
std::optional<ModelScore> scoreNominalRobot(const CalibrationConfig& config,
                                            const std::vector<MotionPair>& pairs,
                                            const std::vector<EncoderSample>& history,
                                            double pairs_offset_s);

/// The paper's comparison (Tables III/IV): the job's model and each of config.compare_models
/// (fitted to the job's pairs) scored on `test_pairs`, which were collected at the job's time
/// offset. The job's model comes first; the nominal robot (the configuration's prior, unfitted:
/// scoreNominal) comes last when there is one, at time offset 0 like the report's nominal (the
/// test pairs re-cut from `test_history` when it is given and the job's offset is not 0). A
/// compared model that cannot be fitted to these pairs is a skipped row with the reason.
std::vector<ModelScore> scoreModelsOnTest(const CalibrationConfig& config,
                                          const CalibrationJobResult& job,
                                          const std::vector<MotionPair>& test_pairs,
                                          const std::vector<EncoderSample>& test_history = {});

/// Held-out scores: scoreModelsOnTest (the job's model, each of config.compare_models fitted to
/// the job's pairs, the nominal robot at time offset 0) on `test_pairs`, which were collected
/// at the configuration's time offset and are re-cut at the job's from `encoder_history` when
/// the two differ. One table for `--test` and `--holdout`.
std::vector<ModelScore> scoreHeldOut(const CalibrationConfig& config,
                                     const CalibrationJobResult& job,
                                     const std::vector<MotionPair>& test_pairs,
                                     const std::vector<EncoderSample>& encoder_history);

/// The time-offset search in words: the estimate with sigma and the cost curve, one line each.
std::string formatTimeOffset(const TimeOffsetResult& offset);

/// The text report's line comparing the nominal (at time offset 0) and calibrated median
/// per-pair RPE; empty without a nominal model or an encoder history to re-cut its pairs.
std::string formatNominalComparison(const CalibrationJobResult& job);

/// calibrate_bag's exit status for a fit: 3 not converged, 4 converged with warnings, 0 clean.
int calibrationExitStatus(const ModelReport& report);
/// The same for a job, with the time offset apart: 3 not converged; 5 converged, but the time
/// offset lies at the edge of its search range or is not observable; 4 converged with another
/// warning (a parameter not determined); 0 a result to stand behind (notes and advice aside).
int calibrationExitStatus(const CalibrationJobResult& job);

}  // namespace odometry_calibration
