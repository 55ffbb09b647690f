#include "odometry_calibration/models/model_yaml.h"

#include <vector>

#include "odometry_calibration/common/yaml_reading.h"

namespace odometry_calibration {

std::string writeModelYaml(const std::string& model,
                           const std::function<void(YAML::Emitter&)>& write_keys)
{
  YAML::Emitter out;
  out.SetDoublePrecision(17);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << model;
  write_keys(out);
  out << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

YAML::Node loadModelYaml(const std::string& text, const std::string& model)
{
  // Read through a const node: a missing key is then an invalid node (named in yaml-cpp's
  // error), not a null one added to the map.
  const YAML::Node node = loadYamlDocument(text, model + " model YAML");
  if (node["model"].as<std::string>() != model)
    throw std::runtime_error("not a " + model + " model");
  return node;
}

void emitJointLayoutYaml(YAML::Emitter& out, const JointLayout& joints)
{
  out << YAML::Key << "joints" << YAML::Value << YAML::BeginSeq;
  for (std::size_t j = 0; j < joints.names.size(); ++j) {
    out << YAML::Flow << YAML::BeginSeq << joints.names[j]
        << (joints.kinds[j] == EncoderKind::kIncremental ? "incremental" : "absolute")
        << YAML::EndSeq;
  }
  out << YAML::EndSeq;
}

void emitSensorPoseYaml(YAML::Emitter& out, const Pose2& T_base_sensor,
                        const Eigen::Matrix3d& prediction_covariance)
{
  out << YAML::Key << "T_base_sensor" << YAML::Value << YAML::Flow << YAML::BeginSeq
      << T_base_sensor.x() << T_base_sensor.y() << T_base_sensor.theta() << YAML::EndSeq;
  out << YAML::Key << "prediction_covariance" << YAML::Value << YAML::Flow << YAML::BeginSeq;
  for (int i = 0; i < 9; ++i)
    out << prediction_covariance(i / 3, i % 3);
  out << YAML::EndSeq;
}

SensorPoseYaml readSensorPoseYaml(const YAML::Node& node)
{
  const auto pose = node["T_base_sensor"].as<std::vector<double>>();
  const auto spread = node["prediction_covariance"].as<std::vector<double>>();
  if (pose.size() != 3 || spread.size() != 9)
    throw std::runtime_error("T_base_sensor needs 3 values, prediction_covariance 9");
  SensorPoseYaml read;
  read.T_base_sensor = Pose2(pose[0], pose[1], pose[2]);
  read.prediction_covariance = Eigen::Map<const Eigen::Matrix3d>(spread.data()).transpose();
  return read;
}

}  // namespace odometry_calibration
