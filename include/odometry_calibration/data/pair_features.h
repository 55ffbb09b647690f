// The joints of a robot as a model sees them, and the input features of model-free models.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// The joints a model sees, in the order of EncoderSample::values.
struct JointLayout
{
  std::vector<std::string> names;
  std::vector<EncoderKind> kinds;
};

/// Input features of model-free models for the samples of one pair (paper Sec. III): the
/// increment (last - first) of each incremental joint and the time-weighted mean of each
/// absolute joint. Throws std::invalid_argument for fewer than two samples or a size mismatch.
Eigen::VectorXd pairFeatures(const std::vector<EncoderSample>& samples, const JointLayout& joints);

/// Checks that every sample carries the joints at `indices` (a model loaded from another robot's
/// result.yaml may name joints the samples do not have). Throws std::invalid_argument
/// "<model>: the model's <what> (indices i, j, ...) are not among the samples' N joints".
void requireJointIndices(const std::vector<EncoderSample>& samples, const std::vector<int>& indices,
                         const std::string& model, const std::string& what);

}  // namespace odometry_calibration
