// The recorded messages of rosbag2 recordings in SQLite storage (recorded_messages.h), read
// without ROS 2: a bag folder (metadata.yaml and its .db3 or .db3.zstd files), or a storage
// file itself. Only the topics asked for are read, in record-time order, each message's CDR
// bytes deserialised (cdr_reader.h) straight from SQLite's buffer.
#pragma once

#include <cstddef>
#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/bag/recorded_messages.h"

namespace odometry_calibration {

/// Whether `path` is to be read as a rosbag2 recording: a folder (a bag folder holds
/// metadata.yaml), or a file ending in .db3, .db3.zstd or .mcap (MCAP storage is read by
/// mcap_messages.h).
bool isRosbag2Path(const std::string& path);

/// The messages of one or more rosbag2 recordings, their storage files merged in record-time
/// order (a split bag's files one after the other). Not copyable.
class Rosbag2SqliteMessages : public RecordedMessages
{
public:
  /// Opens `paths` (each as isRosbag2Path takes it) for the messages on `topics`. Throws
  /// std::runtime_error naming the file and the cause: missing, not SQLite, no rosbag2 tables,
  /// corrupted, a topic asked for that is not CDR-serialised, a storage or compression this
  /// reader does not read.
  Rosbag2SqliteMessages(const std::vector<std::string>& paths,
                        const std::vector<std::string>& topics);
  ~Rosbag2SqliteMessages() override;
  Rosbag2SqliteMessages(const Rosbag2SqliteMessages&) = delete;
  Rosbag2SqliteMessages& operator=(const Rosbag2SqliteMessages&) = delete;

  /// Whether the topics asked for hold any message; then the record times of their first and
  /// last one [ns since the epoch].
  bool empty() const { return first_ns_ > last_ns_; }
  std::int64_t firstTime_ns() const { return first_ns_; }
  std::int64_t lastTime_ns() const { return last_ns_; }
  /// Reads only the messages recorded within [begin_ns, end_ns] (call before the first next()).
  void restrictTo(std::int64_t begin_ns, std::int64_t end_ns);
  /// Every recorded topic in words, for a user choosing topic names:
  /// "'/odom' (nav_msgs/msg/Odometry, 920 messages), ..." (counts every storage file's rows).
  std::string describeTopics() const;
  /// The topics asked for that no storage file records.
  std::vector<std::string> missingTopics() const;

  double beginTime_s() const override;
  double endTime_s() const override;
  bool next() override;
  const std::string& topic() const override;
  double recordTime_s() const override;
  /// Empty: rosbag2 does not record the publishing node.
  std::string publisher() const override;
  /// Throw UnreadableMessage for a message whose CDR bytes do not hold its type.
  bool read(sensor_msgs::JointState& message) override;
  bool read(sensor_msgs::LaserScan& message) override;
  bool read(sensor_msgs::PointCloud2& message) override;
  bool read(nav_msgs::Odometry& message) override;
  bool read(geometry_msgs::PoseStamped& message) override;
  bool read(sensor_msgs::Imu& message) override;
  bool readWheelTick(const std::string& type, double& value) override;

  struct Storage;  ///< one open storage file

private:
  /// The current message as M (cdr_layout.h's types) when its topic's type is M's.
  template <typename M>
  bool readAs(M& message);

  std::vector<std::string> topics_;  ///< asked for
  std::vector<std::unique_ptr<Storage>> storages_;
  Storage* current_ = nullptr;
  bool started_ = false;
  std::int64_t first_ns_ = 1, last_ns_ = 0;
  std::int64_t begin_ns_ = 0, end_ns_ = 0;
};

}  // namespace odometry_calibration
