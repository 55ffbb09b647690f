// Writes a rosbag2 bag folder in MCAP storage, as `ros2 bag record -s mcap` does:
// <folder>/<name>_0.mcap (profile ros2, CDR messages, schemas of encoding ros2msg, the records in
// chunks compressed with zstd or lz4 or not at all, a message index after each chunk, the
// summary with schemas, channels, statistics and chunk indexes, every CRC filled in) and
// metadata.yaml (storage_identifier mcap). The messages are the ROS 1 C++ types, serialised as
// their ROS 2 counterparts (cdr_writer.h). The schemas name their type; their definition text
// is left empty (this package has no ROS 2 message definitions to copy).
#pragma once

#include <cstdint>
#include <cstdio>
#include <map>
#include <string>
#include <vector>

#include <ros/message_traits.h>
#include <ros/time.h>

#include "odometry_calibration/bag/rosbag2_metadata.h"
#include "odometry_calibration/bag_writers/cdr_writer.h"
#include "odometry_calibration/bag_writers/rosbag2_sqlite_writer.h"

namespace odometry_calibration {

/// One bag folder being written. Not copyable.
class Rosbag2McapWriter
{
public:
  /// The uncompressed size at which a chunk is closed unless told otherwise [bytes].
  static constexpr std::size_t kDefaultChunkSize_bytes = 1 << 20;

  /// Starts writing into the existing folder `folder` the bag named `name` (its file
  /// "<name>_0.mcap"), chunks compressed with `compression`: "zstd", "lz4" or "none", each
  /// closed once its records reach `chunk_size_bytes` uncompressed. Throws std::runtime_error
  /// naming the file that cannot be created, std::invalid_argument for another compression.
  Rosbag2McapWriter(const std::string& folder, const std::string& name,
                    const std::string& compression = "zstd",
                    std::size_t chunk_size_bytes = kDefaultChunkSize_bytes);
  ~Rosbag2McapWriter();
  Rosbag2McapWriter(const Rosbag2McapWriter&) = delete;
  Rosbag2McapWriter& operator=(const Rosbag2McapWriter&) = delete;

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

  /// Writes the last chunk, the summary and the footer, closes the file, then writes
  /// metadata.yaml. Throws std::runtime_error when a write fails (a full disk).
  void close();

private:
  /// Appends `bytes` to the file (and to the running CRC of its data section).
  void put(const std::vector<std::uint8_t>& bytes);
  /// Compresses and writes the open chunk and its message indexes.
  void flushChunk();
  /// The summary section's records (schemas, channels, statistics, chunk indexes) and the
  /// summary offsets; returns where the offsets start.
  std::uint64_t writeSummary();

  std::string folder_, file_name_, path_, compression_;
  std::size_t chunk_size_bytes_;
  std::FILE* file_ = nullptr;
  std::uint64_t position_ = 0;                    ///< bytes written so far
  std::uint32_t crc_ = 0;                         ///< of every byte written so far
  std::vector<std::uint8_t> schemas_, channels_;  ///< their records, for the summary
  std::vector<std::uint8_t> chunk_;               ///< the open chunk's records
  std::int64_t chunk_start_ns_ = 0, chunk_end_ns_ = 0;
  /// The open chunk's messages per channel id: (record time, offset in the chunk).
  std::map<std::uint16_t, std::vector<std::pair<std::uint64_t, std::uint64_t>>> index_;
  std::vector<std::uint8_t> chunk_indexes_;  ///< their records, for the summary
  std::uint32_t chunk_count_ = 0;
  std::map<std::uint16_t, std::uint64_t> channel_counts_;
  Rosbag2Metadata metadata_;  ///< its topics in channel-id order (id = index + 1)
  std::int64_t last_ns_ = 0;
};

}  // namespace odometry_calibration
