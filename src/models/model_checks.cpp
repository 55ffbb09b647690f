#include "odometry_calibration/models/model_checks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "odometry_calibration/data/pair_features.h"

namespace odometry_calibration {

void requireEnoughPairs(const std::vector<MotionPair>& pairs, std::size_t minimum,
                        const std::string& what, const std::string& advice)
{
  if (pairs.size() < minimum) {
    throw std::invalid_argument(what + " needs at least " + std::to_string(minimum) +
                                " keyframe pairs, got " + std::to_string(pairs.size()) + ": " +
                                advice);
  }
}

void requirePairsWithJoints(const std::vector<MotionPair>& pairs, const std::vector<int>& indices,
                            const std::string& model, const std::string& joints)
{
  const int needed = *std::max_element(indices.begin(), indices.end()) + 1;
  for (const MotionPair& pair : pairs) {
    if (pair.encoder_samples.size() < 2 || pair.encoder_samples.front().values.size() < needed) {
      throw std::invalid_argument(model + ": every pair needs two or more encoder samples with " +
                                  joints);
    }
  }
}

void requirePredictionSamples(const std::vector<EncoderSample>& samples,
                              const std::vector<int>& indices, const std::string& model,
                              const std::string& joints)
{
  if (samples.size() < 2)
    throw std::invalid_argument(model + " prediction needs at least two encoder samples");
  requireJointIndices(samples, indices, model, joints);
}

void requireJointsAmong(const std::vector<int>& indices, std::size_t joint_count,
                        const std::string& what)
{
  const int joints = static_cast<int>(joint_count);
  for (const int index : indices) {
    if (index >= joints) {
      throw std::invalid_argument(what + " are not among the pairs' " + std::to_string(joints) +
                                  " joints");
    }
  }
}

void requirePositiveOption(double value, const std::string& model, const std::string& name)
{
  if (!(value > 0.0) || !std::isfinite(value))
    throw std::invalid_argument(model + " option '" + name + "' must be > 0");
}

void requireSolverLimits(int max_iterations, int yaw_starts, const std::string& model)
{
  if (max_iterations < 1)
    throw std::invalid_argument(model + " option 'max_iterations' must be >= 1");
  if (yaw_starts < 1 || yaw_starts > 360)
    throw std::invalid_argument(model + " option 'yaw_starts' must be in [1, 360]");
}

bool distinctJointIndices(const std::vector<int>& indices)
{
  if (std::any_of(indices.begin(), indices.end(), [](int index) { return index < 0; }))
    return false;
  std::vector<int> sorted = indices;
  std::sort(sorted.begin(), sorted.end());
  return std::adjacent_find(sorted.begin(), sorted.end()) == sorted.end();
}

}  // namespace odometry_calibration
