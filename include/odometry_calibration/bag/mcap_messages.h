// The recorded messages of rosbag2 recordings in MCAP storage (recorded_messages.h), read
// without ROS 2: a bag folder whose metadata.yaml says storage_identifier mcap, or an .mcap file
// itself (mcap_file.h). Only the topics asked for are read, in record-time order, each
// message's CDR bytes deserialised (cdr_reader.h) straight from its chunk's buffer; the chunks
// are decompressed and checked a few ahead on a thread of their own (mcap_block_loader.h).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/bag/recorded_messages.h"

namespace odometry_calibration {

namespace mcap {
class BlockLoader;
class File;
struct Entry;
}  // namespace mcap

/// Whether `path` is an MCAP recording: a file ending in .mcap, or a bag folder whose
/// metadata.yaml says storage_identifier mcap.
bool isMcapPath(const std::string& path);

/// The messages of one or more MCAP files, merged in record-time order (a split bag's files one
/// after the other). Not copyable.
class McapMessages : public RecordedMessages
{
public:
  /// Opens `paths` (each as isMcapPath takes it) for the messages on `topics`. Throws
  /// std::runtime_error naming the file and the cause (mcap_file.h; a folder without a
  /// readable metadata.yaml, a whole-file compression this reader does not read).
  McapMessages(const std::vector<std::string>& paths, const std::vector<std::string>& topics);
  ~McapMessages() override;
  McapMessages(const McapMessages&) = delete;
  McapMessages& operator=(const McapMessages&) = delete;

  /// Whether the topics asked for hold any message; then the record times of their first and
  /// last one [ns since the epoch].
  bool empty() const { return first_ns_ > last_ns_; }
  std::int64_t firstTime_ns() const { return first_ns_; }
  std::int64_t lastTime_ns() const { return last_ns_; }
  /// Reads only the messages recorded within [begin_ns, end_ns] (call before the first next()).
  void restrictTo(std::int64_t begin_ns, std::int64_t end_ns);
  /// Every recorded topic in words, for a user choosing topic names:
  /// "'/odom' (nav_msgs/msg/Odometry, 920 messages), ...".
  std::string describeTopics() const;
  /// The topics asked for that no file records.
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
  std::vector<std::string> partialReads() const override;

  struct Open;  ///< a block being read

private:
  template <typename M>
  bool readAs(M& message);
  /// Opens the pending blocks that may hold the next message.
  void openPending();
  /// Starts loading the pending blocks in the order openPending takes them.
  void startLoading();

  std::vector<std::string> topics_;
  std::vector<std::unique_ptr<mcap::File>> files_;
  /// A block not opened yet: its file, its index there, its first message's record time.
  struct Pending
  {
    std::size_t file = 0, block = 0;
    std::int64_t first_ns = 0;
  };
  std::vector<Pending> pending_;               ///< latest first
  std::unique_ptr<mcap::BlockLoader> loader_;  ///< loads pending_ from its back
  std::vector<std::unique_ptr<Open>> open_;
  Open* current_ = nullptr;
  bool started_ = false;
  std::int64_t first_ns_ = 1, last_ns_ = 0;
  std::int64_t begin_ns_ = 0, end_ns_ = 0;
};

}  // namespace odometry_calibration
