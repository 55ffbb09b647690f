// The coarse, global search of the time offset tau between the encoder and the sensor clocks:
// the sensor's heading change over each pair against the encoders' heading change over the
// same interval shifted by tau, as the nominal robot predicts it. Rotation does not depend on
// where the sensor sits and barely on the nominal geometry (a wrong separation scales every
// predicted turn alike), so the normalised correlation of the two heading-change series peaks
// at the true tau whatever the robot's parameters; the fine search (time_offset.h) then refits
// the model near that peak only.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/data/encoder_track.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/pairing/pair_collector.h"

namespace odometry_calibration {

struct CoarseTimeOffsetOptions
{
  double min_s = -2.0;   ///< search range start [s]
  double max_s = 2.0;    ///< search range end [s]
  double step_s = 0.02;  ///< grid step [s]
  EncoderInterpolation interpolation = EncoderInterpolation::kCubic;
};

struct CoarseTimeOffset
{
  bool found = false;        ///< false: `problem` says why
  double offset_s = 0.0;     ///< tau at the highest correlation [s]
  double correlation = 0.0;  ///< there: sum(a b) / sqrt(sum(a^2) sum(b^2)) [-]
  bool at_boundary = false;  ///< the peak lies on the search range's edge
  std::size_t pairs = 0;     ///< pairs covered by the encoders at every tau of the range
  std::string problem;
};

/// Searches tau on the grid of `options`: a = each pair's sensor heading change, b(tau) = the
/// heading change `predict` gives over the encoder samples of [start + tau, end + tau] cut from
/// `history`, over the pairs the history covers at every tau; the peak of
/// rho(tau) = sum(a b) / sqrt(sum(a^2) sum(b^2)) (eq. of the uncentred correlation; a robot
/// that never turns gives nothing: not found). Throws std::invalid_argument for an empty range.
CoarseTimeOffset coarseTimeOffset(const std::vector<MotionPair>& pairs,
                                  const std::vector<EncoderSample>& history,
                                  const MotionPredictor& predict,
                                  const CoarseTimeOffsetOptions& options);

}  // namespace odometry_calibration
