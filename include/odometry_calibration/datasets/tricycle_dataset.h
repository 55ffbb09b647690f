// Reader for the tricycle calibration log format (shared/data/tricycle/README.md):
//   a header of '#' lines (kinematic model, nominal parameters, encoder ranges, laser pose),
//   then one sample per line:
//   time: <t> ticks: <steer> <traction> model_pose: <x> <y> <th> tracker_pose: <x> <y> <th>
#pragma once

#include <cstddef>
#include <istream>
#include <stdexcept>
#include <string>
#include <vector>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// A malformed line: carries the source, line number and what was expected.
class DatasetParseError : public std::runtime_error
{
public:
  DatasetParseError(const std::string& source, std::size_t line, const std::string& what)
      : std::runtime_error(source + ":" + std::to_string(line) + ": " + what), line_(line)
  {
  }
  /// 1-based line number of the offending line.
  std::size_t line() const { return line_; }

private:
  std::size_t line_;
};

/// What the header says; fields are empty / false when the header lacks them.
struct TricycleDatasetHeader
{
  std::string kinematic_model;               ///< e.g. "traction_drive_wheel"
  std::vector<std::string> parameter_names;  ///< e.g. Ksteer Ktraction axis_length steer_offset
  std::vector<double> parameter_values;      ///< nominal values, same order
  std::vector<std::string> joint_names;      ///< order of the ticks, e.g. steering traction_wheel
  std::vector<double> joint_max_values;      ///< ticks per turn of each joint, same order
  bool has_sensor_pose = false;              ///< whether "laser wrt base_link" was given
  Pose2 T_base_sensor;                       ///< nominal sensor pose in base_link [m, m, rad]
};

/// One sample line.
struct TricycleDatasetRow
{
  std::size_t line = 0;       ///< 1-based line number in the file
  double stamp_s = 0.0;       ///< time since the first sample [s]
  double steering_ticks = 0;  ///< raw absolute steering reading [ticks]
  double traction_ticks = 0;  ///< raw incremental traction counter (uint32) [ticks]
  Pose2 T_odom_base_model;    ///< the robot's own odometry with nominal parameters
  Pose2 T_world_sensor;       ///< tracker pose of the sensor (the ego-motion source)
};

/// A whole log.
struct TricycleDataset
{
  std::string source;                    ///< file name, for messages
  TricycleDatasetHeader header;          ///< what the header says
  double first_stamp_unix_s = 0.0;       ///< absolute time of the first sample [s] (~0.2 us)
  std::vector<TricycleDatasetRow> rows;  ///< samples in file order, times non-decreasing
  /// The last sample line had no line end: the file may have been cut off while written.
  bool last_line_unterminated = false;
};

/// Parses a log from a stream. Throws DatasetParseError (line number and what was expected) on
/// a malformed line, a tick count outside [0, 2^32), or time going backwards.
TricycleDataset parseTricycleDataset(std::istream& input, const std::string& source);

/// Opens and parses a file; throws std::runtime_error if it cannot be read.
TricycleDataset loadTricycleDataset(const std::string& path);

}  // namespace odometry_calibration
