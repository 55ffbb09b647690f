#include "odometry_calibration/calibration/gyro_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <memory>
#include <stdexcept>

#include <yaml-cpp/yaml.h>
#include <Eigen/Cholesky>
#include <Eigen/Geometry>

#include "odometry_calibration/data/encoder_track.h"

namespace odometry_calibration {

double gyroYawRate(const Eigen::Vector3d& angular_velocity_imu, double roll_rad, double pitch_rad)
{
  const Eigen::Matrix3d R_base_imu = (Eigen::AngleAxisd(pitch_rad, Eigen::Vector3d::UnitY()) *
                                      Eigen::AngleAxisd(roll_rad, Eigen::Vector3d::UnitX()))
                                         .toRotationMatrix();
  return R_base_imu.row(2).dot(angular_velocity_imu);
}

GyroTrack integrateGyro(const std::vector<GyroSample>& samples, double max_gap_s)
{
  GyroTrack track;
  const GyroSample* previous = nullptr;
  double heading_rad = 0.0;
  for (const GyroSample& sample : samples) {
    if (!std::isfinite(sample.stamp_s) || !std::isfinite(sample.yaw_rate_rad_s) ||
        (previous != nullptr && !(sample.stamp_s > previous->stamp_s)))
      continue;
    if (previous != nullptr) {
      const double dt_s = sample.stamp_s - previous->stamp_s;
      if (dt_s > max_gap_s)
        track.gaps.emplace_back(previous->stamp_s, sample.stamp_s);
      // Trapezoid rule: exact for a rate linear between two readings.
      heading_rad += 0.5 * (previous->yaw_rate_rad_s + sample.yaw_rate_rad_s) * dt_s;
    }
    EncoderSample point;
    point.stamp_s = sample.stamp_s;
    point.values = Eigen::VectorXd::Constant(1, heading_rad);
    track.heading.push_back(std::move(point));
    previous = &sample;
  }
  return track;
}

namespace {

/// The gyro's heading change and the window's duration over a cut window.
Eigen::Vector2d windowRegressors(const std::vector<EncoderSample>& window)
{
  return {window.back().values(0) - window.front().values(0),
          window.back().stamp_s - window.front().stamp_s};
}

/// dtheta = a dg + c dt (gyro_fit.h), fitted by weighted least squares (weights 1 / the pairs'
/// rotation variance), the pairs beyond 5 robust sigmas of the first pass left out of the second.
class GyroRotationModel : public MotionModel
{
public:
  std::string name() const override { return "gyro"; }

  ModelReport fit(const std::vector<MotionPair>& pairs) override
  {
    used_.assign(pairs.size(), true);
    solve(pairs);
    std::vector<double> magnitudes;
    for (std::size_t k = 0; k < pairs.size(); ++k)
      magnitudes.push_back(std::abs(residual(pairs[k])) / std::sqrt(variance(pairs[k])));
    std::vector<double> sorted = magnitudes;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    const double robust_sigma = 1.4826 * sorted[sorted.size() / 2];
    for (std::size_t k = 0; k < pairs.size(); ++k)
      used_[k] = magnitudes[k] <= 5.0 * robust_sigma;
    solve(pairs);
    ModelReport report;
    report.model = name();
    report.pairs_used = pairs.size();
    return report;
  }

  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override
  {
    MotionPrediction prediction;
    prediction.mean = Pose2(0.0, 0.0, coefficients_.dot(windowRegressors(samples)));
    return prediction;
  }

  std::string toYaml() const override { return ""; }

  const Eigen::Vector2d& coefficients() const { return coefficients_; }
  const Eigen::Matrix2d& covariance() const { return covariance_; }
  std::size_t used() const
  {
    return static_cast<std::size_t>(std::count(used_.begin(), used_.end(), true));
  }
  double rms() const { return rms_; }

private:
  static double variance(const MotionPair& pair) { return std::max(pair.covariance(2, 2), 1e-12); }

  double residual(const MotionPair& pair) const
  {
    return pair.sensor_motion.theta() - coefficients_.dot(windowRegressors(pair.encoder_samples));
  }

  /// The normal equations over the used pairs; the covariance scaled by chi^2 / dof.
  void solve(const std::vector<MotionPair>& pairs)
  {
    Eigen::Matrix2d normal = Eigen::Matrix2d::Zero();
    Eigen::Vector2d right = Eigen::Vector2d::Zero();
    std::size_t count = 0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (!used_[k])
        continue;
      const Eigen::Vector2d x = windowRegressors(pairs[k].encoder_samples);
      const double weight = 1.0 / variance(pairs[k]);
      normal += weight * x * x.transpose();
      right += weight * x * pairs[k].sensor_motion.theta();
      ++count;
    }
    if (count < 3 || std::abs(normal.determinant()) <= 0.0)
      throw std::invalid_argument("gyro fit: " + std::to_string(count) +
                                  " pairs, or none that turn: scale and bias not determined");
    coefficients_ = normal.ldlt().solve(right);
    double chi2 = 0.0, squares = 0.0;
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      if (!used_[k])
        continue;
      const double r = residual(pairs[k]);
      chi2 += r * r / variance(pairs[k]);
      squares += r * r;
    }
    const double dof = static_cast<double>(count) - 2.0;
    covariance_ = normal.inverse() * std::max(chi2 / dof, 1e-12);
    rms_ = std::sqrt(squares / static_cast<double>(count));
  }

  std::vector<bool> used_;
  Eigen::Vector2d coefficients_ = Eigen::Vector2d(1.0, 0.0);
  Eigen::Matrix2d covariance_ = Eigen::Matrix2d::Zero();
  double rms_ = 0.0;
};

/// The pairs as rotation-only samples (their rotation and its variance; x and y zero), those
/// whose searched windows [start + min, end + max] lie inside the readings and span no gap.
std::vector<MotionPair> rotationPairs(const std::vector<MotionPair>& pairs, const GyroTrack& track,
                                      const GyroFitOptions& options)
{
  std::vector<MotionPair> rotations;
  if (track.heading.size() < 2)
    return rotations;
  for (const MotionPair& pair : pairs) {
    const double from_s = pair.start_stamp_s + options.search_min_s;
    const double to_s = pair.end_stamp_s + options.search_max_s;
    const double variance = pair.covariance(2, 2);
    if (from_s < track.heading.front().stamp_s || to_s > track.heading.back().stamp_s ||
        !(pair.end_stamp_s > pair.start_stamp_s) || !std::isfinite(pair.sensor_motion.theta()) ||
        !std::isfinite(variance) || !(variance > 0.0))
      continue;
    const bool spans_gap = std::any_of(track.gaps.begin(), track.gaps.end(), [&](const auto& gap) {
      return gap.second > from_s && gap.first < to_s;
    });
    if (spans_gap)
      continue;
    MotionPair rotation;
    rotation.start_stamp_s = pair.start_stamp_s;
    rotation.end_stamp_s = pair.end_stamp_s;
    rotation.sensor_motion = Pose2(0.0, 0.0, pair.sensor_motion.theta());
    rotation.covariance = Eigen::Matrix3d::Identity();
    rotation.covariance(2, 2) = variance;
    rotations.push_back(std::move(rotation));
  }
  return rotations;
}

/// The fine search's window: around the coarse peak, inside the configured range.
TimeOffsetOptions fineWindow(const GyroFitOptions& options, double centre_s)
{
  TimeOffsetOptions fine;
  fine.min_s = std::max(options.search_min_s, centre_s - options.fine_half_width_s);
  fine.max_s = std::min(options.search_max_s, centre_s + options.fine_half_width_s);
  fine.step_s = options.fine_step_s;
  fine.trim = 0.0;
  fine.huber_threshold = 0.0;
  return fine;
}

/// scale = 1 / a, bias = -c / a with their σ by first-order propagation of cov(a, c).
void scaleAndBias(const GyroRotationModel& model, GyroFit* fit)
{
  const double a = model.coefficients()(0), c = model.coefficients()(1);
  Eigen::Matrix2d jacobian;
  jacobian << -1.0 / (a * a), 0.0, c / (a * a), -1.0 / a;
  const Eigen::Matrix2d covariance = jacobian * model.covariance() * jacobian.transpose();
  fit->scale.initial = 1.0;
  fit->scale.value = 1.0 / a;
  fit->scale.sigma = std::sqrt(covariance(0, 0));
  fit->bias.value = -c / a;
  fit->bias.sigma = std::sqrt(covariance(1, 1));
}

}  // namespace

GyroFit fitGyro(const std::vector<MotionPair>& pairs, double pairs_time_offset_s,
                const std::vector<GyroSample>& samples, const GyroFitOptions& options)
{
  if (!(options.search_max_s > options.search_min_s) || !(options.fine_step_s > 0.0))
    throw std::invalid_argument("gyro fit: need search_min_s < search_max_s and fine_step_s > 0");
  GyroFit fit;
  const GyroTrack track = integrateGyro(samples, options.max_gap_s);
  const std::vector<MotionPair> rotations = rotationPairs(pairs, track, options);
  char text[300];
  if (rotations.size() < options.min_pairs) {
    std::snprintf(text, sizeof(text),
                  "%zu of %zu pairs lie inside the gyro's %zu readings (searched %.3g to %.3g s) "
                  "without a gap over %.3g s, %zu needed",
                  rotations.size(), pairs.size(), samples.size(), options.search_min_s,
                  options.search_max_s, options.max_gap_s, options.min_pairs);
    fit.problem = text;
    return fit;
  }
  CoarseTimeOffsetOptions coarse;
  coarse.min_s = options.search_min_s;
  coarse.max_s = options.search_max_s;
  const MotionPredictor gyro_heading = [](const std::vector<EncoderSample>& window) {
    return Pose2(0.0, 0.0, windowRegressors(window)(0));
  };
  fit.coarse = coarseTimeOffset(rotations, track.heading, gyro_heading, coarse);
  if (!fit.coarse->found) {
    fit.problem = "coarse time offset: " + fit.coarse->problem;
    return fit;
  }
  fit.fine = estimateTimeOffset(
      rotations, track.heading, [] { return std::make_unique<GyroRotationModel>(); },
      fineWindow(options, fit.coarse->offset_s));
  fit.shift_s = fit.fine.offset_s;
  GyroRotationModel model;
  const std::vector<MotionPair> at_shift = rewindowPairs(rotations, track.heading, fit.shift_s);
  model.fit(at_shift);
  scaleAndBias(model, &fit);
  fit.time_offset.value = pairs_time_offset_s - fit.shift_s;
  fit.time_offset.sigma = fit.fine.sigma_s;
  fit.pairs = model.used();
  fit.residual_rms_rad = model.rms();
  fit.fitted = true;
  return fit;
}

std::string gyroFitText(const GyroFit& fit)
{
  if (!fit.fitted)
    return "gyro: not fitted: " + fit.problem;
  char text[400];
  std::snprintf(text, sizeof(text),
                "gyro: scale %.6f ± %.2g, bias %.3e ± %.2g rad/s, time offset %.5f ± %.2g s "
                "(%zu pairs, rotation residual %.3g rad rms)",
                fit.scale.value, fit.scale.sigma, fit.bias.value, fit.bias.sigma,
                fit.time_offset.value, fit.time_offset.sigma, fit.pairs, fit.residual_rms_rad);
  return text;
}

std::string gyroResultYaml(const GyroFit& fit, const std::string& topic)
{
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap << YAML::Key << "gyro" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "topic" << YAML::Value << topic;
  out << YAML::Key << "fitted" << YAML::Value << fit.fitted;
  if (!fit.fitted) {
    out << YAML::Key << "problem" << YAML::Value << fit.problem;
  } else {
    const std::pair<const char*, const ParameterEstimate*> values[] = {
        {"scale", &fit.scale}, {"bias_rad_s", &fit.bias}, {"time_offset_s", &fit.time_offset}};
    for (const auto& [key, estimate] : values) {
      out << YAML::Key << key << YAML::Value << estimate->value;
      out << YAML::Key << (std::string(key) + "_sigma") << YAML::Value << estimate->sigma;
    }
    out << YAML::Key << "pairs" << YAML::Value << fit.pairs;
    out << YAML::Key << "rotation_residual_rms_rad" << YAML::Value << fit.residual_rms_rad;
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

}  // namespace odometry_calibration
