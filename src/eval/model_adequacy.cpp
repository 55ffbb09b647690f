#include "odometry_calibration/eval/model_adequacy.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace odometry_calibration {
namespace {

/// A relative residual and the motion feature it is tested against.
struct Sample
{
  double feature = 0.0;
  double error = 0.0;
};

/// A relative error is clipped to this magnitude: a bad scan match (an error of any size) moves
/// a trend no more than a pair the model misses by half.
constexpr double kMaxRelativeError = 0.5;

double clipped(double relative_error)
{
  return std::clamp(relative_error, -kMaxRelativeError, kMaxRelativeError);
}

double quantile(std::vector<double> values, double q)
{
  std::sort(values.begin(), values.end());
  return values[static_cast<std::size_t>(q * static_cast<double>(values.size() - 1))];
}

/// The least-squares line of error on feature: its change between the 10th and the 90th
/// percentile of the feature, and the slope's t.
ResidualTrend lineTrend(const std::string& feature, const std::vector<Sample>& samples)
{
  ResidualTrend trend;
  trend.feature = feature;
  const double n = static_cast<double>(samples.size());
  double mean_x = 0.0, mean_y = 0.0;
  std::vector<double> features;
  for (const Sample& s : samples) {
    mean_x += s.feature / n;
    mean_y += s.error / n;
    features.push_back(s.feature);
  }
  double sxx = 0.0, sxy = 0.0;
  for (const Sample& s : samples) {
    sxx += (s.feature - mean_x) * (s.feature - mean_x);
    sxy += (s.feature - mean_x) * (s.error - mean_y);
  }
  if (!(sxx > 0.0))
    return trend;
  const double slope = sxy / sxx;
  double rss = 0.0;
  for (const Sample& s : samples) {
    const double r = s.error - mean_y - slope * (s.feature - mean_x);
    rss += r * r;
  }
  const double slope_sigma = std::sqrt(rss / std::max(n - 2.0, 1.0) / sxx);
  trend.from = quantile(features, 0.1);
  trend.to = quantile(features, 0.9);
  trend.size = slope * (trend.to - trend.from);
  trend.t_statistic = slope_sigma > 0.0 ? slope / slope_sigma : 0.0;
  return trend;
}

/// The mean error on left turns (feature > 0) minus that on right turns, Welch's t.
ResidualTrend directionTrend(const std::vector<Sample>& samples, std::size_t min_pairs)
{
  ResidualTrend trend;
  trend.feature = "turning direction";
  double sum[2] = {0, 0}, sum2[2] = {0, 0}, count[2] = {0, 0};
  for (const Sample& s : samples) {
    const int side = s.feature > 0.0 ? 0 : 1;
    sum[side] += s.error;
    sum2[side] += s.error * s.error;
    count[side] += 1.0;
  }
  if (count[0] < static_cast<double>(min_pairs) / 2 ||
      count[1] < static_cast<double>(min_pairs) / 2)
    return trend;
  double mean[2], variance[2];
  for (int k = 0; k < 2; ++k) {
    mean[k] = sum[k] / count[k];
    variance[k] = std::max(sum2[k] / count[k] - mean[k] * mean[k], 0.0) * count[k] /
                  std::max(count[k] - 1.0, 1.0);
  }
  trend.size = mean[0] - mean[1];
  const double sigma = std::sqrt(variance[0] / count[0] + variance[1] / count[1]);
  trend.t_statistic = sigma > 0.0 ? trend.size / sigma : 0.0;
  return trend;
}

void describe(ResidualTrend* trend)
{
  char text[300];
  if (trend->feature == "turning direction") {
    std::snprintf(text, sizeof(text),
                  "its heading error on left turns differs from right turns by %+.1f %% of the "
                  "turn (t = %.1f)",
                  100.0 * trend->size, trend->t_statistic);
  } else if (trend->feature == "curvature") {
    std::snprintf(text, sizeof(text),
                  "its heading error trends with curvature: %+.1f %% of the turn from gentle "
                  "curves (|curvature| %.2f 1/m) to tight turns (%.2f 1/m) (t = %.1f)",
                  100.0 * trend->size, trend->from, trend->to, trend->t_statistic);
  } else {
    std::snprintf(text, sizeof(text),
                  "its distance error trends with speed: %+.1f %% of the distance from %.2f m/s "
                  "to %.2f m/s (t = %.1f)",
                  100.0 * trend->size, trend->from, trend->to, trend->t_statistic);
  }
  trend->text = text;
}

/// The check in words: not tested, fits (with the trends' numbers), or the significant trends.
std::string checkText(const std::string& model, const AdequacyCheck& check)
{
  if (check.trends.empty())
    return "adequacy: not tested (too few turning or moving pairs)\n";
  if (check.fits) {
    std::string text = "adequacy: " + model +
                       " fits this robot: no trend of its residuals with curvature, speed or "
                       "turning direction (";
    char numbers[120];
    for (std::size_t k = 0; k < check.trends.size(); ++k) {
      std::snprintf(numbers, sizeof(numbers), "%s%s %+.1f %%, t = %.1f", k == 0 ? "" : "; ",
                    check.trends[k].feature.c_str(), 100.0 * check.trends[k].size,
                    check.trends[k].t_statistic);
      text += numbers;
    }
    return text + ")\n";
  }
  std::string text = "adequacy: the model does not fit this robot (" + model + ")";
  for (const ResidualTrend& trend : check.trends) {
    if (trend.significant)
      text += "; " + trend.text;
  }
  return text + "\n";
}

}  // namespace

AdequacyCheck checkModelAdequacy(const MotionModel& model, const std::vector<MotionPair>& pairs,
                                 const AdequacyOptions& options)
{
  std::vector<Sample> curvature, speed, direction;
  for (const MotionPair& pair : pairs) {
    const Pose2 predicted = model.predict(pair.encoder_samples).mean;
    const Pose2& measured = pair.sensor_motion;
    const double turn = measured.theta();
    const double distance = std::hypot(measured.x(), measured.y());
    const double duration = pair.end_stamp_s - pair.start_stamp_s;
    if (std::abs(turn) >= options.min_turn_rad) {
      const double error = clipped(normalizeAngle(predicted.theta() - turn) / turn);
      const double kappa =
          std::min(std::abs(turn) / std::max(distance, 1e-9), options.max_curvature_per_m);
      curvature.push_back({kappa, error});
      direction.push_back({turn, error});
    }
    if (distance >= options.min_distance_m && duration > 0.0) {
      const double error =
          clipped((std::hypot(predicted.x(), predicted.y()) - distance) / distance);
      speed.push_back({distance / duration, error});
    }
  }
  AdequacyCheck check;
  auto test = [&](ResidualTrend trend, std::size_t used) {
    if (used < options.min_pairs)
      return;
    trend.significant = std::abs(trend.t_statistic) > options.min_abs_t &&
                        std::abs(trend.size) > options.min_relative_size;
    describe(&trend);
    check.fits = check.fits && !trend.significant;
    check.trends.push_back(trend);
  };
  test(lineTrend("curvature", curvature), curvature.size());
  test(lineTrend("speed", speed), speed.size());
  test(directionTrend(direction, options.min_pairs), direction.size());
  check.text = checkText(model.name(), check);
  return check;
}

std::string adequacyAdvice(const AdequacyCheck& check, const std::string& model,
                           const std::vector<ModelScore>& scores, const std::string& where)
{
  if (check.fits)
    return "";
  const std::vector<std::string> ranking = rankByAte(scores);
  if (ranking.empty()) {
    return "adequacy: hold out pairs (calibrate_bag --holdout 0.3, or --test BAG) to see which "
           "model generalizes better on this robot\n";
  }
  if (ranking.front() == model || ranking.front() == "nominal")
    return "adequacy: no compared model does better than " + ranking.front() + " on " + where +
           "\n";
  const auto best = std::find_if(scores.begin(), scores.end(),
                                 [&](const ModelScore& s) { return s.model == ranking.front(); });
  const auto own = std::find_if(scores.begin(), scores.end(),
                                [&](const ModelScore& s) { return s.model == model; });
  char text[300];
  std::snprintf(text, sizeof(text), "adequacy: recommended: %s, the best on %s (ATE %.4f m",
                best->model.c_str(), where.c_str(), best->ate_m);
  std::string advice = text;
  if (own != scores.end()) {
    std::snprintf(text, sizeof(text), " against %s's %.4f m", model.c_str(), own->ate_m);
    advice += text;
  }
  return advice + ")\n";
}

}  // namespace odometry_calibration
