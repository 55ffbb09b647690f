#include "odometry_calibration/models/sensor_pose_yaml.h"

#include <stdexcept>
#include <vector>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {

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
