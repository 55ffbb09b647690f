#include "odometry_calibration/models/model_checks.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "odometry_calibration/common/number_text.h"
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

std::string physicalBoundsProblem(const std::vector<std::string>& names,
                                  const std::vector<double>& values)
{
  for (std::size_t i = 0; i < names.size() && i < values.size(); ++i) {
    const std::string& name = names[i];
    const double value = values[i];
    auto contains = [&](const char* part) { return name.find(part) != std::string::npos; };
    const double max_length =
        contains("radius")                                                            ? 5.0
        : contains("separation") || contains("axis_length") || contains("lx_plus_ly") ? 50.0
        : name == "sensor_x" || name == "sensor_y"                                    ? -100.0
                                                                                      : 0.0;
    std::string problem;
    if (!std::isfinite(value))
      problem = "is not finite";
    else if (max_length > 0.0 && !(value > 0.0 && value <= max_length))
      problem = "is outside (0, " + formatNumber(max_length) + "] m";
    else if (max_length < 0.0 && !(std::abs(value) <= -max_length))
      problem = "puts the sensor more than 100 m from the base";
    if (!problem.empty()) {
      return "the fitted " + name + " = " + formatNumber(value) + " " + problem +
             ": no physical value (check the start values, the joints' signs and the pairs)";
    }
  }
  return "";
}

}  // namespace odometry_calibration
