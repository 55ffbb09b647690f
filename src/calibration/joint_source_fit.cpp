#include "odometry_calibration/calibration/joint_source_fit.h"

#include <cctype>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/models/joint_fits.h"

namespace odometry_calibration {

std::string jointFitModelProblem(const std::string& model)
{
  if (model == "diff_drive" || model == "skid_steer" || model == "mecanum" || model == "tricycle")
    return "";
  return "model '" + model +
         "' has no joint fit of several sources (ego_motion.sources); the models that have one "
         "are diff_drive, skid_steer, mecanum and tricycle (or calibrate each source alone with "
         "a one-source configuration)";
}

namespace {

/// `message` with "sensor <k>" (the joint fits' name of the k-th pair set) followed by source
/// k's topic, so that the user reads which laser's pairs cannot be fitted.
std::string namingSources(std::string message, const std::vector<JointSourceInput>& sources)
{
  for (std::size_t k = 0; k < sources.size(); ++k) {
    const std::string sensor = "sensor " + std::to_string(k);
    const std::size_t at = message.find(sensor);
    const std::size_t end = at + sensor.size();
    if (at != std::string::npos &&
        (end == message.size() || !std::isdigit(static_cast<unsigned char>(message[end]))))
      message.insert(end, " ('" + sources[k].topic + "')");
  }
  return message;
}

}  // namespace

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
  const ModelFactoryOptions& models = config.models;
  try {
    if (config.model == "mecanum")
      return fitJointMecanum(models.mecanum, pairs, starts);
    if (config.model == "skid_steer")
      return fitJointSkidSteer(models.skid_steer, pairs, starts);
    if (config.model == "tricycle")
      return fitJointTricycle(models.tricycle, pairs, starts);
    return fitJointDiffDrive(models.diff_drive, pairs, starts);
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(namingSources(error.what(), sources));
  }
}

namespace {

/// The joint fit's intrinsics' values, in the fit's order.
std::vector<double> intrinsicValues(const JointFitReport& joint, std::size_t count)
{
  if (joint.intrinsics.size() != count) {
    throw std::invalid_argument("joint fit of model '" + joint.model + "' has " +
                                std::to_string(joint.intrinsics.size()) + " intrinsics, not " +
                                std::to_string(count));
  }
  std::vector<double> values;
  for (const ParameterEstimate& parameter : joint.intrinsics)
    values.push_back(parameter.value);
  return values;
}

/// The differential drive of the joint wheels with sensor pose `T_base_sensor` (diff_drive's
/// own, or skid_steer's virtual wheels).
DiffDriveModel jointDiffDrive(DiffDriveOptions options, const JointFitReport& joint,
                              const Pose2& T_base_sensor)
{
  const std::vector<double> values = intrinsicValues(joint, 3);
  options.initial_left_radius_m = values[0];
  options.initial_right_radius_m = values[1];
  options.initial_separation_m = values[2];
  options.initial_T_base_sensor = T_base_sensor;
  return DiffDriveModel(options);
}

}  // namespace

std::shared_ptr<MotionModel> jointSensorModel(const CalibrationConfig& config,
                                              const JointFitReport& joint, std::size_t index)
{
  const Pose2& T_base_sensor = joint.sensors.at(index).T_base_sensor;
  const ModelFactoryOptions& models = config.models;
  if (config.model == "mecanum") {
    MecanumOptions options = models.mecanum;
    const std::vector<double> values = intrinsicValues(joint, 5);
    for (std::size_t wheel = 0; wheel < 4; ++wheel)
      options.initial_radius_m[wheel] = values[wheel];
    options.initial_lx_plus_ly_m = values[4];
    options.initial_T_base_sensor = T_base_sensor;
    return std::make_shared<MecanumModel>(options);
  }
  if (config.model == "skid_steer") {
    return std::make_shared<SkidSteerModel>(
        models.skid_steer,
        jointDiffDrive(skidSteerVirtualWheels(models.skid_steer), joint, T_base_sensor));
  }
  if (config.model == "tricycle") {
    TricycleModelOptions options = models.tricycle;
    const std::vector<double> values = intrinsicValues(joint, 4);
    options.initial = TricycleParameters::fromVectors(
        Eigen::Vector4d(values[0], values[1], values[2], values[3]), T_base_sensor.vector());
    return std::make_shared<TricycleModel>(options);
  }
  return std::make_shared<DiffDriveModel>(jointDiffDrive(models.diff_drive, joint, T_base_sensor));
}

std::string jointResultYaml(const CalibrationConfig& config, const JointFitReport& joint,
                            const std::vector<JointSourceInput>& sources, const std::string& source)
{
  std::string text = calibrationResultYaml(
      sensorModelReport(joint, 0), *jointSensorModel(config, joint, 0), source,
      sources.front().time_offset_s, jointLayout(config).names, sources.front().fit_interval_s);
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
    if (sources[s].fit_interval_s > 0.0)
      out << YAML::Key << "fit_interval_s" << YAML::Value << sources[s].fit_interval_s;
    out << YAML::Key << "pairs" << YAML::Value << sensor.pairs;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return text + out.c_str() + "\n";
}

}  // namespace odometry_calibration
