// The YAML round trip every model shares (MotionModel::toYaml and each model's fromYaml): a map
// that starts with `model: <name>`, numbers with 17 significant digits (a double reads back as
// the same double), the check that a text holds the model asked for, YAML errors rethrown naming
// the model; and the part every sensor-motion model saves, the sensor's pose on the robot and
// the covariance its predictions carry (the fit's residual spread).
#pragma once

#include <functional>
#include <stdexcept>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>
#include <Eigen/Core>

#include "odometry_calibration/data/pair_features.h"
#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// A model's YAML text: a map holding `model: <model>`, then the keys `write_keys` emits into
/// it, and a final newline.
std::string writeModelYaml(const std::string& model,
                           const std::function<void(YAML::Emitter&)>& write_keys);

/// The map of a model's YAML text, checked to hold `model: <model>`. Throws std::runtime_error
/// "not a <model> model", and what yaml-cpp throws for text that is no YAML or has no `model`.
YAML::Node loadModelYaml(const std::string& text, const std::string& model);

/// The model `read` makes of the map of `text` (loaded and checked by loadModelYaml). A YAML
/// error (no YAML, a missing key, a value of the wrong type) is rethrown as std::runtime_error
/// "<model> model YAML: <what>"; other exceptions pass unchanged.
template <class Read>
auto readModelYaml(const std::string& text, const std::string& model, Read read)
    -> decltype(read(YAML::Node()))
{
  try {
    return read(loadModelYaml(text, model));
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(model + " model YAML: " + error.what());
  }
}

/// A key table's writer: each `writer(key, value)` emits `key: value` into the open map of the
/// emitter (a std::vector as a flow sequence). A model lists its keys once, in a function that
/// calls a visitor for each; toYaml visits with this writer, fromYaml with a YamlKeyReader.
class YamlKeyWriter
{
public:
  explicit YamlKeyWriter(YAML::Emitter& out) : out_(out) {}
  template <class T>
  void operator()(const char* key, const T& value) const
  {
    out_ << YAML::Key << key << YAML::Value << value;
  }
  template <class T>
  void operator()(const char* key, const std::vector<T>& values) const
  {
    out_ << YAML::Key << key << YAML::Value << YAML::Flow << values;
  }

private:
  YAML::Emitter& out_;
};

/// A key table's reader: each `reader(key, value)` reads `node[key]` as the value's type (what
/// yaml-cpp throws for a missing key or a value of the wrong type).
class YamlKeyReader
{
public:
  explicit YamlKeyReader(const YAML::Node& node) : node_(node) {}
  template <class T>
  void operator()(const char* key, T& value) const
  {
    value = node_[key].template as<T>();
  }

private:
  const YAML::Node& node_;
};

/// Writes `joints: [[name, incremental | absolute], ...]` into the open map of `out` (the model-
/// free models' inputs).
void emitJointLayoutYaml(YAML::Emitter& out, const JointLayout& joints);

/// The sensor's pose and the prediction covariance, as a sensor-motion model saves them.
struct SensorPoseYaml
{
  Pose2 T_base_sensor;                    ///< [m, m, rad]
  Eigen::Matrix3d prediction_covariance;  ///< added to every prediction [m^2, rad^2]
};

/// Writes `T_base_sensor: [x, y, theta]` and `prediction_covariance: [9 values, row-major]`
/// into the open map of `out`.
void emitSensorPoseYaml(YAML::Emitter& out, const Pose2& T_base_sensor,
                        const Eigen::Matrix3d& prediction_covariance);

/// Reads the two keys back. Throws std::runtime_error when a count is wrong (and what yaml-cpp
/// throws for a missing key or a non-number).
SensorPoseYaml readSensorPoseYaml(const YAML::Node& node);

}  // namespace odometry_calibration
