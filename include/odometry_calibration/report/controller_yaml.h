// Controller-ready calibration (controller.yaml beside result.yaml): the fitted geometry in the
// form robot controllers take, read from the fit report's parameters by name.
#pragma once

#include <string>

#include "odometry_calibration/models/joint_fit_report.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// controller.yaml's text for a fit, each value commented with its sigma:
///  - parameters left_wheel_radius, right_wheel_radius, wheel_separation (diff_drive,
///    skid_steer): ros_control diff_drive_controller's wheel_separation and wheel_radius (the
///    configured nominal values, i.e. the parameters' start values) with
///    wheel_separation_multiplier, left_wheel_radius_multiplier and
///    right_wheel_radius_multiplier (fitted / nominal);
///  - parameters wheel_radius_* and lx_plus_ly (mecanum): each fitted radius, their mean
///    (mecanum_drive_controller's wheels_radius) and lx + ly
///    (sum_of_robot_center_projection_on_X_Y_axis).
/// Empty for other models (GP, linear, tricycle: no controller form). `source` names the data.
std::string controllerYaml(const ModelReport& report, const std::string& source);

/// controller.yaml's text for a joint fit of several sensors (the joint wheels, as
/// controllerYaml gives them), its header counting every sensor's pairs in the fit ("joint
/// diff_drive fit of 2 sensors, 119 + 121 = 240 pairs") and pointing at joint_report.txt when
/// a sensor's fit warns.
std::string jointControllerYaml(const JointFitReport& joint, const std::string& source);

}  // namespace odometry_calibration
