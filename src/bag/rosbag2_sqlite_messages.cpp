#include "odometry_calibration/bag/rosbag2_sqlite_messages.h"

#include <stdlib.h>
#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/bag/cdr_reader.h"
#include "odometry_calibration/bag/rosbag2_metadata.h"
#include "odometry_calibration/bag/sqlite_database.h"
#include "odometry_calibration/bag/zstd_file.h"
#include "odometry_calibration/ros/wheel_tick_messages.h"

namespace odometry_calibration {

namespace fs = std::filesystem;

/// One storage file: its topics, and the query walking its messages on the topics asked for.
struct Rosbag2SqliteMessages::Storage
{
  struct Topic
  {
    std::int64_t id = 0;
    std::string name;
    std::string type;  ///< "sensor_msgs/LaserScan" (ROS 1's spelling, "/msg/" dropped)
  };
  std::string path;  ///< as the user named it (the .db3 or .db3.zstd)
  std::unique_ptr<SqliteDatabase> database;
  std::vector<Topic> topics;  ///< the topics asked for that the file records
  std::string topic_ids;      ///< their ids, "1, 3" (for the queries)
  std::unique_ptr<SqliteStatement> rows;
  // The current row (valid while `has_row`; `data` until the next step).
  bool has_row = false;
  std::int64_t time_ns = 0;
  const Topic* topic = nullptr;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
};

namespace {

using Storage = Rosbag2SqliteMessages::Storage;

bool endsWith(const std::string& text, const std::string& end)
{
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

/// "sensor_msgs/msg/LaserScan" as ROS 1 spells it, "sensor_msgs/LaserScan".
std::string ros1TypeName(const std::string& type)
{
  const std::size_t slash = type.find('/');
  if (slash != std::string::npos && type.compare(slash, 5, "/msg/") == 0)
    return type.substr(0, slash) + type.substr(slash + 4);
  return type;
}

/// The topics table's entries among `wanted`; a wanted topic not serialised as CDR refused.
void loadTopics(Storage& storage, const std::vector<std::string>& wanted)
{
  SqliteStatement query(*storage.database,
                        "SELECT id, name, type, serialization_format FROM topics");
  while (query.step()) {
    const std::string name = query.text(1);
    if (std::find(wanted.begin(), wanted.end(), name) == wanted.end())
      continue;
    const std::string format = query.text(3);
    if (format != "cdr") {
      throw std::runtime_error("rosbag2 file '" + storage.path + "': topic '" + name +
                               "' is serialised as '" + format + "'; only 'cdr' is read");
    }
    storage.topics.push_back({query.integer(0), name, ros1TypeName(query.text(2))});
    storage.topic_ids += (storage.topic_ids.empty() ? "" : ", ") + std::to_string(query.integer(0));
  }
  // The messages table checked now, so that a file without one fails at opening.
  SqliteStatement check(*storage.database,
                        "SELECT topic_id, timestamp, data FROM messages LIMIT 1");
  check.step();
}

/// `path` decompressed into a temporary file; returns its path.
std::string decompressed(const std::string& path)
{
  std::string temporary = (fs::temp_directory_path() / "odometry_calibration_db3.XXXXXX").string();
  const int fd = ::mkstemp(temporary.data());
  if (fd < 0)
    throw std::runtime_error("no temporary file to decompress '" + path + "' into");
  ::close(fd);
  try {
    decompressZstdFile(path, temporary);
  } catch (...) {
    std::remove(temporary.c_str());
    throw;
  }
  return temporary;
}

/// Refuses an SQLite file `file` (named `name`) shorter than its header says: a copy cut short
/// would otherwise read as a database with fewer rows. (The header's page count is valid only
/// when its version-valid-for number equals its change counter; else SQLite goes by the file.)
void requireWholeFile(const std::string& file, const std::string& name)
{
  std::ifstream in(file, std::ios::binary);
  unsigned char header[100] = {};
  if (!in.read(reinterpret_cast<char*>(header), sizeof(header)) ||
      std::memcmp(header, "SQLite format 3", 16) != 0)
    return;  // SQLite names what is wrong
  auto be32 = [&](int at) {
    return static_cast<std::uint32_t>(header[at]) << 24 | header[at + 1] << 16 |
           header[at + 2] << 8 | header[at + 3];
  };
  const std::uint32_t page_size = header[16] == 0 && header[17] == 1
                                      ? 65536u
                                      : static_cast<std::uint32_t>(header[16] << 8 | header[17]);
  const std::uint64_t pages = be32(28);
  if (pages == 0 || be32(92) != be32(24))
    return;
  const std::uint64_t expected = pages * page_size;
  const std::uint64_t size = fs::file_size(file);
  if (size < expected) {
    throw std::runtime_error("rosbag2 file '" + name + "' is cut off: its header says " +
                             std::to_string(pages) + " pages of " + std::to_string(page_size) +
                             " bytes (" + std::to_string(expected) + " bytes), it holds " +
                             std::to_string(size));
  }
}

/// Opens the storage file `path` (.db3, or .db3.zstd decompressed first) for `topics`.
std::unique_ptr<Storage> openStorage(const std::string& path,
                                     const std::vector<std::string>& topics)
{
  std::error_code error;
  if (!fs::is_regular_file(path, error))
    throw std::runtime_error("no rosbag2 file '" + path + "'");
  auto storage = std::make_unique<Storage>();
  storage->path = path;
  if (endsWith(path, ".zstd")) {
    const std::string temporary = decompressed(path);
    try {
      requireWholeFile(temporary, path);
      storage->database = std::make_unique<SqliteDatabase>(temporary, SqliteDatabase::Mode::kRead);
    } catch (...) {
      std::remove(temporary.c_str());
      throw;
    }
    // Opened immutable (no locks, no journal): the open descriptor keeps the data readable.
    std::remove(temporary.c_str());
  } else {
    requireWholeFile(path, path);
    storage->database = std::make_unique<SqliteDatabase>(path, SqliteDatabase::Mode::kRead);
  }
  try {
    // Read through a memory map: no copy of each page into SQLite's cache (up to SQLite's
    // limit, 2 GB by default; beyond it, ordinary reads).
    storage->database->execute("PRAGMA mmap_size = 2147418112");
    loadTopics(*storage, topics);
  } catch (const std::runtime_error& error) {
    // Errors on the decompressed copy name the file the user gave.
    std::string text = error.what();
    const std::string copy = "'" + storage->database->path() + "'";
    if (const std::size_t at = text.find(copy); at != std::string::npos)
      text.replace(at, copy.size(), "'" + path + "'");
    throw std::runtime_error(text);
  }
  return storage;
}

/// A bag folder's storage files, its metadata.yaml checked for what this reader reads.
std::vector<std::string> folderFiles(const std::string& folder)
{
  const std::string metadata_path = (fs::path(folder) / "metadata.yaml").string();
  std::ifstream file(metadata_path);
  if (!file)
    throw std::runtime_error("the folder '" + folder + "' has no readable metadata.yaml");
  std::stringstream text;
  text << file.rdbuf();
  const Rosbag2Metadata metadata = parseRosbag2Metadata(text.str(), metadata_path);
  if (metadata.storage_identifier != "sqlite3" && !metadata.storage_identifier.empty()) {
    throw std::runtime_error("the bag '" + folder + "' is stored as '" +
                             metadata.storage_identifier +
                             "'; SQLite (sqlite3) and MCAP (mcap) storage are read (convert it "
                             "with 'ros2 bag convert' to one of them)");
  }
  if (metadata.compression_mode == "MESSAGE" ||
      (!metadata.compression_format.empty() && metadata.compression_format != "zstd")) {
    throw std::runtime_error("the bag '" + folder + "' is compressed per " +
                             (metadata.compression_mode == "MESSAGE" ? "message" : "file") +
                             " with '" + metadata.compression_format +
                             "'; only uncompressed and zstd FILE-compressed bags are read");
  }
  return rosbag2StorageFiles(folder, metadata);
}

/// Steps `storage` to its next row; false after its last.
bool advance(Storage& storage)
{
  while ((storage.has_row = storage.rows && storage.rows->step())) {
    const std::int64_t id = storage.rows->integer(0);
    storage.topic = nullptr;
    for (const Storage::Topic& topic : storage.topics) {
      if (topic.id == id)
        storage.topic = &topic;
    }
    if (!storage.topic)
      continue;  // not asked for (the query already leaves these out)
    storage.time_ns = storage.rows->integer(1);
    storage.data = storage.rows->blob(2, storage.size);
    return true;
  }
  return false;
}

/// The first or last record time (`order` ASC or DESC) of `storage`'s topics; false: none.
bool edgeTime(const Storage& storage, const char* order, std::int64_t& time_ns)
{
  if (storage.topics.empty())
    return false;
  SqliteStatement query(*storage.database, "SELECT timestamp FROM messages WHERE topic_id IN (" +
                                               storage.topic_ids + ") ORDER BY timestamp " + order +
                                               " LIMIT 1");
  if (!query.step())
    return false;
  time_ns = query.integer(0);
  return true;
}

}  // namespace

bool isRosbag2Path(const std::string& path)
{
  std::error_code error;
  if (fs::is_directory(path, error))
    return true;  // a bag folder (one without metadata.yaml is refused, saying so)
  return endsWith(path, ".db3") || endsWith(path, ".db3.zstd") || endsWith(path, ".mcap");
}

Rosbag2SqliteMessages::Rosbag2SqliteMessages(const std::vector<std::string>& paths,
                                             const std::vector<std::string>& topics)
    : topics_(topics)
{
  for (const std::string& path : paths) {
    std::error_code error;
    const std::vector<std::string> files =
        fs::is_directory(path, error) ? folderFiles(path) : std::vector<std::string>{path};
    for (const std::string& file : files)
      storages_.push_back(openStorage(file, topics));
  }
  for (const auto& storage : storages_) {
    std::int64_t first_ns = 0, last_ns = 0;
    if (edgeTime(*storage, "ASC", first_ns) && edgeTime(*storage, "DESC", last_ns)) {
      first_ns_ = empty() ? first_ns : std::min(first_ns_, first_ns);
      last_ns_ = empty() ? last_ns : std::max(last_ns_, last_ns);
    }
  }
  begin_ns_ = first_ns_;
  end_ns_ = last_ns_;
}

Rosbag2SqliteMessages::~Rosbag2SqliteMessages() = default;

void Rosbag2SqliteMessages::restrictTo(std::int64_t begin_ns, std::int64_t end_ns)
{
  begin_ns_ = begin_ns;
  end_ns_ = end_ns;
}

std::string Rosbag2SqliteMessages::describeTopics() const
{
  std::string text;
  for (const auto& storage : storages_) {
    SqliteStatement query(*storage->database,
                          "SELECT t.name, t.type, COUNT(m.id) FROM topics t LEFT JOIN messages m "
                          "ON m.topic_id = t.id GROUP BY t.id ORDER BY t.name");
    while (query.step()) {
      text += (text.empty() ? "'" : ", '") + query.text(0) + "' (" + query.text(1) + ", " +
              std::to_string(query.integer(2)) + " messages)";
    }
  }
  return text.empty() ? "none" : text;
}

std::vector<std::string> Rosbag2SqliteMessages::missingTopics() const
{
  std::vector<std::string> missing;
  for (const std::string& topic : topics_) {
    bool recorded = false;
    for (const auto& storage : storages_) {
      for (const Storage::Topic& t : storage->topics)
        recorded = recorded || t.name == topic;
    }
    if (!recorded && std::find(missing.begin(), missing.end(), topic) == missing.end())
      missing.push_back(topic);
  }
  return missing;
}

double Rosbag2SqliteMessages::beginTime_s() const
{
  return static_cast<double>(begin_ns_) * 1e-9;
}

double Rosbag2SqliteMessages::endTime_s() const
{
  return static_cast<double>(end_ns_) * 1e-9;
}

bool Rosbag2SqliteMessages::next()
{
  if (!started_) {
    started_ = true;
    for (const auto& storage : storages_) {
      if (storage->topics.empty())
        continue;
      storage->rows = std::make_unique<SqliteStatement>(
          *storage->database,
          "SELECT topic_id, timestamp, data FROM messages WHERE topic_id IN (" +
              storage->topic_ids +
              ") AND timestamp >= ?1 AND timestamp <= ?2 ORDER BY timestamp, id");
      storage->rows->bind(1, begin_ns_);
      storage->rows->bind(2, end_ns_);
      advance(*storage);
    }
  } else if (current_) {
    advance(*current_);
  }
  // The earliest current row of all files (the first file's on a tie).
  current_ = nullptr;
  for (const auto& storage : storages_) {
    if (storage->has_row && (!current_ || storage->time_ns < current_->time_ns))
      current_ = storage.get();
  }
  return current_ != nullptr;
}

const std::string& Rosbag2SqliteMessages::topic() const
{
  return current_->topic->name;
}

double Rosbag2SqliteMessages::recordTime_s() const
{
  return static_cast<double>(current_->time_ns) * 1e-9;
}

std::string Rosbag2SqliteMessages::publisher() const
{
  return "";
}

template <typename M>
bool Rosbag2SqliteMessages::readAs(M& message)
{
  if (current_->topic->type != ros::message_traits::datatype<M>())
    return false;
  try {
    readCdr(current_->data, current_->size, message);
  } catch (const CdrError& error) {
    throw UnreadableMessage("a message on '" + current_->topic->name + "' recorded at " +
                            std::to_string(recordTime_s()) + " s in '" + current_->path +
                            "' is skipped: " + error.what());
  }
  return true;
}

bool Rosbag2SqliteMessages::read(sensor_msgs::JointState& message)
{
  return readAs(message);
}

bool Rosbag2SqliteMessages::read(sensor_msgs::LaserScan& message)
{
  return readAs(message);
}

bool Rosbag2SqliteMessages::read(sensor_msgs::PointCloud2& message)
{
  return readAs(message);
}

bool Rosbag2SqliteMessages::read(nav_msgs::Odometry& message)
{
  return readAs(message);
}

bool Rosbag2SqliteMessages::read(geometry_msgs::PoseStamped& message)
{
  return readAs(message);
}

bool Rosbag2SqliteMessages::read(sensor_msgs::Imu& message)
{
  return readAs(message);
}

bool Rosbag2SqliteMessages::readWheelTick(const std::string& type, double& value)
{
  return visitWheelTickType(type, [&](auto message) {
    if (!readAs(message))
      return false;
    value = static_cast<double>(message.data);
    return true;
  });
}

}  // namespace odometry_calibration
