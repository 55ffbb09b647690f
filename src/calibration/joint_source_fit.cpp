#include "odometry_calibration/calibration/joint_source_fit.h"

#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/models/joint_fits.h"

namespace odometry_calibration {

std::string jointFitModelProblem(const std::string& model)
{
  if (model == "diff_drive" || model == "mecanum")
    return "";
  return "ego_motion.sources: the joint fit of several sources supports models diff_drive and "
         "mecanum so far, not '" +
         model + "' (calibrate each source alone with a one-source configuration)";
}

JointFitReport fitSourcesJointly(const CalibrationConfig& config,
                                 const std::vector<JointSourceInput>& sources)
{
  if (const std::string problem = jointFitModelProblem(config.model); !problem.empty())
    throw std::invalid_argument(problem);
  std::vector<std::vector<MotionPair>> pairs;
  std::vector<Pose2> starts;
  for (const JointSourceInput& source : sources) {
    pairs.push_back(source.pairs);
    starts.push_back(source.T_base_sensor_start);
  }
  return config.model == "mecanum" ? fitJointMecanum(config.models.mecanum, pairs, starts)
                                   : fitJointDiffDrive(config.models.diff_drive, pairs, starts);
}

std::shared_ptr<MotionModel> jointSensorModel(const CalibrationConfig& config,
                                              const JointFitReport& joint, std::size_t index)
{
  if (config.model == "mecanum") {
    MecanumOptions options = config.models.mecanum;
    for (std::size_t wheel = 0; wheel < 4; ++wheel)
      options.initial_radius_m[wheel] = joint.intrinsics.at(wheel).value;
    options.initial_lx_plus_ly_m = joint.intrinsics.at(4).value;
    options.initial_T_base_sensor = joint.sensors.at(index).T_base_sensor;
    return std::make_shared<MecanumModel>(options);
  }
  DiffDriveOptions options = config.models.diff_drive;
  options.initial_left_radius_m = joint.intrinsics.at(0).value;
  options.initial_right_radius_m = joint.intrinsics.at(1).value;
  options.initial_separation_m = joint.intrinsics.at(2).value;
  options.initial_T_base_sensor = joint.sensors.at(index).T_base_sensor;
  return std::make_shared<DiffDriveModel>(options);
}

std::string jointResultYaml(const CalibrationConfig& config, const JointFitReport& joint,
                            const std::vector<JointSourceInput>& sources, const std::string& source)
{
  std::string text =
      calibrationResultYaml(sensorModelReport(joint, 0), *jointSensorModel(config, joint, 0),
                            source, sources.front().time_offset_s, jointLayout(config).names);
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap << YAML::Key << "sensors" << YAML::Value << YAML::BeginSeq;
  for (std::size_t s = 0; s < sources.size(); ++s) {
    const JointSensorReport& sensor = joint.sensors.at(s);
    out << YAML::BeginMap;
    out << YAML::Key << "topic" << YAML::Value << sources[s].topic;
    out << YAML::Key << "frame" << YAML::Value << sources[s].frame;
    out << YAML::Key << "T_base_sensor" << YAML::Value << YAML::BeginMap;
    const char* keys[3] = {"x_m", "y_m", "theta_rad"};
    for (int i = 0; i < 3; ++i) {
      out << YAML::Key << keys[i] << YAML::Value << sensor.pose[i].value;
      out << YAML::Key << (std::string(keys[i]) + "_sigma") << YAML::Value << sensor.pose[i].sigma;
    }
    out << YAML::EndMap;
    out << YAML::Key << "time_offset_s" << YAML::Value << sources[s].time_offset_s;
    out << YAML::Key << "pairs" << YAML::Value << sensor.pairs;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return text + out.c_str() + "\n";
}

}  // namespace odometry_calibration
