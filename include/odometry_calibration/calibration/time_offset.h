// Estimation of the time offset tau between the encoder and the laser clocks: encoder values
// are taken at scan time + tau. The pairs' measured displacements do not depend on tau, their
// encoder windows do: for each tau of a grid the windows are cut again from the full encoder
// history, the model is refitted, and the mean Huber loss of the prediction errors is recorded;
// the minimum is refined with a parabola through its neighbours, whose curvature gives the
// offset's sigma.
#pragma once

#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include "odometry_calibration/data/encoder_track.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// The search.
struct TimeOffsetOptions
{
  double min_s = -0.4;   ///< search range start [s]
  double max_s = 0.4;    ///< search range end [s]
  double step_s = 0.02;  ///< grid step [s]
  /// Fraction of the largest errors left out of the cost at each offset [-]. 0: none. A set
  /// trimmed at each offset anew leaves out, away from the true offset, the pairs that tell it
  /// best (those turning fastest, whose errors grow most): the curve flattens on one side and
  /// its minimum moves (by 14 ms on a simulated 4.5 Hz base with a sweeping 5.5 Hz scanner).
  double trim = 0.0;
  /// Each pair's squared whitened error r^2 enters the cost through Huber's loss with this
  /// threshold k: r^2 up to k, 2 k r - k^2 beyond, so that a wrong match pulls the minimum
  /// by a bounded amount (0: r^2) [sigma].
  double huber_threshold = 3.0;
  /// How the windows' end values are taken between encoder readings.
  EncoderInterpolation interpolation = EncoderInterpolation::kCubic;
};

/// The estimate and the cost curve behind it.
struct TimeOffsetResult
{
  double offset_s = 0.0;  ///< tau [s]
  double sigma_s = 0.0;   ///< its standard deviation from the cost curvature [s]; NaN if flat
  std::vector<std::pair<double, double>> curve;  ///< (tau [s], cost [-]) over the grid
  bool at_boundary = false;                      ///< the minimum lies on the search range's edge
  bool flat = false;  ///< the cost does not change with tau: nothing to estimate from
};

/// Searches tau. `make_model` gives a fresh model for each fit; `pairs` are the collected
/// pairs (their encoder samples are replaced per tau); `history` all decoded encoder samples.
/// Throws std::invalid_argument for an empty search range or too few pairs at every tau.
TimeOffsetResult estimateTimeOffset(const std::vector<MotionPair>& pairs,
                                    const std::vector<EncoderSample>& history,
                                    const std::function<std::unique_ptr<MotionModel>()>& make_model,
                                    const TimeOffsetOptions& options);

/// What rewindowPairs does with a pair whose window at the new offset the history does not
/// cover (at its ends).
enum class UncoveredPairs
{
  kLeftOut,     ///< left out (a search comparing offsets on the pairs each covers)
  kKeptAsMade,  ///< kept with the window it was made with (a fit that loses no pair)
};

/// The pairs with their encoder windows cut at offset `tau_s`, end values taken as
/// `interpolation` says; pairs the history does not cover as `uncovered` says.
std::vector<MotionPair> rewindowPairs(
    const std::vector<MotionPair>& pairs, const std::vector<EncoderSample>& history, double tau_s,
    EncoderInterpolation interpolation = EncoderInterpolation::kCubic,
    UncoveredPairs uncovered = UncoveredPairs::kLeftOut);

}  // namespace odometry_calibration
