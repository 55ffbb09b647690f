#include <algorithm>
#include <stdexcept>
#include <string>

#include "odometry_calibration/data/pair_features.h"

namespace odometry_calibration {

Eigen::VectorXd pairFeatures(const std::vector<EncoderSample>& samples, const JointLayout& joints)
{
  if (samples.size() < 2) {
    throw std::invalid_argument("pair features need at least two encoder samples");
  }
  const auto m = static_cast<Eigen::Index>(joints.kinds.size());
  for (const EncoderSample& sample : samples) {
    if (sample.values.size() != m) {
      throw std::invalid_argument("encoder sample has " + std::to_string(sample.values.size()) +
                                  " values, the joint layout " + std::to_string(m));
    }
  }
  Eigen::VectorXd features(m);
  const double duration = samples.back().stamp_s - samples.front().stamp_s;
  for (Eigen::Index j = 0; j < m; ++j) {
    if (joints.kinds[static_cast<std::size_t>(j)] == EncoderKind::kIncremental) {
      features(j) = samples.back().values(j) - samples.front().values(j);
      continue;
    }
    // Absolute joint: mean over the interval, each step weighted by its duration and taking
    // the end reading (the reading the kinematics use); plain mean if no time passed.
    double sum = 0.0;
    for (std::size_t k = 1; k < samples.size(); ++k) {
      const double dt = samples[k].stamp_s - samples[k - 1].stamp_s;
      sum += (duration > 0.0 ? dt : 1.0) * samples[k].values(j);
    }
    features(j) = sum / (duration > 0.0 ? duration : static_cast<double>(samples.size() - 1));
  }
  return features;
}

void requireJointIndices(const std::vector<EncoderSample>& samples, const std::vector<int>& indices,
                         const std::string& model, const std::string& what)
{
  int needed = 0;
  std::string listed;
  for (const int index : indices) {
    needed = std::max(needed, index + 1);
    listed += (listed.empty() ? "" : ", ") + std::to_string(index);
  }
  for (const EncoderSample& sample : samples) {
    if (sample.values.size() < needed) {
      throw std::invalid_argument(model + ": the model's " + what + " (indices " + listed +
                                  ") are not among the samples' " +
                                  std::to_string(sample.values.size()) + " joints");
    }
  }
}

}  // namespace odometry_calibration
