// A rosbag2 bag folder's metadata.yaml (`rosbag2_bagfile_information`), as rosbag2 has written
// it since Foxy (versions 1 to 9): the storage, its files, their compression and the topics.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace odometry_calibration {

struct Rosbag2Topic
{
  std::string name;
  std::string type;  ///< as recorded: "sensor_msgs/msg/LaserScan"
  std::string serialization_format = "cdr";
  std::uint64_t message_count = 0;
};

struct Rosbag2Metadata
{
  int version = 5;
  std::string storage_identifier = "sqlite3";
  std::vector<std::string> relative_file_paths;
  std::string compression_format;  ///< "" or "zstd"
  std::string compression_mode;    ///< "", "FILE" or "MESSAGE"
  std::int64_t starting_time_ns = 0;
  std::int64_t duration_ns = 0;
  std::uint64_t message_count = 0;
  std::vector<Rosbag2Topic> topics;
};

/// Parses metadata.yaml's text (`path` names it in errors). Throws std::runtime_error for text
/// that is not a rosbag2 metadata file or a version above 9.
Rosbag2Metadata parseRosbag2Metadata(const std::string& text, const std::string& path);

/// `metadata` as metadata.yaml's text (from version 5 on with `files` for a bag of one file).
std::string rosbag2MetadataYaml(const Rosbag2Metadata& metadata);

/// The storage files of the bag folder `folder` in order, each found on disk: relative to the
/// folder (version 4 on) or, as versions 1 to 3 wrote them, to its parent. Throws
/// std::runtime_error naming a file that is missing.
std::vector<std::string> rosbag2StorageFiles(const std::string& folder,
                                             const Rosbag2Metadata& metadata);

}  // namespace odometry_calibration
