// The `wheels` section's checks and names (its keys: calibration_config_schema.cpp).
#include <stdexcept>
#include <string>
#include <vector>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/models/base_odometry_model.h"

namespace odometry_calibration {

const std::vector<std::string>& wheelTickMessageTypes()
{
  static const std::vector<std::string> types = {
      "std_msgs/Int16",  "std_msgs/Int32",   "std_msgs/Int64",  "std_msgs/UInt16",
      "std_msgs/UInt32", "std_msgs/Float32", "std_msgs/Float64"};
  return types;
}

int wheelTickMessageBits(const std::string& type)
{
  if (type == "std_msgs/Int16" || type == "std_msgs/UInt16")
    return 16;
  if (type == "std_msgs/Int32" || type == "std_msgs/UInt32")
    return 32;
  if (type == "std_msgs/Float32")
    return 24;  // a float's exact integers
  if (type == "std_msgs/Int64" || type == "std_msgs/Float64")
    return 52;  // counter_bits' own limit (a double's exact integers)
  return 0;
}

std::string wheelInputName(const WheelInputConfig& wheels, const std::string& joint_state_topic)
{
  if (wheels.source == WheelSource::kJointState)
    return "JointState on '" + joint_state_topic + "'";
  if (wheels.source == WheelSource::kJointVelocity)
    return "JointState velocities on '" + joint_state_topic + "'";
  if (wheels.source == WheelSource::kOdometry)
    return "base odometry on '" + (wheels.topics.empty() ? "" : wheels.topics[0]) + "'";
  std::string topics;
  for (const std::string& topic : wheels.topics)
    topics += (topics.empty() ? "'" : ", '") + topic + "'";
  return wheels.message_type + " ticks on " + topics;
}

std::vector<JointConfig> baseOdometryJoints()
{
  std::vector<JointConfig> joints;
  for (const std::string& name : baseOdometryJointNames()) {
    JointConfig joint;
    joint.name = name;
    joints.push_back(joint);
  }
  return joints;
}

namespace {

/// wheels.source odometry: one topic, and no model that needs wheel joints.
void validateOdometryInput(const CalibrationConfig& config)
{
  if (config.wheels.topics.size() != 1 || config.wheels.topics[0].empty()) {
    throw std::runtime_error(
        "wheels.topics: wheels.source odometry reads one nav_msgs/Odometry "
        "topic (the base's own odometry, e.g. [/odom]); " +
        std::to_string(config.wheels.topics.size()) + " given");
  }
  std::vector<std::pair<std::string, std::string>> models = {{"model", config.model},
                                                             {"prior_model", config.prior_model}};
  for (const std::string& model : config.compare_models)
    models.emplace_back("compare_models", model);
  for (const auto& [key, model] : models) {
    if (model != "base_odometry" && model != "linear" && model != "gp" && model != "none") {
      throw std::runtime_error(key + ": " + model +
                               " needs wheel joints, and wheels.source odometry has none: set " +
                               key + " to base_odometry (or linear, gp)");
    }
  }
}

}  // namespace

void validateWheelInput(const CalibrationConfig& config)
{
  const WheelInputConfig& wheels = config.wheels;
  if (wheels.source == WheelSource::kOdometry)
    return validateOdometryInput(config);
  if (wheels.source != WheelSource::kTicks) {
    if (!wheels.topics.empty())
      throw std::runtime_error(
          "wheels.topics: only wheels.source ticks (per-wheel topics) and odometry read topics");
    return;
  }
  if (wheels.topics.size() != config.joints.size()) {
    throw std::runtime_error("wheels.topics: " + std::to_string(wheels.topics.size()) +
                             " topics for " + std::to_string(config.joints.size()) +
                             " joints: wheels.source ticks needs one topic per joint, in the "
                             "joints' order");
  }
  for (std::size_t i = 0; i < wheels.topics.size(); ++i) {
    if (wheels.topics[i].empty())
      throw std::runtime_error("wheels.topics[" + std::to_string(i) + "] is empty");
    for (std::size_t j = 0; j < i; ++j) {
      if (wheels.topics[j] == wheels.topics[i]) {
        throw std::runtime_error("wheels.topics: '" + wheels.topics[i] +
                                 "' is listed twice: each joint needs its own topic");
      }
    }
  }
  const int bits = wheelTickMessageBits(wheels.message_type);
  for (std::size_t i = 0; i < config.joints.size(); ++i) {
    if (config.joints[i].counter_bits > bits) {
      throw std::runtime_error("joints[" + std::to_string(i) + "].counter_bits " +
                               std::to_string(config.joints[i].counter_bits) + " does not fit " +
                               wheels.message_type + " (" + std::to_string(bits) +
                               " bits): set it to the counter's width");
    }
  }
}

}  // namespace odometry_calibration
