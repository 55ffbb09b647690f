#include "odometry_calibration/bag_writers/rosbag2_sqlite_writer.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "odometry_calibration/bag/sqlite_database.h"
#include "odometry_calibration/bag/zstd_file.h"
#include "odometry_calibration/common/atomic_file.h"

namespace odometry_calibration {

std::string rosbag2TypeName(const std::string& ros1_type)
{
  const std::size_t slash = ros1_type.find('/');
  if (slash == std::string::npos || ros1_type.find('/', slash + 1) != std::string::npos)
    return ros1_type;
  return ros1_type.substr(0, slash) + "/msg" + ros1_type.substr(slash);
}

Rosbag2SqliteWriter::Rosbag2SqliteWriter(const std::string& folder, const std::string& name,
                                         bool zstd)
    : folder_(folder), file_name_(name + "_0.db3"), zstd_(zstd)
{
  const std::string path = (std::filesystem::path(folder) / file_name_).string();
  std::remove(path.c_str());
  database_ = std::make_unique<SqliteDatabase>(path, SqliteDatabase::Mode::kCreate);
  // One transaction and no journal: the folder is staged and only put in place complete.
  database_->execute("PRAGMA journal_mode=OFF");
  database_->execute(
      "CREATE TABLE topics(id INTEGER PRIMARY KEY, name TEXT NOT NULL, type TEXT NOT NULL, "
      "serialization_format TEXT NOT NULL, offered_qos_profiles TEXT NOT NULL)");
  database_->execute(
      "CREATE TABLE messages(id INTEGER PRIMARY KEY, topic_id INTEGER NOT NULL, "
      "timestamp INTEGER NOT NULL, data BLOB NOT NULL)");
  database_->execute("BEGIN");
  insert_ = std::make_unique<SqliteStatement>(
      *database_, "INSERT INTO messages(topic_id, timestamp, data) VALUES (?1, ?2, ?3)");
  metadata_.version = 5;
  metadata_.storage_identifier = "sqlite3";
  metadata_.starting_time_ns = 0;
}

Rosbag2SqliteWriter::~Rosbag2SqliteWriter() = default;

void Rosbag2SqliteWriter::writeSerialized(const std::string& topic, const std::string& type,
                                          std::int64_t time_ns,
                                          const std::vector<std::uint8_t>& cdr)
{
  auto known = std::find_if(metadata_.topics.begin(), metadata_.topics.end(),
                            [&](const Rosbag2Topic& t) { return t.name == topic; });
  if (known == metadata_.topics.end()) {
    SqliteStatement add(*database_,
                        "INSERT INTO topics(id, name, type, serialization_format, "
                        "offered_qos_profiles) VALUES (?1, ?2, ?3, 'cdr', '')");
    add.bind(1, static_cast<std::int64_t>(metadata_.topics.size() + 1));
    add.bind(2, topic);
    add.bind(3, type);
    add.step();
    metadata_.topics.push_back({topic, type, "cdr", 0});
    known = metadata_.topics.end() - 1;
  }
  insert_->bind(1, static_cast<std::int64_t>(known - metadata_.topics.begin() + 1));
  insert_->bind(2, time_ns);
  insert_->bindBlob(3, cdr.data(), cdr.size());
  insert_->step();
  insert_->reset();
  ++known->message_count;
  if (metadata_.message_count++ == 0 || time_ns < metadata_.starting_time_ns)
    metadata_.starting_time_ns = time_ns;
  last_ns_ = std::max(last_ns_, time_ns);
}

void Rosbag2SqliteWriter::close()
{
  insert_.reset();
  database_->execute("CREATE INDEX timestamp_idx ON messages (timestamp ASC)");
  database_->execute("COMMIT");
  const std::string path = database_->path();
  database_.reset();
  metadata_.duration_ns = metadata_.message_count > 0 ? last_ns_ - metadata_.starting_time_ns : 0;
  metadata_.relative_file_paths = {file_name_};
  if (zstd_) {
    compressZstdFile(path, path + ".zstd");
    std::remove(path.c_str());
    metadata_.relative_file_paths = {file_name_ + ".zstd"};
    metadata_.compression_format = "zstd";
    metadata_.compression_mode = "FILE";
  }
  writeFileAtomically((std::filesystem::path(folder_) / "metadata.yaml").string(),
                      rosbag2MetadataYaml(metadata_));
}

}  // namespace odometry_calibration
