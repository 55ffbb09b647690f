#include "odometry_calibration/calibration/time_offset.h"

#include "odometry_calibration/data/encoder_track.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Cholesky>

namespace odometry_calibration {

std::vector<MotionPair> rewindowPairs(const std::vector<MotionPair>& pairs,
                                      const std::vector<EncoderSample>& history, double tau_s,
                                      EncoderInterpolation interpolation, UncoveredPairs uncovered)
{
  std::vector<MotionPair> result;
  result.reserve(pairs.size());
  for (const MotionPair& pair : pairs) {
    MotionPair moved = pair;
    moved.encoder_samples = cutEncoderWindow(history, pair.start_stamp_s + tau_s,
                                             pair.end_stamp_s + tau_s, interpolation);
    if (moved.encoder_samples.size() >= 2)
      result.push_back(std::move(moved));
    else if (uncovered == UncoveredPairs::kKeptAsMade)
      result.push_back(pair);
  }
  return result;
}

namespace {

/// Huber's loss of a squared whitened error r^2 with threshold k: r^2 up to k, 2 k r - k^2
/// beyond (k = 0: r^2) [-].
double huberLoss(double squared_error, double k)
{
  if (k <= 0.0 || squared_error <= k * k)
    return squared_error;
  return 2.0 * k * std::sqrt(squared_error) - k * k;
}

/// Trimmed mean of the Huber losses (huberLoss) of the squared whitened prediction errors of a
/// model fitted to `pairs`.
double robustCost(const std::vector<MotionPair>& pairs, MotionModel& model, double trim,
                  double huber_threshold)
{
  model.fit(pairs);
  std::vector<double> errors;
  errors.reserve(pairs.size());
  for (const MotionPair& pair : pairs) {
    const Eigen::Vector3d e =
        boxMinus(model.predict(pair.encoder_samples).mean, pair.sensor_motion);
    errors.push_back(huberLoss(e.dot(pair.covariance.ldlt().solve(e)), huber_threshold));
  }
  std::sort(errors.begin(), errors.end());
  const std::size_t kept = std::max<std::size_t>(
      1, static_cast<std::size_t>(std::floor((1.0 - trim) * static_cast<double>(errors.size()))));
  double sum = 0.0;
  for (std::size_t i = 0; i < kept; ++i)
    sum += errors[i];
  return sum / static_cast<double>(kept);
}

}  // namespace

TimeOffsetResult estimateTimeOffset(const std::vector<MotionPair>& pairs,
                                    const std::vector<EncoderSample>& history,
                                    const std::function<std::unique_ptr<MotionModel>()>& make_model,
                                    const TimeOffsetOptions& options)
{
  if (!(options.max_s > options.min_s) || !(options.step_s > 0.0) || options.trim < 0.0 ||
      options.trim >= 1.0 || !(options.huber_threshold >= 0.0)) {
    throw std::invalid_argument(
        "time offset search: need min_s < max_s, step_s > 0, "
        "0 <= trim < 1, huber_threshold >= 0");
  }
  TimeOffsetResult result;
  const int steps = static_cast<int>(std::round((options.max_s - options.min_s) / options.step_s));
  std::size_t best = 0;
  for (int i = 0; i <= steps; ++i) {
    const double tau = options.min_s + i * options.step_s;
    const std::vector<MotionPair> moved = rewindowPairs(pairs, history, tau, options.interpolation);
    double cost = std::numeric_limits<double>::infinity();
    try {
      auto model = make_model();
      cost = robustCost(moved, *model, options.trim, options.huber_threshold);
    } catch (const std::invalid_argument& error) {
      // Too few pairs covered at this offset: leave it out of the curve's minimum.
      if (moved.size() >= pairs.size() / 2)
        throw;  // not a coverage problem: report it
    }
    result.curve.emplace_back(tau, cost);
    if (cost < result.curve[best].second)
      best = result.curve.size() - 1;
  }
  if (!std::isfinite(result.curve[best].second)) {
    throw std::invalid_argument("time offset search: no offset in the range gave enough pairs");
  }
  double highest = result.curve[best].second;
  for (const auto& point : result.curve) {
    if (std::isfinite(point.second))
      highest = std::max(highest, point.second);
  }
  result.flat = highest - result.curve[best].second <=
                1e-6 * std::max(1e-12, std::abs(result.curve[best].second));
  result.offset_s = result.curve[best].first;
  result.sigma_s = std::numeric_limits<double>::quiet_NaN();
  result.at_boundary = best == 0 || best + 1 == result.curve.size();
  if (!result.at_boundary) {
    // Parabola through the minimum and its neighbours: vertex and curvature.
    const double h = options.step_s;
    const double c_minus = result.curve[best - 1].second, c0 = result.curve[best].second,
                 c_plus = result.curve[best + 1].second;
    const double curvature = (c_plus - 2.0 * c0 + c_minus) / (h * h);
    if (std::isfinite(curvature) && curvature > 0.0) {
      result.offset_s += -0.5 * h * (c_plus - c_minus) / (c_plus - 2.0 * c0 + c_minus);
      // The cost is a mean of squared whitened errors over n pairs (Huber's loss is that near
      // the minimum for all but a few): the total chi^2 is n times
      // it, and sigma^2 = 2 / (d^2 chi^2 / d tau^2), scaled by the cost level (chi^2/dof).
      const double n = static_cast<double>(pairs.size());
      result.sigma_s = std::sqrt(2.0 * std::max(c0, 1e-12) / (n * curvature));
    }
  }
  return result;
}

}  // namespace odometry_calibration
