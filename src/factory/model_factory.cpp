#include "odometry_calibration/factory/model_factory.h"

#include <algorithm>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/gp/gp_model.h"
#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/tracked_model.h"

namespace odometry_calibration {

std::vector<std::string> knownModelNames()
{
  return {"linear",     "diff_drive",    "gp",     "tricycle", "mecanum",
          "skid_steer", "base_odometry", "tracked"};
}

bool isKnownModel(const std::string& name)
{
  const std::vector<std::string> known = knownModelNames();
  return std::find(known.begin(), known.end(), name) != known.end();
}

void requireKnownModel(const std::string& name, const std::string& what)
{
  if (isKnownModel(name))
    return;
  std::string known;
  for (const std::string& model : knownModelNames())
    known += " " + model;
  throw std::invalid_argument(what + ": unknown model '" + name + "' (known:" + known + ")");
}

std::unique_ptr<MotionModel> makeModel(const std::string& name, const ModelFactoryOptions& options)
{
  const std::size_t joints = options.joints.names.size();
  if (name == "linear") {
    LinearModelOptions linear = options.linear;
    linear.joints = options.joints;
    return std::make_unique<LinearModel>(linear);
  }
  if (name == "diff_drive") {
    const DiffDriveEncoderLayout& layout = options.diff_drive.layout;
    requireJointsAmong({layout.left_index, layout.right_index}, joints,
                       "diff_drive: the wheel joints");
    return std::make_unique<DiffDriveModel>(options.diff_drive);
  }
  if (name == "tracked") {  // the diff_drive section's joints and start values
    const DiffDriveEncoderLayout& layout = options.diff_drive.layout;
    requireJointsAmong({layout.left_index, layout.right_index}, joints,
                       "tracked: the wheel joints");
    return std::make_unique<TrackedModel>(options.diff_drive);
  }
  if (name == "gp") {
    return std::make_unique<GaussianProcessModel>(options.gp, options.joints);
  }
  if (name == "tricycle") {
    const TricycleEncoderLayout& layout = options.tricycle.layout;
    requireJointsAmong({layout.steering_index, layout.traction_index}, joints,
                       "tricycle: the steering and traction joints");
    return std::make_unique<TricycleModel>(options.tricycle);
  }
  if (name == "mecanum") {
    const MecanumEncoderLayout& layout = options.mecanum.layout;
    requireJointsAmong({layout.front_left_index, layout.front_right_index, layout.rear_left_index,
                        layout.rear_right_index},
                       joints, "mecanum: the four wheel joints");
    return std::make_unique<MecanumModel>(options.mecanum);
  }
  if (name == "skid_steer") {
    requireJointsAmong(options.skid_steer.left_indices, joints, "skid_steer: the wheel joints");
    requireJointsAmong(options.skid_steer.right_indices, joints, "skid_steer: the wheel joints");
    return std::make_unique<SkidSteerModel>(options.skid_steer);
  }
  if (name == "base_odometry") {
    const BaseOdometryLayout& layout = options.base_odometry.layout;
    requireJointsAmong({layout.forward_index, layout.lateral_index, layout.yaw_index}, joints,
                       "base_odometry: the base odometry's joints");
    return std::make_unique<BaseOdometryModel>(options.base_odometry);
  }
  requireKnownModel(name, "makeModel");
  throw std::logic_error("makeModel: model '" + name + "' is known but not made");
}

std::unique_ptr<MotionModel> loadModel(const std::string& model_yaml)
{
  std::string name;
  try {
    name = loadYamlDocument(model_yaml, "model YAML")["model"].as<std::string>("");
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(std::string("model YAML: ") + error.what());
  }
  if (name == "diff_drive")
    return std::make_unique<DiffDriveModel>(DiffDriveModel::fromYaml(model_yaml));
  if (name == "linear")
    return std::make_unique<LinearModel>(LinearModel::fromYaml(model_yaml));
  if (name == "gp")
    return GaussianProcessModel::fromYaml(model_yaml);
  if (name == "tricycle")
    return std::make_unique<TricycleModel>(TricycleModel::fromYaml(model_yaml));
  if (name == "mecanum")
    return std::make_unique<MecanumModel>(MecanumModel::fromYaml(model_yaml));
  if (name == "skid_steer")
    return std::make_unique<SkidSteerModel>(SkidSteerModel::fromYaml(model_yaml));
  if (name == "base_odometry")
    return std::make_unique<BaseOdometryModel>(BaseOdometryModel::fromYaml(model_yaml));
  if (name == "tracked")
    return std::make_unique<TrackedModel>(TrackedModel::fromYaml(model_yaml));
  throw std::runtime_error("model YAML: unknown or missing 'model' ('" + name + "')");
}

}  // namespace odometry_calibration
