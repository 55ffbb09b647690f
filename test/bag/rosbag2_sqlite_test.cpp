// The rosbag2 SQLite reader and writer (rosbag2_sqlite_messages.h, rosbag2_sqlite_writer.h,
// rosbag2_metadata.h): metadata.yaml of the versions rosbag2 has written, bags written and read
// back (folder, .db3, zstd, split into files), and every bad input refused with a message naming
// the file.
#include <stdlib.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "odometry_calibration/bag/rosbag2_metadata.h"
#include "odometry_calibration/bag/rosbag2_sqlite_messages.h"
#include "odometry_calibration/bag_writers/rosbag2_sqlite_writer.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

class Rosbag2 : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/rosbag2_sqlite_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }
  void TearDown() override { fs::remove_all(directory_); }

  static ros::Time at(double t_s)
  {
    ros::Time time;
    time.fromNSec(1700000000000000000ull + static_cast<std::uint64_t>(std::llround(t_s * 1e9)));
    return time;
  }

  /// A bag folder `name` with joint states at 0, 0.1, ... and scans at 0.05, 0.15, ...
  /// (`count` each, from `start_s`), and a tf message the readers are not asked for.
  std::string writeBag(const std::string& name, bool zstd = false, int count = 5,
                       double start_s = 0.0)
  {
    const std::string folder = directory_ + "/" + name;
    fs::create_directory(folder);
    Rosbag2SqliteWriter writer(folder, name, zstd);
    for (int k = 0; k < count; ++k) {
      sensor_msgs::JointState joints;
      joints.header.stamp = at(start_s + 0.1 * k);
      joints.name = {"left", "right"};
      joints.position = {0.1 * k, -0.1 * k};
      writer.write("/joint_states", joints.header.stamp, joints);
      writer.write("/tf", joints.header.stamp, tf2_msgs::TFMessage());
      sensor_msgs::LaserScan scan;
      scan.header.stamp = at(start_s + 0.1 * k + 0.05);
      scan.header.frame_id = "laser";
      scan.ranges.assign(10, static_cast<float>(k));
      writer.write("/scan", scan.header.stamp, scan);
    }
    writer.close();
    return folder;
  }

  void writeText(const std::string& path, const std::string& text) { std::ofstream(path) << text; }

  std::string directory_;
};

const std::vector<std::string> kTopics = {"/joint_states", "/scan"};

/// The topics and record times of every message.
std::vector<std::pair<std::string, double>> walk(RecordedMessages& messages)
{
  std::vector<std::pair<std::string, double>> result;
  while (messages.next())
    result.emplace_back(messages.topic(), messages.recordTime_s());
  return result;
}

TEST_F(Rosbag2, ABagFolderIsReadInTimeOrderOnlyOnTheTopicsAskedFor)
{
  for (const bool zstd : {false, true}) {
    const std::string folder = writeBag(zstd ? "compressed" : "plain", zstd);
    EXPECT_TRUE(isRosbag2Path(folder));
    EXPECT_EQ(fs::exists(folder + "/" + (zstd ? "compressed_0.db3.zstd" : "plain_0.db3")), true);
    Rosbag2SqliteMessages messages({folder}, kTopics);
    ASSERT_FALSE(messages.empty());
    EXPECT_NEAR(messages.beginTime_s(), 1.7e9, 1e-6);
    EXPECT_NEAR(messages.endTime_s(), 1.7e9 + 0.45, 1e-6);
    int k = 0;
    for (; messages.next(); ++k) {
      EXPECT_EQ(messages.topic(), k % 2 == 0 ? "/joint_states" : "/scan");
      EXPECT_NEAR(messages.recordTime_s(), 1.7e9 + 0.05 * k, 1e-6);
      EXPECT_EQ(messages.publisher(), "");
      sensor_msgs::JointState joints;
      sensor_msgs::LaserScan scan;
      nav_msgs::Odometry odometry;
      EXPECT_FALSE(messages.read(odometry));
      if (k % 2 == 0) {
        ASSERT_TRUE(messages.read(joints));
        EXPECT_FALSE(messages.read(scan));
        EXPECT_EQ(joints.position, (std::vector<double>{0.1 * (k / 2), -0.1 * (k / 2)}));
        EXPECT_EQ(joints.header.stamp, at(0.1 * (k / 2)));
      } else {
        ASSERT_TRUE(messages.read(scan));
        EXPECT_EQ(scan.ranges, std::vector<float>(10, static_cast<float>(k / 2)));
        EXPECT_EQ(scan.header.frame_id, "laser");
      }
    }
    EXPECT_EQ(k, 10);
  }
}

TEST_F(Rosbag2, TheStorageFileAloneAndTheWindowAreRead)
{
  const std::string folder = writeBag("bag");
  EXPECT_TRUE(isRosbag2Path(folder + "/bag_0.db3"));
  Rosbag2SqliteMessages messages({folder + "/bag_0.db3"}, {"/scan"});
  messages.restrictTo(messages.firstTime_ns() + 100000000, messages.firstTime_ns() + 250000000);
  const auto read = walk(messages);
  ASSERT_EQ(read.size(), 2u);  // the scans at 0.15 and 0.25 (0.05 is the first)
  EXPECT_NEAR(read[0].second, 1.7e9 + 0.15, 1e-6);
}

TEST_F(Rosbag2, SplitAndSeveralBagsAreMergedInTimeOrder)
{
  // Two bags over the same time, interleaved: a split bag whose files overlap, and the same
  // bags given as two paths.
  const std::string a = writeBag("a", false, 5, 0.0);
  const std::string b = writeBag("b", true, 5, 0.02);
  const std::string split = directory_ + "/split";
  fs::create_directory(split);
  fs::copy_file(a + "/a_0.db3", split + "/split_0.db3");
  fs::copy_file(b + "/b_0.db3.zstd", split + "/split_1.db3.zstd");
  Rosbag2Metadata metadata;
  metadata.relative_file_paths = {"split_0.db3", "split_1.db3.zstd"};
  metadata.compression_format = "zstd";
  metadata.compression_mode = "FILE";
  writeText(split + "/metadata.yaml", rosbag2MetadataYaml(metadata));
  for (const std::vector<std::string>& paths :
       {std::vector<std::string>{split}, std::vector<std::string>{a, b}}) {
    Rosbag2SqliteMessages messages(paths, kTopics);
    const auto read = walk(messages);
    ASSERT_EQ(read.size(), 20u);
    for (std::size_t k = 1; k < read.size(); ++k)
      EXPECT_LE(read[k - 1].second, read[k].second) << k;
    EXPECT_NEAR(read[1].second - read[0].second, 0.02, 1e-6);
  }
}

TEST_F(Rosbag2, BothSpellingsOfATypeAreMatched)
{
  const std::string folder = directory_ + "/ros1_names";
  fs::create_directory(folder);
  Rosbag2SqliteWriter writer(folder, "ros1_names");
  sensor_msgs::LaserScan scan;
  scan.ranges = {1.0f};
  writer.writeSerialized("/scan", "sensor_msgs/LaserScan", 5, writeCdr(scan));
  writer.close();
  Rosbag2SqliteMessages messages({folder}, {"/scan"});
  ASSERT_TRUE(messages.next());
  sensor_msgs::LaserScan read;
  EXPECT_TRUE(messages.read(read));
  EXPECT_EQ(read.ranges, scan.ranges);
  EXPECT_EQ(rosbag2TypeName("sensor_msgs/LaserScan"), "sensor_msgs/msg/LaserScan");
}

/// Runs `statement` on the database `path`.
void runSql(const std::string& path, const std::string& statement)
{
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open(path.c_str(), &db), SQLITE_OK);
  EXPECT_EQ(sqlite3_exec(db, statement.c_str(), nullptr, nullptr, nullptr), SQLITE_OK)
      << sqlite3_errmsg(db);
  sqlite3_close(db);
}

TEST_F(Rosbag2, ACutMessageIsSkippableNamingTopicAndOffset)
{
  const std::string folder = writeBag("cut");
  runSql(folder + "/cut_0.db3",
         "UPDATE messages SET data = substr(data, 1, 30) WHERE id = (SELECT MIN(m.id) FROM "
         "messages m JOIN topics t ON t.id = m.topic_id WHERE t.name = '/scan')");
  Rosbag2SqliteMessages messages({folder}, {"/scan"});
  ASSERT_TRUE(messages.next());
  sensor_msgs::LaserScan scan;
  try {
    messages.read(scan);
    FAIL() << "a cut scan was read";
  } catch (const UnreadableMessage& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("'/scan'"), std::string::npos) << text;
    EXPECT_NE(text.find("cut off at byte"), std::string::npos) << text;
  }
  ASSERT_TRUE(messages.next());  // the next scan reads
  EXPECT_TRUE(messages.read(scan));
}

/// The text of the error opening `paths` throws ("" if none).
std::string openingError(const std::vector<std::string>& paths)
{
  try {
    Rosbag2SqliteMessages messages(paths, kTopics);
    walk(messages);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST_F(Rosbag2, BadInputIsRefusedNamingTheFileAndTheCause)
{
  auto expectError = [&](const std::string& path, const std::string& cause) {
    const std::string text = openingError({path});
    EXPECT_NE(text.find(path), std::string::npos) << text;
    EXPECT_NE(text.find(cause), std::string::npos) << text;
  };
  expectError(directory_ + "/missing.db3", "no rosbag2 file");
  writeText(directory_ + "/text.db3", std::string(5000, 'x'));
  expectError(directory_ + "/text.db3", "not an SQLite database");
  runSql(directory_ + "/empty.db3", "CREATE TABLE other(a INTEGER)");
  expectError(directory_ + "/empty.db3", "no such table: topics");
  writeText(directory_ + "/text.db3.zstd", "not zstd");
  expectError(directory_ + "/text.db3.zstd", "does not decompress");
  const std::string folder = writeBag("json");
  runSql(folder + "/json_0.db3", "UPDATE topics SET serialization_format = 'json'");
  expectError(folder + "/json_0.db3", "'/joint_states' is serialised as 'json'");
  // A folder whose metadata names a missing file, another storage, per-message compression.
  const std::string other = directory_ + "/other";
  fs::create_directory(other);
  expectError(other, "has no readable metadata.yaml");
  Rosbag2Metadata metadata;
  metadata.relative_file_paths = {"gone_0.db3"};
  writeText(other + "/metadata.yaml", rosbag2MetadataYaml(metadata));
  expectError(other, "lacks its storage file 'gone_0.db3'");
  metadata.storage_identifier = "mcap";
  writeText(other + "/metadata.yaml", rosbag2MetadataYaml(metadata));
  expectError(other, "is stored as 'mcap'; SQLite (sqlite3) and MCAP (mcap) storage are read");
  metadata.storage_identifier = "sqlite3";
  metadata.compression_mode = "MESSAGE";
  metadata.compression_format = "zstd";
  writeText(other + "/metadata.yaml", rosbag2MetadataYaml(metadata));
  expectError(other, "compressed per message");
  writeText(other + "/metadata.yaml", "rosbag2_bagfile_information: [1, 2");
  const std::string text = openingError({other});
  EXPECT_NE(text.find(other + "/metadata.yaml' is not a rosbag2 metadata file"), std::string::npos)
      << text;
}

TEST(Rosbag2Metadata, TheVersionsWrittenSinceFoxyAreParsed)
{
  // Version 1-3 named the files with the folder first; 4 on relative to the folder; 5 added
  // `files`, 6 custom_data, 7 type_description_hash, 8 ros_distro, 9 offered_qos as a list.
  const std::string topics = R"(
  topics_with_message_count:
    - topic_metadata:
        name: /scan
        type: sensor_msgs/msg/LaserScan
        serialization_format: cdr
        offered_qos_profiles: ""
      message_count: 355
)";
  const std::string v1 =
      "rosbag2_bagfile_information:\n  version: 1\n  storage_identifier: "
      "sqlite3\n  relative_file_paths: [bag/bag_0.db3]\n  message_count: 355\n" +
      topics;
  Rosbag2Metadata m = parseRosbag2Metadata(v1, "v1");
  EXPECT_EQ(m.version, 1);
  EXPECT_EQ(m.relative_file_paths, std::vector<std::string>{"bag/bag_0.db3"});
  ASSERT_EQ(m.topics.size(), 1u);
  EXPECT_EQ(m.topics[0].type, "sensor_msgs/msg/LaserScan");
  EXPECT_EQ(m.topics[0].message_count, 355u);
  const std::string v4 =
      "rosbag2_bagfile_information:\n  version: 4\n  storage_identifier: sqlite3\n"
      "  relative_file_paths: [bag_0.db3.zstd, bag_1.db3.zstd]\n  duration: {nanoseconds: "
      "46000000000}\n"
      "  starting_time: {nanoseconds_since_epoch: 1700000000000000000}\n  message_count: 9\n"
      "  compression_format: zstd\n  compression_mode: FILE\n" +
      topics;
  m = parseRosbag2Metadata(v4, "v4");
  EXPECT_EQ(m.relative_file_paths.size(), 2u);
  EXPECT_EQ(m.compression_format, "zstd");
  EXPECT_EQ(m.compression_mode, "FILE");
  EXPECT_EQ(m.duration_ns, 46000000000);
  EXPECT_EQ(m.starting_time_ns, 1700000000000000000);
  const std::string v9 =
      "rosbag2_bagfile_information:\n  version: 9\n  storage_identifier: sqlite3\n"
      "  relative_file_paths: [bag_0.db3]\n  files:\n    - path: bag_0.db3\n      message_count: "
      "9\n"
      "  custom_data: {}\n  ros_distro: jazzy\n  compression_format: \"\"\n  compression_mode: "
      "\"\"\n" +
      topics;
  m = parseRosbag2Metadata(v9, "v9");
  EXPECT_EQ(m.version, 9);
  EXPECT_EQ(m.compression_format, "");
  // What this writer writes reads back.
  const Rosbag2Metadata again = parseRosbag2Metadata(rosbag2MetadataYaml(m), "again");
  EXPECT_EQ(again.relative_file_paths, m.relative_file_paths);
  EXPECT_EQ(again.topics.size(), 1u);
  EXPECT_THROW(parseRosbag2Metadata("rosbag2_bagfile_information:\n  version: 10\n  "
                                    "relative_file_paths: [a.db3]\n",
                                    "v10"),
               std::runtime_error);
  EXPECT_THROW(parseRosbag2Metadata("other: 1", "other"), std::runtime_error);
  EXPECT_THROW(parseRosbag2Metadata("rosbag2_bagfile_information:\n  version: 5\n", "no files"),
               std::runtime_error);
}

TEST_F(Rosbag2, OldVersionsFindFilesNamedWithTheirFolder)
{
  const std::string folder = writeBag("old");
  Rosbag2Metadata metadata;
  metadata.version = 3;
  metadata.relative_file_paths = {"old/old_0.db3"};
  EXPECT_EQ(rosbag2StorageFiles(folder, metadata),
            std::vector<std::string>{(fs::path(directory_) / "old/old_0.db3").string()});
}

}  // namespace
}  // namespace odometry_calibration
