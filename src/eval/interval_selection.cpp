#include "odometry_calibration/eval/interval_selection.h"

#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/data/reference_pairs.h"
#include "odometry_calibration/eval/metrics.h"

namespace odometry_calibration {

namespace {

/// ATE dead-reckoned through `block` by a fit to the pairs that do not touch it (even by one
/// shared sample, which would let the fit see the block's first reference pose); infinity when
/// that fit is impossible (too few pairs) or did not converge.
double blockAte(const std::vector<EncoderSample>& samples, const std::vector<Pose2>& T_world_sensor,
                const std::vector<MotionPair>& pairs, const SampleBlock& block,
                const TricycleEncoderLayout& layout, const TricycleParameters& initial,
                const TricycleCalibrationOptions& calibration)
{
  const double block_start_s = samples[block.first].stamp_s;
  const double block_end_s = samples[block.last].stamp_s;
  std::vector<MotionPair> training;
  for (const MotionPair& pair : pairs) {
    if (pair.end_stamp_s < block_start_s || pair.start_stamp_s > block_end_s) {
      training.push_back(pair);
    }
  }
  constexpr double kUnusable = std::numeric_limits<double>::infinity();
  try {
    const TricycleCalibrationResult fit = calibrateTricycle(training, layout, initial, calibration);
    if (!fit.converged) {
      return kUnusable;
    }
    const auto begin = static_cast<std::ptrdiff_t>(block.first);
    const auto end = static_cast<std::ptrdiff_t>(block.last) + 1;
    const std::vector<EncoderSample> block_samples(samples.begin() + begin, samples.begin() + end);
    const std::vector<Pose2> reference(T_world_sensor.begin() + begin,
                                       T_world_sensor.begin() + end);
    const double ate = absoluteTrajectoryError(
        tricycleSensorTrajectory(fit.calibrated, layout, block_samples, reference.front()),
        reference);
    return std::isfinite(ate) ? ate : kUnusable;
  } catch (const std::invalid_argument&) {
    return kUnusable;
  }
}

}  // namespace

void validate(const IntervalSelectionOptions& options)
{
  if (options.candidates_s.empty()) {
    throw std::invalid_argument("interval selection: no candidate interval");
  }
  for (std::size_t i = 0; i < options.candidates_s.size(); ++i) {
    const double t = options.candidates_s[i];
    if (!(t > 0.0) || !std::isfinite(t) || (i > 0 && !(t > options.candidates_s[i - 1]))) {
      throw std::invalid_argument(
          "interval selection: candidate intervals must be increasing numbers > 0 s");
    }
  }
  if (options.fold_counts.empty()) {
    throw std::invalid_argument("interval selection: no fold count");
  }
  for (std::size_t folds : options.fold_counts) {
    if (folds < 2) {
      throw std::invalid_argument("interval selection: at least 2 folds are needed");
    }
  }
}

IntervalChoice chooseTricycleInterval(const std::vector<EncoderSample>& samples,
                                      const std::vector<Pose2>& T_world_sensor,
                                      const TricycleEncoderLayout& layout,
                                      const TricycleParameters& initial,
                                      const TricycleCalibrationOptions& calibration,
                                      const Eigen::Matrix3d& covariance,
                                      const IntervalSelectionOptions& options)
{
  validate(options);
  if (samples.size() != T_world_sensor.size()) {
    throw std::invalid_argument("interval selection: one reference pose per sample expected");
  }
  std::vector<double> stamps_s;
  stamps_s.reserve(samples.size());
  for (const EncoderSample& sample : samples) {
    stamps_s.push_back(sample.stamp_s);
  }
  std::vector<std::vector<SampleBlock>> partitions;
  for (std::size_t folds : options.fold_counts) {
    partitions.push_back(timeBlocks(stamps_s, folds));
  }
  IntervalChoice choice;
  double best = std::numeric_limits<double>::infinity();
  for (double interval_s : options.candidates_s) {
    const std::vector<MotionPair> pairs =
        referencePairs(samples, T_world_sensor, interval_s, covariance, options.stride_s);
    IntervalScore score;
    score.interval_s = interval_s;
    score.pairs = pairs.size();
    double sum_of_rms = 0.0;
    for (const std::vector<SampleBlock>& blocks : partitions) {
      double sum_squares = 0.0;
      for (const SampleBlock& block : blocks) {
        const double ate =
            blockAte(samples, T_world_sensor, pairs, block, layout, initial, calibration);
        sum_squares += ate * ate;
      }
      sum_of_rms += std::sqrt(sum_squares / static_cast<double>(blocks.size()));
    }
    score.validation_ate_m = sum_of_rms / static_cast<double>(partitions.size());
    if (score.validation_ate_m < best) {
      best = score.validation_ate_m;
      choice.interval_s = interval_s;
    }
    choice.curve.push_back(score);
  }
  if (!std::isfinite(best)) {
    throw std::invalid_argument(
        "interval selection: no candidate interval leaves enough pairs in every fold; record a "
        "longer drive or set the interval by hand");
  }
  return choice;
}

}  // namespace odometry_calibration
