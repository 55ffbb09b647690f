#include "odometry_calibration/bag/rosbag2_metadata.h"

#include <filesystem>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
constexpr int kNewestVersion = 9;

template <typename T>
T scalar(const YAML::Node& node, const T& fallback)
{
  return node && node.IsScalar() ? node.as<T>() : fallback;
}

std::vector<Rosbag2Topic> parseTopics(const YAML::Node& list)
{
  std::vector<Rosbag2Topic> topics;
  if (!list || !list.IsSequence())
    return topics;
  for (const YAML::Node& entry : list) {
    const YAML::Node metadata = entry["topic_metadata"];
    if (!metadata || !metadata.IsMap())
      throw std::runtime_error("a topic without its topic_metadata");
    Rosbag2Topic topic;
    topic.name = scalar<std::string>(metadata["name"], "");
    topic.type = scalar<std::string>(metadata["type"], "");
    topic.serialization_format = scalar<std::string>(metadata["serialization_format"], "");
    topic.message_count = scalar<std::uint64_t>(entry["message_count"], 0);
    topics.push_back(topic);
  }
  return topics;
}

Rosbag2Metadata parseInformation(const YAML::Node& info)
{
  Rosbag2Metadata metadata;
  metadata.version = scalar<int>(info["version"], 0);
  if (metadata.version < 1 || metadata.version > kNewestVersion) {
    throw std::runtime_error("version " + std::to_string(metadata.version) +
                             " is not one this tool reads (1 to " + std::to_string(kNewestVersion) +
                             ")");
  }
  metadata.storage_identifier = scalar<std::string>(info["storage_identifier"], "");
  const YAML::Node paths = info["relative_file_paths"];
  if (!paths || !paths.IsSequence() || paths.size() == 0)
    throw std::runtime_error("no relative_file_paths");
  for (const YAML::Node& path : paths)
    metadata.relative_file_paths.push_back(path.as<std::string>());
  metadata.compression_format = scalar<std::string>(info["compression_format"], "");
  metadata.compression_mode = scalar<std::string>(info["compression_mode"], "");
  // (A missing map must not be indexed: yaml-cpp throws for a key of an undefined node.)
  const YAML::Node starting_time = info["starting_time"], duration = info["duration"];
  if (starting_time && starting_time.IsMap())
    metadata.starting_time_ns = scalar<std::int64_t>(starting_time["nanoseconds_since_epoch"], 0);
  if (duration && duration.IsMap())
    metadata.duration_ns = scalar<std::int64_t>(duration["nanoseconds"], 0);
  metadata.message_count = scalar<std::uint64_t>(info["message_count"], 0);
  metadata.topics = parseTopics(info["topics_with_message_count"]);
  return metadata;
}

}  // namespace

Rosbag2Metadata parseRosbag2Metadata(const std::string& text, const std::string& path)
{
  try {
    const YAML::Node root = YAML::Load(text);
    const YAML::Node info = root.IsMap() ? root["rosbag2_bagfile_information"] : YAML::Node();
    if (!info || !info.IsMap())
      throw std::runtime_error("no rosbag2_bagfile_information");
    return parseInformation(info);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error("'" + path + "' is not a rosbag2 metadata file: " + error.what());
  } catch (const std::runtime_error& error) {
    throw std::runtime_error("'" + path +
                             "' is not a rosbag2 metadata file this tool reads: " + error.what());
  }
}

std::string rosbag2MetadataYaml(const Rosbag2Metadata& metadata)
{
  YAML::Emitter out;
  out << YAML::BeginMap << YAML::Key << "rosbag2_bagfile_information" << YAML::Value
      << YAML::BeginMap;
  out << YAML::Key << "version" << YAML::Value << metadata.version;
  out << YAML::Key << "storage_identifier" << YAML::Value << metadata.storage_identifier;
  out << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds"
      << YAML::Value << metadata.duration_ns << YAML::EndMap;
  out << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key
      << "nanoseconds_since_epoch" << YAML::Value << metadata.starting_time_ns << YAML::EndMap;
  out << YAML::Key << "message_count" << YAML::Value << metadata.message_count;
  out << YAML::Key << "topics_with_message_count" << YAML::Value << YAML::BeginSeq;
  for (const Rosbag2Topic& topic : metadata.topics) {
    out << YAML::BeginMap << YAML::Key << "topic_metadata" << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "name" << YAML::Value << topic.name << YAML::Key << "type" << YAML::Value
        << topic.type << YAML::Key << "serialization_format" << YAML::Value
        << topic.serialization_format << YAML::Key << "offered_qos_profiles" << YAML::Value
        << YAML::DoubleQuoted << "" << YAML::EndMap;
    out << YAML::Key << "message_count" << YAML::Value << topic.message_count << YAML::EndMap;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "compression_format" << YAML::Value << YAML::DoubleQuoted
      << metadata.compression_format;
  out << YAML::Key << "compression_mode" << YAML::Value << YAML::DoubleQuoted
      << metadata.compression_mode;
  out << YAML::Key << "relative_file_paths" << YAML::Value << metadata.relative_file_paths;
  if (metadata.version >= 5 && metadata.relative_file_paths.size() == 1) {  // one file: the bag
    out << YAML::Key << "files" << YAML::Value << YAML::BeginSeq << YAML::BeginMap;
    out << YAML::Key << "path" << YAML::Value << metadata.relative_file_paths.front();
    out << YAML::Key << "starting_time" << YAML::Value << YAML::BeginMap << YAML::Key
        << "nanoseconds_since_epoch" << YAML::Value << metadata.starting_time_ns << YAML::EndMap;
    out << YAML::Key << "duration" << YAML::Value << YAML::BeginMap << YAML::Key << "nanoseconds"
        << YAML::Value << metadata.duration_ns << YAML::EndMap;
    out << YAML::Key << "message_count" << YAML::Value << metadata.message_count;
    out << YAML::EndMap << YAML::EndSeq;
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

std::vector<std::string> rosbag2StorageFiles(const std::string& folder,
                                             const Rosbag2Metadata& metadata)
{
  std::vector<std::string> files;
  for (const std::string& relative : metadata.relative_file_paths) {
    // Version 4 on: relative to the folder; before: to its parent (the folder's name first).
    const fs::path candidates[] = {fs::path(folder) / relative,
                                   fs::path(folder).parent_path() / relative,
                                   fs::path(folder) / fs::path(relative).filename()};
    std::error_code error;
    const fs::path* found = nullptr;
    for (const fs::path& candidate : candidates) {
      if (!found && fs::is_regular_file(candidate, error))
        found = &candidate;
    }
    if (!found) {
      throw std::runtime_error("the bag folder '" + folder + "' lacks its storage file '" +
                               relative + "' (named in its metadata.yaml)");
    }
    files.push_back(found->string());
  }
  return files;
}

}  // namespace odometry_calibration
