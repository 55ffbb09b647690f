// The configuration the fuzz targets that pair (messages, bag) run with: the shipped
// diff_drive.yaml, every match in the calling thread so that a finding replays the same way.
#pragma once

#include "odometry_calibration/config/calibration_config.h"

namespace odometry_calibration {
namespace test {

inline const CalibrationConfig& diffDriveFuzzConfig()
{
  static const CalibrationConfig loaded = [] {
    CalibrationConfig config =
        loadCalibrationConfig(ODOMETRY_CALIBRATION_CONFIG_DIR "/diff_drive.yaml");
    config.collector.background_matching = false;
    return config;
  }();
  return loaded;
}

}  // namespace test
}  // namespace odometry_calibration
