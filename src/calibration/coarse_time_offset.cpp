#include "odometry_calibration/calibration/coarse_time_offset.h"

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// Fewer pairs than this, or a root-mean-square heading change below this, find nothing.
constexpr std::size_t kMinPairs = 10;
constexpr double kMinRmsTurnRad = 0.005;
/// A peak correlation below this is no evidence of a shift.
constexpr double kMinCorrelation = 0.5;

/// The pairs whose shifted intervals the history covers over the whole range.
std::vector<const MotionPair*> coveredPairs(const std::vector<MotionPair>& pairs,
                                            const std::vector<EncoderSample>& history,
                                            const CoarseTimeOffsetOptions& options)
{
  std::vector<const MotionPair*> covered;
  if (history.size() < 2)
    return covered;
  for (const MotionPair& pair : pairs) {
    if (pair.start_stamp_s + options.min_s >= history.front().stamp_s &&
        pair.end_stamp_s + options.max_s <= history.back().stamp_s &&
        pair.end_stamp_s > pair.start_stamp_s)
      covered.push_back(&pair);
  }
  return covered;
}

/// rho(tau) over `covered`, with the sensor's heading changes `a` and their sum of squares.
double correlationAt(double tau_s, const std::vector<const MotionPair*>& covered,
                     const std::vector<double>& a, double aa,
                     const std::vector<EncoderSample>& history, const MotionPredictor& predict,
                     EncoderInterpolation interpolation)
{
  double ab = 0.0, bb = 0.0;
  for (std::size_t k = 0; k < covered.size(); ++k) {
    const std::vector<EncoderSample> window = cutEncoderWindow(
        history, covered[k]->start_stamp_s + tau_s, covered[k]->end_stamp_s + tau_s, interpolation);
    if (window.size() < 2)
      continue;
    const double b = predict(window).theta();
    if (!std::isfinite(b))
      continue;
    ab += a[k] * b;
    bb += b * b;
  }
  return bb > 0.0 ? ab / std::sqrt(aa * bb) : 0.0;
}

}  // namespace

CoarseTimeOffset coarseTimeOffset(const std::vector<MotionPair>& pairs,
                                  const std::vector<EncoderSample>& history,
                                  const MotionPredictor& predict,
                                  const CoarseTimeOffsetOptions& options)
{
  if (!(options.max_s > options.min_s) || !(options.step_s > 0.0) || !predict)
    throw std::invalid_argument(
        "coarse time offset search: need min_s < max_s, step_s > 0 and "
        "a nominal model");
  CoarseTimeOffset result;
  const std::vector<const MotionPair*> covered = coveredPairs(pairs, history, options);
  result.pairs = covered.size();
  std::vector<double> a;
  double aa = 0.0;
  for (const MotionPair* pair : covered) {
    a.push_back(pair->sensor_motion.theta());
    aa += a.back() * a.back();
  }
  char text[300];
  if (covered.size() < kMinPairs) {
    std::snprintf(text, sizeof(text),
                  "%zu pairs lie %.3g s inside the encoder readings, %zu needed", covered.size(),
                  std::max(-options.min_s, options.max_s), kMinPairs);
    result.problem = text;
    return result;
  }
  const double rms_turn_rad = std::sqrt(aa / static_cast<double>(covered.size()));
  if (rms_turn_rad < kMinRmsTurnRad) {
    std::snprintf(text, sizeof(text),
                  "the robot barely turns (%.2g rad per pair, root mean square): heading changes "
                  "carry no timing",
                  rms_turn_rad);
    result.problem = text;
    return result;
  }
  const int steps = static_cast<int>(std::round((options.max_s - options.min_s) / options.step_s));
  int best = -1;
  for (int i = 0; i <= steps; ++i) {
    const double tau_s = options.min_s + i * options.step_s;
    const double rho =
        correlationAt(tau_s, covered, a, aa, history, predict, options.interpolation);
    if (best < 0 || rho > result.correlation) {
      best = i;
      result.correlation = rho;
      result.offset_s = tau_s;
    }
  }
  result.at_boundary = best == 0 || best == steps;
  result.found = result.correlation >= kMinCorrelation;
  if (!result.found) {
    std::snprintf(text, sizeof(text),
                  "the heading changes of the sensor and the encoders correlate at most %.2f "
                  "(at %.3f s), below %.2f",
                  result.correlation, result.offset_s, kMinCorrelation);
    result.problem = text;
  }
  return result;
}

}  // namespace odometry_calibration
