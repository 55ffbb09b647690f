#include "odometry_calibration/models/model_factory.h"

#include <algorithm>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/models/gp_model.h"

namespace odometry_calibration {

std::vector<std::string> knownModelNames()
{
  return {"linear", "diff_drive", "gp", "tricycle", "mecanum"};
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
  if (name == "linear") {
    LinearModelOptions linear = options.linear;
    linear.joints = options.joints;
    return std::make_unique<LinearModel>(linear);
  }
  if (name == "diff_drive") {
    const int joints = static_cast<int>(options.joints.names.size());
    const DiffDriveEncoderLayout& layout = options.diff_drive.layout;
    if (layout.left_index >= joints || layout.right_index >= joints) {
      throw std::invalid_argument("diff_drive: the wheel joints are not among the pairs' " +
                                  std::to_string(joints) + " joints");
    }
    return std::make_unique<DiffDriveModel>(options.diff_drive);
  }
  if (name == "gp") {
    return std::make_unique<GaussianProcessModel>(options.gp, options.joints);
  }
  if (name == "tricycle") {
    const int joints = static_cast<int>(options.joints.names.size());
    const TricycleEncoderLayout& layout = options.tricycle.layout;
    if (layout.steering_index >= joints || layout.traction_index >= joints) {
      throw std::invalid_argument(
          "tricycle: the steering and traction joints are not among the "
          "pairs' " +
          std::to_string(joints) + " joints");
    }
    return std::make_unique<TricycleModel>(options.tricycle);
  }
  if (name == "mecanum") {
    const int joints = static_cast<int>(options.joints.names.size());
    const MecanumEncoderLayout& layout = options.mecanum.layout;
    for (int index : {layout.front_left_index, layout.front_right_index, layout.rear_left_index,
                      layout.rear_right_index}) {
      if (index >= joints) {
        throw std::invalid_argument("mecanum: the four wheel joints are not among the pairs' " +
                                    std::to_string(joints) + " joints");
      }
    }
    return std::make_unique<MecanumModel>(options.mecanum);
  }
  requireKnownModel(name, "makeModel");
  throw std::logic_error("makeModel: model '" + name + "' is known but not made");
}

std::unique_ptr<MotionModel> loadModel(const std::string& model_yaml)
{
  std::string name;
  try {
    name = YAML::Load(model_yaml)["model"].as<std::string>("");
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
  throw std::runtime_error("model YAML: unknown or missing 'model' ('" + name + "')");
}

}  // namespace odometry_calibration
