// The parameter vectors of the parametric models, named once: the order in which each model
// fits and reports them, their units, and which of them are relative quantities (a scale, a
// length: their σ is judged as a fraction of the value, observability.h). The model reports
// (parameterEstimates) and the excitation guidance (which motions each parameter needs) both
// read them, so that a renamed or added parameter cannot disagree between the two.
#pragma once

#include <string>
#include <vector>

namespace odometry_calibration {

struct ParameterLayout
{
  std::vector<std::string> names;     ///< in the fit's order: the intrinsics, then the extrinsic
  std::vector<std::string> units;     ///< one per name ("m", "rad", "m/turn", "-")
  std::vector<std::string> relative;  ///< the names judged relative to their value
};

/// left_wheel_radius, right_wheel_radius, wheel_separation [m]; sensor_x, sensor_y [m],
/// sensor_theta [rad].
const ParameterLayout& diffDriveParameters();

/// The four wheel radii (front left, front right, rear left, rear right) and lx_plus_ly [m];
/// sensor_x, sensor_y [m], sensor_theta [rad].
const ParameterLayout& mecanumParameters();

/// steering_scale [-], traction_scale [m/turn], axis_length [m], steering_offset [rad];
/// sensor_x, sensor_y [m], sensor_theta [rad] (tricycle seed, section 3).
const ParameterLayout& tricycleParameters();

/// translation_scale, rotation_scale [-]; sensor_x, sensor_y [m], sensor_theta [rad] (a base
/// that publishes only its odometry, base_odometry_model.h).
const ParameterLayout& baseOdometryParameters();

}  // namespace odometry_calibration
