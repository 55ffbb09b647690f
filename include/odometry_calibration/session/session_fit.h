// One calibration of a session's pairs, the same for the live node's ~calibrate and for
// calibrate_bag (parity by construction): the keyframe interval of the fitted pairs
// (the configured one, a given one, or one chosen by time-blocked cross-validation among the
// candidates, calibration/fit_interval.h), then the calibration job (calibration_job.h: the
// encoder-laser time offset when the configuration asks for it, the fit).
#pragma once

#include <cmath>
#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/config/calibration_config.h"

namespace odometry_calibration {

/// How the keyframe interval of the fitted pairs is found.
enum class FitIntervalMode
{
  kConfigured,  ///< keyframes.interval_s
  kFixed,       ///< SessionFitRequest::fixed_interval_s (one of the candidates)
  kChoose,      ///< cross-validation among keyframes.interval_s and the candidates
};

struct SessionFitRequest
{
  CalibrationConfig config;       ///< the model's configuration (config.model is the one fitted)
  std::vector<MotionPair> pairs;  ///< at keyframes.interval_s, time offset as configured
  std::vector<IntervalPairs> candidates;       ///< the other intervals' pairs, collected alike
  std::vector<EncoderSample> encoder_history;  ///< continuous since the first pair (or empty)
  FitIntervalMode interval_mode = FitIntervalMode::kConfigured;
  double fixed_interval_s = 0.0;  ///< with kFixed [s]
  /// With kChoose: the cuts of the cross-validation (empty: FitIntervalOptions' default).
  std::vector<std::size_t> fold_counts;
  /// Only pairs ending by this stamp are fitted (calibrate_bag --holdout: the training part).
  double fit_until_stamp_s = INFINITY;
  /// The time-offset search already run on exactly `pairs` (reused with kConfigured).
  std::optional<TimeOffsetResult> offset_search;
  bool compare_trajectories = false;  ///< the report's trajectories (calibration_job.h)
};

/// Beyond this difference between the time offset estimated on the pairs and the one they were
/// paired at, calibrate() pairs the recorded inputs again (nextPairingOffset_s); within it the
/// pairs and their offset stand [s].
constexpr double kOffsetPairingToleranceS = 0.002;
/// At most this many pairings again (an offset found far from the configured one settles in
/// two to four).
constexpr int kMaxPairingRounds = 4;

/// One pairing of the recorded inputs: the time offset it paired at and the one estimated on
/// its pairs [s].
struct OffsetRound
{
  double paired_at_s = 0.0;
  double estimate_s = 0.0;
};

/// The offset to pair at after the pairings `before` and `last`: the estimate f(t) on pairs
/// made at offset t leans toward t, and the offset sought is the fixed point f(t) = t. The
/// secant of g(t) = f(t) - t through the two, t1 - g1 (t1 - t0) / (g1 - g0), when its slope
/// lies in [-2, -0.25]; otherwise (a lean the secant cannot trust, or t0 = t1) the last
/// estimate f(t1) [s].
double nextPairingOffset_s(const OffsetRound& before, const OffsetRound& last);

/// How calibrate() paired the inputs when the configuration estimates the time offset.
struct OffsetPairing
{
  double configured_s = 0.0;  ///< the offset the pairs were made at [s]
  double estimate_s = 0.0;    ///< the offset estimated on them [s]
  bool paired_again = false;  ///< the recorded inputs were paired again, at estimate_s
  std::string text;           ///< what was done, one line ending in '\n' (empty: nothing estimated)
};

struct SessionFit
{
  CalibrationJobResult job;
  double fit_interval_s = 0.0;              ///< the interval of the fitted pairs [s]
  std::optional<FitIntervalChoice> choice;  ///< the cross-validation, when it ran
  std::string interval_text;  ///< how the interval was found, one line (empty: configured)
  /// With kChoose: why cross-validation could not choose (the fit then used keyframes.interval_s
  /// and warns); empty otherwise.
  std::string interval_problem;
  bool offset_estimated = false;  ///< the time offset was searched (history available)
  /// With the offset estimated: how the session made the fitted pairs (CalibrationSession::
  /// calibrate; fitSessionPairs leaves it empty).
  OffsetPairing offset_pairing;
};

/// Fits request.config.model as described above. The time offset is searched only with an
/// encoder history; asked for without one, the fit keeps the configured offset and warns.
/// Throws std::invalid_argument (too few or degenerate pairs, an unknown fixed interval) and
/// what the model's fit throws.
SessionFit fitSessionPairs(const SessionFitRequest& request);

/// The sentence on the time offset for a reply: the estimate with sigma, or why there is none
/// ("" when the configuration does not ask for it).
std::string timeOffsetSentence(const CalibrationConfig& config, const SessionFit& fit);

}  // namespace odometry_calibration
