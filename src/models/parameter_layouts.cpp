#include "odometry_calibration/models/parameter_layouts.h"

namespace odometry_calibration {

const ParameterLayout& diffDriveParameters()
{
  static const ParameterLayout layout{
      {"left_wheel_radius", "right_wheel_radius", "wheel_separation", "sensor_x", "sensor_y",
       "sensor_theta"},
      {"m", "m", "m", "m", "m", "rad"},
      {"left_wheel_radius", "right_wheel_radius", "wheel_separation"}};
  return layout;
}

const ParameterLayout& mecanumParameters()
{
  static const ParameterLayout layout{
      {"wheel_radius_front_left", "wheel_radius_front_right", "wheel_radius_rear_left",
       "wheel_radius_rear_right", "lx_plus_ly", "sensor_x", "sensor_y", "sensor_theta"},
      {"m", "m", "m", "m", "m", "m", "m", "rad"},
      {"wheel_radius_front_left", "wheel_radius_front_right", "wheel_radius_rear_left",
       "wheel_radius_rear_right", "lx_plus_ly"}};
  return layout;
}

const ParameterLayout& tricycleParameters()
{
  static const ParameterLayout layout{{"steering_scale", "traction_scale", "axis_length",
                                       "steering_offset", "sensor_x", "sensor_y", "sensor_theta"},
                                      {"-", "m/turn", "m", "rad", "m", "m", "rad"},
                                      {"steering_scale", "traction_scale", "axis_length"}};
  return layout;
}

const ParameterLayout& baseOdometryParameters()
{
  static const ParameterLayout layout{
      {"translation_scale", "rotation_scale", "sensor_x", "sensor_y", "sensor_theta"},
      {"-", "-", "m", "m", "rad"},
      {"translation_scale", "rotation_scale"}};
  return layout;
}

}  // namespace odometry_calibration
