// Writes a rosbag2 bag folder in SQLite storage, as ROS 2's `ros2 bag record -s sqlite3` does:
// <folder>/<name>_0.db3 (tables topics and messages, CDR-serialised messages, indexed by
// timestamp) and metadata.yaml (version 5), optionally the storage file compressed with zstd
// (compression_mode FILE: <name>_0.db3.zstd). The messages are the ROS 1 C++ types, serialised
// as their ROS 2 counterparts (cdr_writer.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <ros/message_traits.h>
#include <ros/time.h>

#include "odometry_calibration/bag/rosbag2_metadata.h"
#include "odometry_calibration/bag_writers/cdr_writer.h"

namespace odometry_calibration {

class SqliteDatabase;
class SqliteStatement;

/// "sensor_msgs/LaserScan" as ROS 2 spells it, "sensor_msgs/msg/LaserScan".
std::string rosbag2TypeName(const std::string& ros1_type);

/// One bag folder being written. Not copyable.
class Rosbag2SqliteWriter
{
public:
  /// Starts writing into the existing folder `folder` the bag named `name` (its storage file
  /// "<name>_0.db3"; the name of the folder it will have). Throws std::runtime_error naming
  /// the file that cannot be created.
  Rosbag2SqliteWriter(const std::string& folder, const std::string& name, bool zstd = false);
  ~Rosbag2SqliteWriter();
  Rosbag2SqliteWriter(const Rosbag2SqliteWriter&) = delete;
  Rosbag2SqliteWriter& operator=(const Rosbag2SqliteWriter&) = delete;

  /// `message` (a type of cdr_layout.h) on `topic`, recorded at `time`.
  template <typename M>
  void write(const std::string& topic, const ros::Time& time, const M& message)
  {
    writeSerialized(topic, rosbag2TypeName(ros::message_traits::datatype<M>()),
                    static_cast<std::int64_t>(time.toNSec()), writeCdr(message));
  }
  /// A message already serialised as CDR, of ROS 2 type `type`.
  void writeSerialized(const std::string& topic, const std::string& type, std::int64_t time_ns,
                       const std::vector<std::uint8_t>& cdr);

  /// Indexes and closes the storage file (compressing it if asked), then writes metadata.yaml.
  void close();

private:
  std::string folder_, file_name_;
  bool zstd_;
  std::unique_ptr<SqliteDatabase> database_;
  std::unique_ptr<SqliteStatement> insert_;
  Rosbag2Metadata metadata_;  ///< its topics in id order (id = index + 1), counts, times
  std::int64_t last_ns_ = 0;
};

}  // namespace odometry_calibration
