#include "odometry_calibration/models/linear_model.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>

#include <Eigen/Cholesky>
#include <Eigen/QR>

#include "odometry_calibration/common/median.h"
#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/models/model_yaml.h"

namespace odometry_calibration {

void validate(const LinearModelOptions& o)
{
  if (o.joints.kinds.empty() || o.joints.kinds.size() != o.joints.names.size()) {
    throw std::invalid_argument("linear model: 'joints' needs one kind per joint name");
  }
  if (!(o.huber_threshold > 0.0) || !(o.outlier_threshold > o.huber_threshold)) {
    throw std::invalid_argument(
        "linear model: need huber_threshold > 0 and outlier_threshold > huber_threshold");
  }
  if (o.max_iterations < 1) {
    throw std::invalid_argument("linear model option 'max_iterations' must be >= 1");
  }
}

LinearModel::LinearModel(LinearModelOptions options) : options_(std::move(options))
{
  validate(options_);
  weights_ = Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(options_.joints.kinds.size()));
}

namespace {

/// Robust regression of one output (eq. 9 for one row of W): IRLS with Huber weights on
/// residuals scaled by sigma_j and by a robust (MAD) scale, pairs beyond the outlier threshold
/// dropped. Returns the row, the final scale, and marks outliers and the pairs the Huber weight
/// down-weights (beyond its threshold, not dropped).
Eigen::VectorXd robustRow(const Eigen::MatrixXd& X, const Eigen::VectorXd& y,
                          const Eigen::VectorXd& sigma, const LinearModelOptions& options,
                          std::vector<bool>* outlier, std::vector<bool>* down_weighted,
                          double* scale, int* iterations)
{
  const Eigen::Index n = X.rows();
  Eigen::VectorXd weight = sigma.cwiseInverse().cwiseAbs2();
  Eigen::VectorXd row = Eigen::VectorXd::Zero(X.cols());
  *scale = 1.0;
  for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
    *iterations = std::max(*iterations, iteration + 1);
    const Eigen::MatrixXd XtW = X.transpose() * weight.asDiagonal();
    const Eigen::VectorXd next = (XtW * X).ldlt().solve(XtW * y);
    const Eigen::VectorXd scaled = (y - X * next).cwiseQuotient(sigma);
    std::vector<double> magnitudes(scaled.data(), scaled.data() + n);
    for (double& m : magnitudes)
      m = std::abs(m);
    *scale = std::max(1.4826 * median(magnitudes), 1e-12);
    for (Eigen::Index j = 0; j < n; ++j) {
      const double u = std::abs(scaled(j)) / *scale;
      (*outlier)[static_cast<std::size_t>(j)] = u > options.outlier_threshold;
      (*down_weighted)[static_cast<std::size_t>(j)] =
          u > options.huber_threshold && u <= options.outlier_threshold;
      const double huber = u <= options.huber_threshold ? 1.0 : options.huber_threshold / u;
      weight(j) = (*outlier)[static_cast<std::size_t>(j)] ? 0.0 : huber / (sigma(j) * sigma(j));
    }
    const bool settled = (next - row).norm() <= 1e-12 * std::max(1.0, next.norm());
    row = next;
    if (settled)
      break;
  }
  return row;
}

/// The regression's data, one row per pair: the features (pairFeatures), the sensor motion
/// (x, y, theta) and its standard deviations from the pair's covariance.
struct LinearDesign
{
  Eigen::MatrixXd X;      ///< n x m
  Eigen::MatrixXd Y;      ///< n x 3
  Eigen::MatrixXd sigma;  ///< n x 3
};

/// The design of `pairs`. Throws std::invalid_argument for a pair without positive variances or
/// features that do not vary independently (the weights would not be determined).
LinearDesign linearDesign(const std::vector<MotionPair>& pairs, const JointLayout& joints)
{
  const auto m = static_cast<Eigen::Index>(joints.kinds.size());
  const auto n = static_cast<Eigen::Index>(pairs.size());
  LinearDesign design{Eigen::MatrixXd(n, m), Eigen::MatrixXd(n, 3), Eigen::MatrixXd(n, 3)};
  for (Eigen::Index j = 0; j < n; ++j) {
    const MotionPair& pair = pairs[static_cast<std::size_t>(j)];
    design.X.row(j) = pairFeatures(pair.encoder_samples, joints).transpose();
    design.Y.row(j) = pair.sensor_motion.vector().transpose();
    design.sigma.row(j) = pair.covariance.diagonal().cwiseSqrt().transpose();
    if (!(design.sigma.row(j).minCoeff() > 0.0)) {
      throw std::invalid_argument("pair " + std::to_string(j) +
                                  " has a covariance without positive variances");
    }
  }
  if (Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(design.X).rank() < m) {
    throw std::invalid_argument(
        "linear model: the encoder increments do not vary independently (a joint never moved "
        "or two joints always moved together); drive with every joint moving in both "
        "directions");
  }
  return design;
}

/// Which pairs any axis' fit rejected (beyond the outlier threshold) or down-weighted.
struct LinearPairFlags
{
  std::vector<bool> outlier_any;
  std::vector<bool> down_weighted_any;
};

/// Fits row `axis` of `weights` (robustRow) and returns its covariance, scale^2 (X^T Sigma^-1
/// X)^-1 over the inliers; the inliers' residual variance goes to `residual_variance`, the
/// axis' rejected and down-weighted pairs into `flags`.
Eigen::MatrixXd fitLinearAxis(const LinearDesign& design, int axis,
                              const LinearModelOptions& options, Eigen::MatrixXd* weights,
                              double* residual_variance, LinearPairFlags* flags, int* iterations)
{
  const Eigen::MatrixXd& X = design.X;
  const Eigen::MatrixXd& sigma = design.sigma;
  const Eigen::Index n = X.rows(), m = X.cols();
  const auto count_n = static_cast<std::size_t>(n);
  std::vector<bool> outlier(count_n, false);
  std::vector<bool> down_weighted(count_n, false);
  double scale = 1.0;
  weights->row(axis) = robustRow(X, design.Y.col(axis), sigma.col(axis), options, &outlier,
                                 &down_weighted, &scale, iterations)
                           .transpose();
  for (std::size_t j = 0; j < count_n; ++j) {
    if (down_weighted[j])
      flags->down_weighted_any[j] = true;
  }
  Eigen::VectorXd w(n);
  double sum2 = 0.0;
  std::size_t count = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const bool is_outlier = outlier[static_cast<std::size_t>(j)];
    w(j) = is_outlier ? 0.0 : 1.0 / (sigma(j, axis) * sigma(j, axis));
    if (is_outlier) {
      flags->outlier_any[static_cast<std::size_t>(j)] = true;
    } else {
      const double r = design.Y(j, axis) - X.row(j).dot(weights->row(axis));
      sum2 += r * r;
      ++count;
    }
  }
  *residual_variance = count > 0 ? sum2 / static_cast<double>(count) : 0.0;
  return scale * scale *
         (X.transpose() * w.asDiagonal() * X).ldlt().solve(Eigen::MatrixXd::Identity(m, m));
}

/// The residual RMS of the weights over all pairs (rejected ones included).
ResidualRms linearResidualRms(const LinearDesign& design, const Eigen::MatrixXd& weights)
{
  const Eigen::Index n = design.X.rows();
  double sum_t = 0.0, sum_r = 0.0;
  for (Eigen::Index j = 0; j < n; ++j) {
    const Eigen::Vector3d r = design.Y.row(j).transpose() - weights * design.X.row(j).transpose();
    sum_t += r.head<2>().squaredNorm();
    sum_r += r(2) * r(2);
  }
  return {std::sqrt(sum_t / n), std::sqrt(sum_r / n), static_cast<std::size_t>(n)};
}

const char* const kAxisNames[] = {"x", "y", "theta"};

/// The structure check on the inliers: per axis, a warning when the residual RMS
/// (`residual_rms`) exceeds the pairs' own noise by more than `warning_ratio`, saying how much
/// larger it is on the larger half of the motions.
std::vector<std::string> linearStructureWarnings(const LinearDesign& design,
                                                 const Eigen::MatrixXd& weights,
                                                 const std::vector<bool>& outlier,
                                                 const Eigen::Vector3d& residual_rms,
                                                 double warning_ratio)
{
  const Eigen::MatrixXd& Y = design.Y;
  const Eigen::Index n = Y.rows();
  Eigen::Vector3d noise2 = Eigen::Vector3d::Zero(), small2 = noise2, large2 = noise2;
  std::vector<double> motion_size;
  for (Eigen::Index j = 0; j < n; ++j) {
    motion_size.push_back(std::hypot(Y(j, 0), Y(j, 1)) + std::abs(Y(j, 2)));
  }
  const double size_median = median(motion_size);
  std::size_t inliers = 0, small = 0, large = 0;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (outlier[static_cast<std::size_t>(j)])
      continue;
    const Eigen::Vector3d r = Y.row(j).transpose() - weights * design.X.row(j).transpose();
    ++inliers;
    noise2 += design.sigma.row(j).transpose().cwiseAbs2();
    if (motion_size[static_cast<std::size_t>(j)] <= size_median) {
      small2 += r.cwiseAbs2();
      ++small;
    } else {
      large2 += r.cwiseAbs2();
      ++large;
    }
  }
  std::vector<std::string> warnings;
  for (int axis = 0; axis < 3 && inliers > 0; ++axis) {
    const double noise = std::sqrt(noise2(axis) / static_cast<double>(inliers));
    const double ratio = residual_rms(axis) / noise;
    if (ratio > warning_ratio) {
      const double growth = small > 0 && large > 0 && small2(axis) > 0.0
                                ? std::sqrt((large2(axis) / large) / (small2(axis) / small))
                                : 1.0;
      warnings.push_back(
          std::string("linear model residual on ") + kAxisNames[axis] + " is " +
          formatNumber(ratio) + "x the pairs' own noise" +
          (growth > 1.5 ? " and grows with the motion per pair (" + formatNumber(growth) +
                              "x larger on the larger half)"
                        : "") +
          ": the sensor motion is not linear in the encoder increments at this keyframe "
          "interval; use a shorter keyframe interval or the GP model");
    }
  }
  return warnings;
}

/// Counts the rejected pairs (outliers), and the down-weighted ones among the others, into
/// `report`, with the termination text naming the outlier threshold.
void reportLinearOutliers(const LinearPairFlags& flags, double outlier_threshold,
                          ModelReport* report)
{
  const std::vector<bool>& outlier = flags.outlier_any;
  report->outliers = static_cast<std::size_t>(std::count(outlier.begin(), outlier.end(), true));
  report->rejected = report->outliers;
  for (std::size_t j = 0; j < outlier.size(); ++j) {
    if (flags.down_weighted_any[j] && !outlier[j])
      ++report->down_weighted;
  }
  if (report->outliers > 0) {
    report->termination = std::to_string(report->outliers) + " pairs rejected beyond " +
                          formatNumber(outlier_threshold) + " robust sigma";
  } else {
    report->termination = "robust least squares converged";
  }
}

}  // namespace

ModelReport LinearModel::fit(const std::vector<MotionPair>& pairs)
{
  const auto m = static_cast<Eigen::Index>(options_.joints.kinds.size());
  if (static_cast<Eigen::Index>(pairs.size()) < 3 * m) {
    throw std::invalid_argument("linear model needs at least " + std::to_string(3 * m) +
                                " pairs for " + std::to_string(m) + " joints, got " +
                                std::to_string(pairs.size()));
  }
  const auto start = std::chrono::steady_clock::now();
  const LinearDesign design = linearDesign(pairs, options_.joints);
  ModelReport report;
  report.model = name();
  report.pairs_used = pairs.size();
  LinearPairFlags flags{std::vector<bool>(pairs.size(), false),
                        std::vector<bool>(pairs.size(), false)};
  weight_covariance_.assign(3, Eigen::MatrixXd::Zero(m, m));
  for (int axis = 0; axis < 3; ++axis) {
    weight_covariance_[static_cast<std::size_t>(axis)] = fitLinearAxis(
        design, axis, options_, &weights_, &residual_variance_(axis), &flags, &report.iterations);
  }
  reportLinearOutliers(flags, options_.outlier_threshold, &report);
  report.residual_rms_xytheta = residual_variance_.cwiseSqrt();
  report.after = linearResidualRms(design, weights_);
  report.warnings =
      linearStructureWarnings(design, weights_, flags.outlier_any, report.residual_rms_xytheta,
                              options_.structure_warning_ratio);
  report.fit_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  for (int axis = 0; axis < 3; ++axis) {
    for (Eigen::Index c = 0; c < m; ++c) {
      report.parameters.push_back(
          {std::string("W_") + kAxisNames[axis] + "_" +
               options_.joints.names[static_cast<std::size_t>(c)],
           "", 0.0, weights_(axis, c),
           std::sqrt(weight_covariance_[static_cast<std::size_t>(axis)](c, c))});
    }
  }
  return report;
}

MotionPrediction LinearModel::predict(const std::vector<EncoderSample>& samples) const
{
  const Eigen::VectorXd features = pairFeatures(samples, options_.joints);
  if (weights_.cols() != features.size()) {
    throw std::invalid_argument("linear: the model has weights for " +
                                std::to_string(weights_.cols()) + " features, the joints give " +
                                std::to_string(features.size()));
  }
  const Eigen::Vector3d mean = weights_ * features;
  MotionPrediction prediction;
  prediction.mean = Pose2(mean(0), mean(1), mean(2));
  for (int axis = 0; axis < 3; ++axis) {
    const double parameter_variance =
        weight_covariance_.empty()
            ? 0.0
            : features.dot(weight_covariance_[static_cast<std::size_t>(axis)] * features);
    prediction.covariance(axis, axis) = residual_variance_(axis) + parameter_variance;
  }
  return prediction;
}

std::string LinearModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    emitJointLayoutYaml(out, options_.joints);
    out << YAML::Key << "weights" << YAML::Value << YAML::BeginSeq;
    for (int axis = 0; axis < 3; ++axis) {
      out << YAML::Flow << YAML::BeginSeq;
      for (Eigen::Index c = 0; c < weights_.cols(); ++c)
        out << weights_(axis, c);
      out << YAML::EndSeq;
    }
    out << YAML::EndSeq;
    out << YAML::Key << "residual_variance" << YAML::Value << YAML::Flow << YAML::BeginSeq
        << residual_variance_(0) << residual_variance_(1) << residual_variance_(2) << YAML::EndSeq;
    out << YAML::Key << "weight_covariance" << YAML::Value << YAML::BeginSeq;
    for (const Eigen::MatrixXd& covariance : weight_covariance_) {
      out << YAML::Flow << YAML::BeginSeq;
      for (Eigen::Index i = 0; i < covariance.size(); ++i)
        out << covariance(i);
      out << YAML::EndSeq;
    }
    out << YAML::EndSeq;
  });
}

LinearModel LinearModel::fromYaml(const std::string& text)
{
  return readModelYaml(text, "linear", [](const YAML::Node& node) {
    LinearModelOptions options;
    for (const YAML::Node& joint : node["joints"]) {
      options.joints.names.push_back(joint[0].as<std::string>());
      options.joints.kinds.push_back(joint[1].as<std::string>() == "absolute"
                                         ? EncoderKind::kAbsolute
                                         : EncoderKind::kIncremental);
    }
    LinearModel model(options);
    const auto m = static_cast<Eigen::Index>(options.joints.names.size());
    const auto variance = node["residual_variance"].as<std::vector<double>>();
    if (node["weights"].size() != 3 || variance.size() != 3) {
      throw std::runtime_error("weights need 3 rows and residual_variance 3 values");
    }
    for (int axis = 0; axis < 3; ++axis) {
      const auto row = node["weights"][axis].as<std::vector<double>>();
      if (static_cast<Eigen::Index>(row.size()) != m) {
        throw std::runtime_error("a weights row needs one value per joint");
      }
      model.weights_.row(axis) = Eigen::Map<const Eigen::VectorXd>(row.data(), m).transpose();
      model.residual_variance_(axis) = variance[static_cast<std::size_t>(axis)];
    }
    model.weight_covariance_.clear();
    for (const YAML::Node& entry : node["weight_covariance"]) {
      const auto values = entry.as<std::vector<double>>();
      if (static_cast<Eigen::Index>(values.size()) != m * m) {
        throw std::runtime_error("weight_covariance entries need m x m values");
      }
      model.weight_covariance_.push_back(Eigen::Map<const Eigen::MatrixXd>(values.data(), m, m));
    }
    if (!model.weight_covariance_.empty() && model.weight_covariance_.size() != 3)
      throw std::runtime_error("weight_covariance needs 3 entries (one per axis) or none");
    return model;
  });
}

}  // namespace odometry_calibration
