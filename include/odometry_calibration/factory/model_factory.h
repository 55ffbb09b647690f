// Builds any calibration model by name, from one set of options.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/gp/gp_options.h"
#include "odometry_calibration/models/base_odometry_model.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/linear_model.h"
#include "odometry_calibration/models/mecanum_model.h"
#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/skid_steer_model.h"
#include "odometry_calibration/models/tricycle_model.h"

namespace odometry_calibration {

/// Options for every model; each model reads its own part. `joints` is the layout of the
/// pairs' encoder samples (copied into the models that need it).
struct ModelFactoryOptions
{
  JointLayout joints;
  LinearModelOptions linear;
  DiffDriveOptions diff_drive;
  GpOptions gp;
  TricycleModelOptions tricycle;
  MecanumOptions mecanum;
  SkidSteerOptions skid_steer;
  BaseOdometryOptions base_odometry;
};

/// Names makeModel knows.
std::vector<std::string> knownModelNames();

/// Whether makeModel knows `name`.
bool isKnownModel(const std::string& name);

/// Throws std::invalid_argument "<what>: unknown model '<name>' (known: linear diff_drive ...)"
/// unless makeModel knows `name`; `what` names where the name came from (a key, an option).
void requireKnownModel(const std::string& name, const std::string& what);

/// A new, unfitted model. Throws std::invalid_argument for an unknown name (listing the known
/// ones) or options that do not fit the joints.
std::unique_ptr<MotionModel> makeModel(const std::string& name, const ModelFactoryOptions& options);

/// A fitted model from its toYaml() text (the `model` key names which). Throws
/// std::runtime_error for an unknown model or a missing key.
std::unique_ptr<MotionModel> loadModel(const std::string& model_yaml);

}  // namespace odometry_calibration
