// checkBagRecords on well-formed bags of each compression (every message indexed, nothing
// refused) and on bags with one length or index entry changed (refused, naming where), and the
// bag reader's length check of a message whose array count was corrupted inside its bytes.
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

#include "odometry_calibration/bag/bag_record_check.h"
#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/config/calibration_config.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
using test_support::readFile;

constexpr int kJointStates = 200;
constexpr int kScans = 40;

class BagRecordCheck : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/bag_record_check_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// A bag of JointStates at 50 Hz and LaserScans at 10 Hz, in chunks of about 8 KiB (so that
  /// there are many).
  std::string writeBag(const std::string& name, rosbag::CompressionType compression)
  {
    const std::string path = directory_ + "/" + name;
    rosbag::Bag bag(path, rosbag::bagmode::Write);
    bag.setCompression(compression);
    bag.setChunkThreshold(8 * 1024);
    const ros::Time start(1700000000.0);
    for (int i = 0; i < kJointStates; ++i) {
      sensor_msgs::JointState joints;
      joints.header.stamp = start + ros::Duration(0.02 * i);
      joints.name = {"left_wheel_joint", "right_wheel_joint"};
      joints.position = {0.01 * i, 0.012 * i};
      bag.write("/joint_states", joints.header.stamp, joints);
      if (i % 5 == 0) {
        sensor_msgs::LaserScan scan;
        scan.header.stamp = joints.header.stamp;
        scan.header.frame_id = "laser";
        scan.angle_min = -1.5f;
        scan.angle_increment = 0.01f;
        scan.angle_max = scan.angle_min + 299 * scan.angle_increment;
        scan.range_min = 0.1f;
        scan.range_max = 10.0f;
        scan.ranges.assign(300, 2.0f);
        bag.write("/scan", scan.header.stamp, scan);
      }
    }
    bag.close();
    return path;
  }

  /// Writes `bytes` as `name` in the test's folder.
  std::string write(const std::string& name, const std::string& bytes)
  {
    const std::string path = directory_ + "/" + name;
    std::ofstream(path, std::ios::binary) << bytes;
    return path;
  }

  /// What checkBagRecords says of `bytes` written as `name`; "" when it takes them.
  std::string checkError(const std::string& name, const std::string& bytes)
  {
    try {
      checkBagRecords(write(name, bytes));
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  }

  /// What runBags (diff_drive.yaml) says of `bytes` written as `name`; "" when it reads them.
  std::string runError(const std::string& name, const std::string& bytes)
  {
    const CalibrationConfig config =
        loadCalibrationConfig(std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/diff_drive.yaml");
    try {
      runBags({write(name, bytes)}, config);
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  }

  static std::uint32_t u32(const std::string& bytes, std::size_t at)
  {
    std::uint32_t value = 0;
    std::memcpy(&value, bytes.data() + at, 4);
    return value;
  }
  static void setU32(std::string& bytes, std::size_t at, std::uint32_t value)
  {
    std::memcpy(&bytes[at], &value, 4);
  }

  /// The start of the first message data record: its header fields are sorted by name, so
  /// "conn" (4 + 9 bytes) comes right before "op" = 0x02.
  static std::size_t firstMessageRecord(const std::string& bytes)
  {
    const std::size_t op = bytes.find(std::string("\x04\0\0\0op=\x02", 8));
    EXPECT_NE(op, std::string::npos);
    return op - 13 - 4;
  }

  std::string directory_;
};

TEST_F(BagRecordCheck, WellFormedBagsOfEachCompressionPass)
{
  for (const auto& [name, compression] : {std::pair{"none.bag", rosbag::compression::Uncompressed},
                                          std::pair{"bz2.bag", rosbag::compression::BZ2},
                                          std::pair{"lz4.bag", rosbag::compression::LZ4}}) {
    const BagRecordCheckSummary summary = checkBagRecords(writeBag(name, compression));
    EXPECT_GT(summary.chunks, 5u) << name;
    EXPECT_EQ(summary.index_entries, std::uint64_t{kJointStates + kScans}) << name;
    // The chunks hold the messages and, where a topic first appears, its connection record.
    EXPECT_EQ(summary.records, summary.index_entries + 2) << name;
  }
}

TEST_F(BagRecordCheck, MessageLengthBeyondItsChunkIsRefused)
{
  std::string bytes = readFile(writeBag("clean.bag", rosbag::compression::Uncompressed));
  const std::size_t record = firstMessageRecord(bytes);
  const std::size_t data_length = record + 4 + u32(bytes, record);
  setU32(bytes, data_length, 0xFFFFFF00u);
  const std::string error = checkError("long.bag", bytes);
  EXPECT_NE(error.find("chunk at byte 4117: record at chunk offset"), std::string::npos) << error;
  EXPECT_NE(error.find("claims 4294967040 data bytes"), std::string::npos) << error;
}

TEST_F(BagRecordCheck, IndexEntryOffTheRecordStartsIsRefused)
{
  std::string bytes = readFile(writeBag("clean.bag", rosbag::compression::Uncompressed));
  // The first index record: its last header field is "ver" (4 + 8 bytes), then the data length,
  // then entries of uint32 sec, nsec, offset.
  const std::size_t op = bytes.find(std::string("\x04\0\0\0op=\x04", 8));
  ASSERT_NE(op, std::string::npos);
  const std::size_t ver = bytes.find(std::string("\x08\0\0\0ver=", 8), op);
  ASSERT_NE(ver, std::string::npos);
  const std::size_t first_offset = ver + 12 + 4 + 8;
  setU32(bytes, first_offset, u32(bytes, first_offset) + 1);
  const std::string error = checkError("index.bag", bytes);
  EXPECT_NE(error.find("entry 0 points at chunk offset"), std::string::npos) << error;
  // The same bag with the entry restored passes: the change above was all that was wrong.
  setU32(bytes, first_offset, u32(bytes, first_offset) - 1);
  EXPECT_EQ(checkBagRecords(write("restored.bag", bytes)).index_entries,
            std::uint64_t{kJointStates + kScans});
}

TEST_F(BagRecordCheck, CorruptedArrayCountInsideAMessageIsReportedNotAllocated)
{
  std::string bytes = readFile(writeBag("clean.bag", rosbag::compression::Uncompressed));
  // The first message is a JointState: header (seq, stamp, empty frame_id) = 16 bytes, then
  // the count of its names. 2^31 names of at least 4 bytes each: 8 GiB had roscpp believed it.
  const std::size_t record = firstMessageRecord(bytes);
  const std::size_t data = record + 4 + u32(bytes, record) + 4;
  ASSERT_EQ(u32(bytes, data + 16), 2u);
  setU32(bytes, data + 16, 0x7FFFFFFFu);
  EXPECT_EQ(checkError("count.bag", bytes), "");  // the records are intact; the message is not
  const std::string error = runError("count.bag", bytes);
  EXPECT_NE(error.find("count.bag"), std::string::npos) << error;
  EXPECT_NE(error.find("sensor_msgs/JointState message on '/joint_states' at 1700000000.0"),
            std::string::npos)
      << error;
  EXPECT_NE(error.find("claims strings or arrays longer than its"), std::string::npos) << error;
}

TEST_F(BagRecordCheck, HeaderFieldBeyondItsHeaderIsRefusedBeforeRosbagOpensTheBag)
{
  // rosbag's open parses the bag header record with ros::Header::parse, which copies each
  // field's claimed length unchecked (found by the bag fuzz target: heap-buffer-overflow).
  std::string bytes = readFile(writeBag("clean.bag", rosbag::compression::Uncompressed));
  const std::size_t first_field = 13 + 4;  // after "#ROSBAG V2.0\n" and the header length
  setU32(bytes, first_field, 219);
  const std::string error = runError("field.bag", bytes);
  EXPECT_NE(error.find("field.bag' is corrupted or cut off: the bag header record has a header "
                       "field of 219 bytes"),
            std::string::npos)
      << error;
}

TEST_F(BagRecordCheck, ConnectionHeaderFieldBeyondItsDataIsRefused)
{
  // The connection records' data is a header too (topic, type, md5sum, message_definition).
  std::string bytes = readFile(writeBag("clean.bag", rosbag::compression::Uncompressed));
  const std::size_t type = bytes.find(std::string("\x1b\0\0\0type=sensor_msgs/JointState", 31));
  ASSERT_NE(type, std::string::npos);
  setU32(bytes, type, 0x10000);
  const std::string error = checkError("connection.bag", bytes);
  EXPECT_NE(error.find("has a connection header field of 65536 bytes"), std::string::npos) << error;
}

TEST_F(BagRecordCheck, NotABagAndUnindexedBagsAreRefused)
{
  EXPECT_NE(checkError("text.bag", "#ROSBAG V3.0\nnothing").find("#ROSBAG V2.0"),
            std::string::npos);
  EXPECT_THROW(checkBagRecords(directory_ + "/missing.bag"), std::runtime_error);
  // rosbag's reader of format 1.2 allocates the header lengths it reads (4 GB, found by the bag
  // fuzz target): such bags are refused with the way to convert them.
  const std::string old_format = checkError("old.bag", "#ROSBAG V1.2\n\xff\xff\xff\xff");
  EXPECT_NE(old_format.find("format 1.2"), std::string::npos) << old_format;
  EXPECT_NE(old_format.find("rosbag filter"), std::string::npos) << old_format;
  std::string bytes = readFile(writeBag("clean.bag", rosbag::compression::Uncompressed));
  const std::size_t field = bytes.find("index_pos=");
  ASSERT_NE(field, std::string::npos);
  for (std::size_t i = 0; i < 8; ++i)
    bytes[field + 10 + i] = '\0';
  const std::string error = checkError("unindexed.bag", bytes);
  EXPECT_NE(error.find("its index was never written"), std::string::npos) << error;
  EXPECT_NE(error.find("rosbag reindex"), std::string::npos) << error;
}

}  // namespace
}  // namespace odometry_calibration
