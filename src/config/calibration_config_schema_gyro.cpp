// The `gyro:` keys of calibration_config_schema.h: the IMU's topic and mounting, and whether
// ~odom takes its heading from it.
#include "odometry_calibration/config/calibration_config_schema.h"

namespace odometry_calibration {

const std::vector<ConfigSchemaEntry<CalibrationConfig>>& gyroConfigSchema()
{
  using Entry = ConfigSchemaEntry<CalibrationConfig>;
  static const std::vector<Entry> entries = {
      text<CalibrationConfig>(
          "gyro.topic", "", true,
          "sensor_msgs/Imu topic whose angular velocity is fitted as a further source: scale, "
          "bias, time offset (empty: no gyro)",
          [](auto& c) -> auto& { return c.gyro.topic; }),
      number<CalibrationConfig>(
          "gyro.roll_rad", 0.0, "rad", rangeClosed(-1.5, 1.5),
          "the IMU frame's roll in base_link (about x, applied first)",
          [](auto& c) -> auto& { return c.gyro.roll_rad; }),
      number<CalibrationConfig>(
          "gyro.pitch_rad", 0.0, "rad", rangeClosed(-1.5, 1.5),
          "the IMU frame's pitch in base_link (about y, after the roll)",
          [](auto& c) -> auto& { return c.gyro.pitch_rad; }),
      number<CalibrationConfig>(
          "gyro.max_gap_s", 0.1, "s", rangeClosed(0.001, 10.0),
          "readings further apart are a gap: a pair across it is left out "
          "of the gyro's fit",
          [](auto& c) -> auto& { return c.gyro.max_gap_s; }),
      flag<CalibrationConfig>(
          "gyro.odom_heading", false,
          "~odom's heading from the calibrated gyro (scale, bias, time offset of the last "
          "~calibrate), its translation from the wheels; needs gyro.topic",
          [](auto& c) -> auto& { return c.gyro.odom_heading; }),
  };
  return entries;
}

}  // namespace odometry_calibration
