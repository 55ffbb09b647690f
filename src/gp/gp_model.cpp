#include "odometry_calibration/gp/gp_model.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <exception>
#include <limits>
#include <mutex>
#include <stdexcept>
#include <thread>

#include "odometry_calibration/gp/gp_denormals.h"
#include "odometry_calibration/gp/gp_inducing.h"
#include "odometry_calibration/gp/gp_inputs.h"
#include "odometry_calibration/gp/gp_outliers.h"

namespace odometry_calibration {
namespace {

constexpr std::size_t kMinimumPairs = 10;
constexpr Eigen::Index kMinimumDistinctInputs = 5;

/// Features (m x n, raw), targets and known variances (3 x n) of the pairs.
struct PairArrays
{
  Eigen::MatrixXd features;
  Eigen::MatrixXd targets;
  Eigen::MatrixXd variances;
};

PairArrays extractPairs(const std::vector<MotionPair>& pairs, const JointLayout& joints)
{
  const auto n = static_cast<Eigen::Index>(pairs.size());
  PairArrays arrays;
  arrays.features.resize(static_cast<Eigen::Index>(joints.kinds.size()), n);
  arrays.targets.resize(3, n);
  arrays.variances.resize(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const MotionPair& pair = pairs[static_cast<std::size_t>(i)];
    try {
      arrays.features.col(i) = pairFeatures(pair.encoder_samples, joints);
    } catch (const std::invalid_argument& error) {
      throw std::invalid_argument("gp: pair " + std::to_string(i) + ": " + error.what());
    }
    arrays.targets.col(i) = pair.sensor_motion.vector();
    arrays.variances.col(i) = pair.covariance.diagonal();
    if (!arrays.features.col(i).allFinite() || !arrays.targets.col(i).allFinite() ||
        !arrays.variances.col(i).allFinite() || (arrays.variances.col(i).array() < 0.0).any()) {
      throw std::invalid_argument("gp: pair " + std::to_string(i) +
                                  " has a non-finite feature, motion or covariance, or a "
                                  "negative variance");
    }
  }
  return arrays;
}

/// Known variances for weighting the pre-fit: zeros replaced by the axis' mean positive variance.
Eigen::MatrixXd prefitVariances(const Eigen::MatrixXd& variances)
{
  Eigen::MatrixXd out = variances;
  for (Eigen::Index axis = 0; axis < 3; ++axis) {
    const Eigen::ArrayXd row = variances.row(axis).transpose().array();
    const double positive = (row > 0.0).cast<double>().sum();
    const double fill = positive > 0.0 ? (row > 0.0).select(row, 0.0).sum() / positive : 1.0;
    out.row(axis) = (row > 0.0).select(row, fill).matrix().transpose();
  }
  return out;
}

Eigen::MatrixXd selectColumns(const Eigen::MatrixXd& matrix, const std::vector<Eigen::Index>& cols)
{
  Eigen::MatrixXd out(matrix.rows(), static_cast<Eigen::Index>(cols.size()));
  for (std::size_t k = 0; k < cols.size(); ++k) {
    out.col(static_cast<Eigen::Index>(k)) = matrix.col(cols[k]);
  }
  return out;
}

/// Runs job(axis) for the three axes on up to `threads` threads; rethrows the first exception.
template <typename Job>
void forEachAxis(int threads, const Job& job)
{
  std::atomic<int> next{0};
  std::exception_ptr failure;
  std::mutex failure_mutex;
  const auto worker = [&]() {
    for (int axis = next++; axis < 3; axis = next++) {
      try {
        job(axis);
      } catch (...) {
        std::lock_guard<std::mutex> lock(failure_mutex);
        if (!failure) {
          failure = std::current_exception();
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) {
    pool.emplace_back(worker);
  }
  worker();
  for (std::thread& thread : pool) {
    thread.join();
  }
  if (failure) {
    std::rethrow_exception(failure);
  }
}

}  // namespace

GaussianProcessModel::GaussianProcessModel(GpOptions options, JointLayout joints)
    : options_(options), joints_(std::move(joints))
{
  validate(options_);
  if (joints_.kinds.empty() || joints_.names.size() != joints_.kinds.size()) {
    throw std::invalid_argument(
        "gp: the joint layout needs at least one joint and one name per joint kind");
  }
}

void GaussianProcessModel::fitOutputs(const Eigen::MatrixXd& inputs, const Eigen::MatrixXd& targets,
                                      const Eigen::MatrixXd& variances,
                                      const std::vector<bool>& inlier, bool warm, bool optimise)
{
  std::vector<Eigen::Index> used;
  for (std::size_t i = 0; i < inlier.size(); ++i) {
    if (inlier[i]) {
      used.push_back(static_cast<Eigen::Index>(i));
    }
  }
  const Eigen::MatrixXd x = selectColumns(inputs, used);
  const Eigen::MatrixXd y = selectColumns(targets, used);
  const Eigen::MatrixXd s = selectColumns(variances, used);
  const GpInputGroups groups = groupDuplicateInputs(x);
  Eigen::MatrixXd inducing(x.rows(), 0);
  if (groups.size() > static_cast<Eigen::Index>(options_.likelihood_subset) ||
      groups.size() > static_cast<Eigen::Index>(options_.max_exact_pairs)) {
    inducing = selectInducingInputs(
        groups.inputs, static_cast<Eigen::Index>(options_.inducing_points), options_.seed);
  }
  const GpKernel kernel(options_.kernel, static_cast<int>(x.rows()));
  std::array<Eigen::VectorXd, 3> warm_starts;
  for (int axis = 0; axis < 3; ++axis) {
    warm_starts[axis] = outputs_[axis].hyperparameters;
  }
  const int hardware = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  const int threads = std::min(3, options_.num_threads > 0 ? options_.num_threads : hardware);
  forEachAxis(threads, [&](int axis) {
    GpOutputProblem problem;
    problem.kernel = kernel;
    problem.groups = groups;
    problem.targets = y.row(axis).transpose();
    problem.known_variance = s.row(axis).transpose();
    problem.linear_mean = options_.mean == GpMeanFunction::kLinear;
    problem.learn_noise = options_.learn_noise;
    const double known = problem.known_variance.mean();
    const double spread =
        problem.targets.squaredNorm() / static_cast<double>(problem.targets.size());
    problem.noise_floor = known > 0.0 ? 1e-6 * known : 1e-9 * spread + 1e-300;
    const Eigen::VectorXd* start = warm ? &warm_starts[static_cast<std::size_t>(axis)] : nullptr;
    const int previous_iterations = warm ? outputs_[static_cast<std::size_t>(axis)].iterations : 0;
    outputs_[static_cast<std::size_t>(axis)] =
        fitGpOutput(problem, options_, inducing,
                    options_.seed + 7919u * static_cast<unsigned>(axis), start, optimise);
    outputs_[static_cast<std::size_t>(axis)].iterations += previous_iterations;
  });
}

namespace {

/// The divisors of the raw features: their RMS over the pairs (1 for a feature that is zero
/// throughout).
Eigen::VectorXd rmsInputScale(const Eigen::MatrixXd& features)
{
  const Eigen::Index n = features.cols();
  Eigen::VectorXd scale = (features.rowwise().squaredNorm() / static_cast<double>(n)).cwiseSqrt();
  for (Eigen::Index p = 0; p < scale.size(); ++p) {
    if (!(scale(p) > 0.0)) {
      scale(p) = 1.0;
    }
  }
  return scale;
}

/// The number of inliers; throws std::invalid_argument when fewer than kMinimumPairs of the
/// `n` pairs are left.
std::size_t requireAgreeingPairs(const std::vector<bool>& inlier, Eigen::Index n)
{
  const auto count = static_cast<std::size_t>(std::count(inlier.begin(), inlier.end(), true));
  if (count < kMinimumPairs) {
    throw std::invalid_argument("gp: only " + std::to_string(count) + " of " + std::to_string(n) +
                                " pairs agree with each other; check the pairs' quality");
  }
  return count;
}

}  // namespace

ModelReport GaussianProcessModel::fit(const std::vector<MotionPair>& pairs)
{
  const auto start_time = std::chrono::steady_clock::now();
  if (pairs.size() < kMinimumPairs) {
    throw std::invalid_argument("gp: needs at least " + std::to_string(kMinimumPairs) +
                                " keyframe pairs, got " + std::to_string(pairs.size()) +
                                ": record a longer drive");
  }
  PairArrays arrays = extractPairs(pairs, joints_);
  // Tick-quantised increments in any unit (radians from a JointState) merge like ticks do.
  snapQuantisedFeatures(&arrays.features);
  const Eigen::Index n = arrays.features.cols();
  input_scale_ = rmsInputScale(arrays.features);
  const Eigen::MatrixXd inputs = input_scale_.cwiseInverse().asDiagonal() * arrays.features;
  const GpInputGroups all_groups = groupDuplicateInputs(inputs);
  if (all_groups.size() < kMinimumDistinctInputs) {
    throw std::invalid_argument("gp: the " + std::to_string(n) + " pairs hold only " +
                                std::to_string(all_groups.size()) +
                                " distinct encoder feature vectors: drive, turn and stop at "
                                "different speeds while recording");
  }

  const GpPrefitResult prefit =
      robustPolynomialPrefit(inputs, arrays.targets, prefitVariances(arrays.variances),
                             options_.prefit_huber_threshold, options_.outlier_threshold);
  std::vector<bool> inlier = prefit.inlier;
  requireAgreeingPairs(inlier, n);
  fitted_ = false;
  fitOutputs(inputs, arrays.targets, arrays.variances, inlier, false, true);
  fitted_ = true;
  const Eigen::MatrixXd means =
      refitWithoutOutliers(all_groups, inputs, arrays.targets, arrays.variances, &inlier);
  ModelReport report = makeReport(pairs, arrays.targets, arrays.variances, means, inlier);
  report.fit_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_time).count();
  return report;
}

Eigen::MatrixXd GaussianProcessModel::refitWithoutOutliers(const GpInputGroups& all_groups,
                                                           const Eigen::MatrixXd& inputs,
                                                           const Eigen::MatrixXd& targets,
                                                           const Eigen::MatrixXd& variances,
                                                           std::vector<bool>* inlier)
{
  const Eigen::Index n = inputs.cols();
  Eigen::MatrixXd means = pairMeans(all_groups);
  for (int pass = 0; pass < options_.outlier_passes && options_.outlier_threshold > 0.0; ++pass) {
    const std::vector<bool> next = recheckInliers(all_groups, means, targets, variances, *inlier);
    std::size_t changed = 0;
    for (std::size_t i = 0; i < next.size(); ++i) {
      changed += next[i] != (*inlier)[i] ? 1 : 0;
    }
    if (changed == 0) {
      break;
    }
    *inlier = next;
    requireAgreeingPairs(*inlier, n);
    // A few changed pairs do not move the hyperparameters: recompute the posterior only.
    fitOutputs(inputs, targets, variances, *inlier, true,
               changed * 100 > static_cast<std::size_t>(n));
    means = pairMeans(all_groups);
  }
  return means;
}

Eigen::MatrixXd GaussianProcessModel::pairMeans(const GpInputGroups& groups) const
{
  Eigen::MatrixXd means(3, groups.pairCount());
  for (int axis = 0; axis < 3; ++axis) {
    const Eigen::VectorXd group_means = outputs_[axis].means(groups.inputs);
    for (Eigen::Index g = 0; g < groups.size(); ++g) {
      for (auto k = groups.offsets[static_cast<std::size_t>(g)];
           k < groups.offsets[static_cast<std::size_t>(g) + 1]; ++k) {
        means(axis, groups.members[static_cast<std::size_t>(k)]) = group_means(g);
      }
    }
  }
  return means;
}

std::vector<bool> GaussianProcessModel::recheckInliers(const GpInputGroups& groups,
                                                       const Eigen::MatrixXd& means,
                                                       const Eigen::MatrixXd& targets,
                                                       const Eigen::MatrixXd& variances,
                                                       const std::vector<bool>& inlier) const
{
  std::vector<bool> next(inlier.size(), true);
  for (Eigen::Index g = 0; g < groups.size(); ++g) {
    const auto begin = groups.offsets[static_cast<std::size_t>(g)];
    const auto end = groups.offsets[static_cast<std::size_t>(g) + 1];
    bool any_rejected = false;
    for (auto k = begin; k < end; ++k) {
      any_rejected |=
          !inlier[static_cast<std::size_t>(groups.members[static_cast<std::size_t>(k)])];
    }
    // Training inputs are judged against the noise alone (the in-sample posterior variance is
    // small); inputs left out also get the posterior variance of f.
    Eigen::Vector3d f_variance = Eigen::Vector3d::Zero();
    if (any_rejected) {
      for (int axis = 0; axis < 3; ++axis) {
        double mean = 0.0;
        outputs_[axis].predict(groups.inputs.col(g), false, &mean, &f_variance(axis));
      }
    }
    for (auto k = begin; k < end; ++k) {
      const Eigen::Index i = groups.members[static_cast<std::size_t>(k)];
      for (int axis = 0; axis < 3; ++axis) {
        double residual = targets(axis, i) - means(axis, i);
        if (axis == 2) {
          residual = normalizeAngle(residual);
        }
        const double variance =
            f_variance(axis) + outputs_[axis].noise_variance + variances(axis, i);
        if (std::abs(residual) > options_.outlier_threshold * std::sqrt(variance)) {
          next[static_cast<std::size_t>(i)] = false;
        }
      }
    }
  }
  return next;
}

MotionPrediction GaussianProcessModel::predictFeatures(const Eigen::VectorXd& features) const
{
  if (!fitted_) {
    throw std::logic_error("gp: predict() before fit() or fromYaml()");
  }
  if (features.size() != input_scale_.size()) {
    throw std::invalid_argument("gp: expected " + std::to_string(input_scale_.size()) +
                                " features, got " + std::to_string(features.size()));
  }
  const Eigen::VectorXd x = features.cwiseQuotient(input_scale_);
  const DenormalsAsZero denormals_as_zero;  // kernel values far from the data (gp_denormals.h)
  MotionPrediction prediction;
  Eigen::Vector3d mean;
  for (int axis = 0; axis < 3; ++axis) {
    outputs_[axis].predict(x, options_.predict_learned_noise, &mean(axis),
                           &prediction.covariance(axis, axis));
  }
  prediction.mean = Pose2(mean(0), mean(1), mean(2));
  return prediction;
}

MotionPrediction GaussianProcessModel::predict(const std::vector<EncoderSample>& samples) const
{
  return predictFeatures(pairFeatures(samples, joints_));
}

}  // namespace odometry_calibration
