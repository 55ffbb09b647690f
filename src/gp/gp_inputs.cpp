#include "odometry_calibration/gp/gp_inputs.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>

namespace odometry_calibration {

GpInputGroups groupDuplicateInputs(const Eigen::MatrixXd& inputs)
{
  const Eigen::Index n = inputs.cols();
  const Eigen::Index m = inputs.rows();
  std::vector<Eigen::Index> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), Eigen::Index{0});
  const auto less = [&](Eigen::Index a, Eigen::Index b) {
    for (Eigen::Index p = 0; p < m; ++p) {
      if (inputs(p, a) != inputs(p, b)) {
        return inputs(p, a) < inputs(p, b);
      }
    }
    return a < b;
  };
  std::sort(order.begin(), order.end(), less);

  GpInputGroups groups;
  groups.members = order;
  groups.offsets.push_back(0);
  std::vector<Eigen::Index> first_members;
  for (Eigen::Index k = 0; k < n; ++k) {
    const Eigen::Index index = order[static_cast<std::size_t>(k)];
    if (k == 0 || inputs.col(index) != inputs.col(order[static_cast<std::size_t>(k - 1)])) {
      if (k > 0) {
        groups.offsets.push_back(k);
      }
      first_members.push_back(index);
    }
  }
  groups.offsets.push_back(n);
  if (n == 0) {
    groups.offsets.assign(1, 0);
  }
  groups.inputs.resize(m, static_cast<Eigen::Index>(first_members.size()));
  for (std::size_t g = 0; g < first_members.size(); ++g) {
    groups.inputs.col(static_cast<Eigen::Index>(g)) = inputs.col(first_members[g]);
  }
  return groups;
}

int snapQuantisedFeatures(Eigen::MatrixXd* features)
{
  int snapped = 0;
  for (Eigen::Index p = 0; p < features->rows(); ++p) {
    std::vector<double> values;
    for (Eigen::Index i = 0; i < features->cols(); ++i)
      values.push_back((*features)(p, i));
    std::sort(values.begin(), values.end());
    const double largest = std::max(std::abs(values.front()), std::abs(values.back()));
    if (!(largest > 0.0) || !std::isfinite(largest))
      continue;
    // The quantum: the smallest gap between values that differ by more than rounding.
    const double rounding = 1e-9 * largest;
    double quantum = std::numeric_limits<double>::infinity();
    for (std::size_t i = 1; i < values.size(); ++i) {
      const double gap = values[i] - values[i - 1];
      if (gap > rounding)
        quantum = std::min(quantum, gap);
    }
    if (!std::isfinite(quantum))
      continue;
    // Snap only if every value is a whole multiple of it up to rounding (tick-quantised
    // increments, whatever their unit); continuous features are left alone.
    bool whole = true;
    for (const double value : values) {
      const double ratio = value / quantum;
      whole = whole && std::abs(ratio - std::round(ratio)) < 1e-6;
    }
    if (!whole)
      continue;
    for (Eigen::Index i = 0; i < features->cols(); ++i)
      (*features)(p, i) = std::round((*features)(p, i) / quantum) * quantum;
    ++snapped;
  }
  return snapped;
}

GpInputGroups singletonGroups(const Eigen::MatrixXd& inputs)
{
  GpInputGroups groups;
  groups.inputs = inputs;
  groups.members.resize(static_cast<std::size_t>(inputs.cols()));
  std::iota(groups.members.begin(), groups.members.end(), Eigen::Index{0});
  groups.offsets.resize(static_cast<std::size_t>(inputs.cols()) + 1);
  std::iota(groups.offsets.begin(), groups.offsets.end(), Eigen::Index{0});
  return groups;
}

GpInputGroups subsetGroups(const GpInputGroups& groups, Eigen::Index max_groups, unsigned seed)
{
  if (groups.size() <= max_groups) {
    return groups;
  }
  std::vector<Eigen::Index> chosen(static_cast<std::size_t>(groups.size()));
  std::iota(chosen.begin(), chosen.end(), Eigen::Index{0});
  // Fisher-Yates with our own index draws: std::shuffle's algorithm is implementation-defined.
  std::mt19937_64 rng(seed);
  for (std::size_t k = chosen.size() - 1; k > 0; --k) {
    const std::size_t j = static_cast<std::size_t>(rng() % (k + 1));
    std::swap(chosen[k], chosen[j]);
  }
  chosen.resize(static_cast<std::size_t>(max_groups));
  std::sort(chosen.begin(), chosen.end());

  GpInputGroups subset;
  subset.inputs.resize(groups.inputs.rows(), max_groups);
  subset.offsets.push_back(0);
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    const Eigen::Index g = chosen[k];
    subset.inputs.col(static_cast<Eigen::Index>(k)) = groups.inputs.col(g);
    for (Eigen::Index i = groups.offsets[static_cast<std::size_t>(g)];
         i < groups.offsets[static_cast<std::size_t>(g) + 1]; ++i) {
      subset.members.push_back(groups.members[static_cast<std::size_t>(i)]);
    }
    subset.offsets.push_back(static_cast<Eigen::Index>(subset.members.size()));
  }
  return subset;
}

namespace {

constexpr double kLog2Pi = 1.8378770664093453;

/// lambda_i = s_i + eta of pair i. Throws std::invalid_argument when it is not positive.
double pairNoiseVariance(const Eigen::VectorXd& known_variance, Eigen::Index i,
                         double extra_noise_variance)
{
  const double lambda = known_variance(i) + extra_noise_variance;
  if (!(lambda > 0.0)) {
    throw std::invalid_argument("gp: a pair has no noise variance");
  }
  return lambda;
}

/// Merges the pairs of group `g` (not a singleton) into entry g of `merged` and adds the group's
/// constant c_G (and its derivative) to the sums.
void mergeGroup(const GpInputGroups& groups, Eigen::Index g, const Eigen::VectorXd& targets,
                const Eigen::VectorXd& known_variance, double extra_noise_variance,
                GpMergedTargets* merged)
{
  const auto begin = groups.offsets[static_cast<std::size_t>(g)];
  const auto end = groups.offsets[static_cast<std::size_t>(g) + 1];
  double precision = 0.0;
  double weighted = 0.0;
  double precision2 = 0.0;
  double log_lambda = 0.0;
  for (auto k = begin; k < end; ++k) {
    const Eigen::Index i = groups.members[static_cast<std::size_t>(k)];
    const double lambda = pairNoiseVariance(known_variance, i, extra_noise_variance);
    precision += 1.0 / lambda;
    precision2 += 1.0 / (lambda * lambda);
    weighted += targets(i) / lambda;
    log_lambda += std::log(lambda);
  }
  const double v = 1.0 / precision;
  const double ybar = v * weighted;
  double scatter = 0.0;   // sum (y - ybar)^2 / lambda
  double scatter2 = 0.0;  // sum (y - ybar)^2 / lambda^2
  double first2 = 0.0;    // sum (y - ybar) / lambda^2
  for (auto k = begin; k < end; ++k) {
    const Eigen::Index i = groups.members[static_cast<std::size_t>(k)];
    const double lambda = known_variance(i) + extra_noise_variance;
    const double r = targets(i) - ybar;
    scatter += r * r / lambda;
    scatter2 += r * r / (lambda * lambda);
    first2 += r / (lambda * lambda);
  }
  const auto count = static_cast<double>(end - begin);
  merged->targets(g) = ybar;
  merged->variance(g) = v;
  merged->log_constant +=
      -0.5 * scatter - 0.5 * (count * kLog2Pi + log_lambda) + 0.5 * (kLog2Pi + std::log(v));
  // d v/d eta = v^2 sum 1/lambda^2; d ybar/d eta = -v sum (y - ybar)/lambda^2;
  // d c/d eta = 1/2 sum (y-ybar)^2/lambda^2 - 1/2 sum 1/lambda + 1/2 v sum 1/lambda^2
  // (the ybar-dependence of c vanishes: ybar minimises its scatter term).
  merged->d_variance_d_noise(g) = v * v * precision2;
  merged->d_targets_d_noise(g) = -v * first2;
  merged->d_log_constant_d_noise += 0.5 * scatter2 - 0.5 * precision + 0.5 * v * precision2;
}

}  // namespace

GpMergedTargets mergeGroupTargets(const GpInputGroups& groups, const Eigen::VectorXd& targets,
                                  const Eigen::VectorXd& known_variance,
                                  double extra_noise_variance)
{
  const Eigen::Index g_count = groups.size();
  GpMergedTargets merged;
  merged.targets.resize(g_count);
  merged.variance.resize(g_count);
  merged.d_targets_d_noise.resize(g_count);
  merged.d_variance_d_noise.resize(g_count);
  for (Eigen::Index g = 0; g < g_count; ++g) {
    const auto begin = groups.offsets[static_cast<std::size_t>(g)];
    const auto end = groups.offsets[static_cast<std::size_t>(g) + 1];
    if (end - begin != 1) {
      mergeGroup(groups, g, targets, known_variance, extra_noise_variance, &merged);
      continue;
    }
    // Singleton: nothing merged, c = 0.
    const Eigen::Index i = groups.members[static_cast<std::size_t>(begin)];
    merged.targets(g) = targets(i);
    merged.variance(g) = pairNoiseVariance(known_variance, i, extra_noise_variance);
    merged.d_targets_d_noise(g) = 0.0;
    merged.d_variance_d_noise(g) = 1.0;
  }
  return merged;
}

}  // namespace odometry_calibration
