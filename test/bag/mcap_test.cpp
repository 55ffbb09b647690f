// The MCAP reader and writer (mcap_records.h, mcap_file.h, mcap_messages.h,
// rosbag2_mcap_writer.h): bags written and read back (folder and file, zstd, lz4 and
// uncompressed chunks, several chunks, split into files), a file cut off while recording read
// up to the cut and saying so, and every damage refused naming the file, the byte and the cause.
#include <stdlib.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/bag/mcap_messages.h"
#include "odometry_calibration/bag/mcap_records.h"
#include "odometry_calibration/bag_writers/cdr_writer.h"
#include "odometry_calibration/bag_writers/rosbag2_mcap_writer.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
using test_support::readFile;

const std::vector<std::string> kTopics = {"/joint_states", "/scan"};

class Mcap : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/mcap_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }
  void TearDown() override { fs::remove_all(directory_); }

  static ros::Time at(double t_s)
  {
    ros::Time time;
    time.fromNSec(1700000000000000000ull + static_cast<std::uint64_t>(std::llround(t_s * 1e9)));
    return time;
  }

  /// A bag folder `name` with joint states at 0, 0.1, ... and scans of `rays` rays at 0.05,
  /// 0.15, ... (`count` each, from `start_s`), and a tf message the readers are not asked for.
  std::string writeBag(const std::string& name, const std::string& compression = "zstd",
                       int count = 5, double start_s = 0.0, std::size_t rays = 10)
  {
    const std::string folder = directory_ + "/" + name;
    fs::create_directory(folder);
    Rosbag2McapWriter writer(folder, name, compression);
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
      scan.ranges.assign(rays, static_cast<float>(k));
      writer.write("/scan", scan.header.stamp, scan);
    }
    writer.close();
    return folder;
  }

  std::string directory_;
};

/// The topics and record times of every message, each read as its type.
std::vector<std::pair<std::string, double>> walk(RecordedMessages& messages)
{
  std::vector<std::pair<std::string, double>> result;
  while (messages.next()) {
    sensor_msgs::JointState joints;
    sensor_msgs::LaserScan scan;
    EXPECT_TRUE(messages.read(joints) || messages.read(scan)) << messages.topic();
    result.emplace_back(messages.topic(), messages.recordTime_s());
  }
  return result;
}

TEST_F(Mcap, ABagIsReadInTimeOrderOnlyOnTheTopicsAskedForWithEveryCompression)
{
  for (const std::string compression : {"zstd", "lz4", "none"}) {
    SCOPED_TRACE(compression);
    const std::string folder = writeBag("bag_" + compression, compression);
    const std::string file = folder + "/bag_" + compression + "_0.mcap";
    EXPECT_TRUE(isMcapPath(folder));
    EXPECT_TRUE(isMcapPath(file));
    for (const std::string& path : {folder, file}) {
      McapMessages messages({path}, kTopics);
      ASSERT_FALSE(messages.empty());
      EXPECT_TRUE(messages.partialReads().empty());
      EXPECT_NEAR(messages.beginTime_s(), 1.7e9, 1e-6);
      EXPECT_NEAR(messages.endTime_s(), 1.7e9 + 0.45, 1e-6);
      int k = 0;
      for (; messages.next(); ++k) {
        EXPECT_EQ(messages.topic(), k % 2 == 0 ? "/joint_states" : "/scan");
        EXPECT_NEAR(messages.recordTime_s(), 1.7e9 + 0.05 * k, 1e-6);
        sensor_msgs::JointState joints;
        sensor_msgs::LaserScan scan;
        nav_msgs::Odometry odometry;
        EXPECT_FALSE(messages.read(odometry));
        if (k % 2 == 0) {
          ASSERT_TRUE(messages.read(joints));
          EXPECT_EQ(joints.position, (std::vector<double>{0.1 * (k / 2), -0.1 * (k / 2)}));
        } else {
          ASSERT_TRUE(messages.read(scan));
          EXPECT_EQ(scan.ranges, std::vector<float>(10, static_cast<float>(k / 2)));
          EXPECT_EQ(scan.header.frame_id, "laser");
        }
      }
      EXPECT_EQ(k, 10);
      EXPECT_NE(messages.describeTopics().find("'/tf' (tf2_msgs/msg/TFMessage, 5 messages)"),
                std::string::npos)
          << messages.describeTopics();
    }
  }
  // Compressed chunks are smaller than the same records uncompressed.
  EXPECT_LT(fs::file_size(directory_ + "/bag_zstd/bag_zstd_0.mcap"),
            fs::file_size(directory_ + "/bag_none/bag_none_0.mcap"));
}

TEST_F(Mcap, ManyChunksTheWindowAndSplitFilesAreReadInTimeOrder)
{
  // 400 scans of 2000 rays (8 kB each): several 1 MiB chunks.
  const std::string a = writeBag("a", "lz4", 400, 0.0, 2000);
  const std::string b = writeBag("b", "zstd", 400, 0.02, 2000);
  for (const std::vector<std::string>& paths :
       {std::vector<std::string>{a}, std::vector<std::string>{a, b}}) {
    McapMessages messages(paths, kTopics);
    const auto read = walk(messages);
    ASSERT_EQ(read.size(), 800u * paths.size());
    for (std::size_t k = 1; k < read.size(); ++k)
      ASSERT_LE(read[k - 1].second, read[k].second) << k;
  }
  McapMessages window({a}, {"/scan"});
  window.restrictTo(window.firstTime_ns() + 100000000, window.firstTime_ns() + 250000000);
  const auto read = walk(window);
  ASSERT_EQ(read.size(), 2u);  // the scans at 0.15 and 0.25 (0.05 is the first)
  EXPECT_NEAR(read[0].second, 1.7e9 + 0.15, 1e-6);
  EXPECT_EQ(McapMessages({a}, {"/scan", "/odom"}).missingTopics(),
            std::vector<std::string>{"/odom"});
}

/// The text of the error opening and reading `path` throws ("" if none).
std::string readingError(const std::string& path, std::size_t* read = nullptr,
                         std::vector<std::string>* partial = nullptr)
{
  try {
    McapMessages messages({path}, kTopics);
    const std::size_t count = walk(messages).size();
    if (read)
      *read = count;
    if (partial)
      *partial = messages.partialReads();
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

void writeBytes(const std::string& path, const std::string& bytes)
{
  std::ofstream(path, std::ios::binary) << bytes;
}

TEST_F(Mcap, AFileCutOffWhileRecordingIsReadUpToTheCutAndSaysSo)
{
  const std::string folder = writeBag("cut", "zstd", 400, 0.0, 2000);
  const std::string bytes = readFile(folder + "/cut_0.mcap");
  std::size_t whole = 0;
  ASSERT_EQ(readingError(folder, &whole), "");
  ASSERT_EQ(whole, 800u);
  const std::string cut = directory_ + "/cut.mcap";
  writeBytes(cut, bytes.substr(0, bytes.size() * 2 / 3));
  std::size_t read = 0;
  std::vector<std::string> partial;
  EXPECT_EQ(readingError(cut, &read, &partial), "");
  EXPECT_GT(read, 100u);
  EXPECT_LT(read, whole);
  ASSERT_EQ(partial.size(), 1u);
  EXPECT_NE(partial[0].find("'" + cut + "' has no intact footer"), std::string::npos) << partial[0];
  EXPECT_NE(partial[0].find("read only up to byte "), std::string::npos) << partial[0];
  EXPECT_NE(partial[0].find("runs past the end of the file"), std::string::npos) << partial[0];
}

/// The byte where the first record with `opcode` starts in the top level of `bytes`.
std::size_t findRecord(const std::string& bytes, std::uint8_t opcode)
{
  std::size_t at = mcap::kMagicSize;
  while (at + 9 <= bytes.size()) {
    std::uint64_t length = 0;
    std::memcpy(&length, bytes.data() + at + 1, 8);
    if (static_cast<std::uint8_t>(bytes[at]) == opcode)
      return at;
    at += 9 + length;
  }
  return std::string::npos;
}

TEST_F(Mcap, DamageIsRefusedNamingTheFileTheByteAndTheCause)
{
  auto expectError = [&](const std::string& name, const std::string& bytes,
                         const std::string& cause) {
    const std::string path = directory_ + "/" + name;
    writeBytes(path, bytes);
    const std::string text = readingError(path);
    EXPECT_NE(text.find("MCAP file '" + path + "'"), std::string::npos) << text;
    EXPECT_NE(text.find(cause), std::string::npos) << text;
  };
  expectError("text.mcap", std::string(100, 'x'), "does not start with MCAP's magic");
  EXPECT_NE(readingError(directory_ + "/missing.mcap").find("no MCAP file"), std::string::npos);
  const std::string bytes = readFile(writeBag("plain", "none") + "/plain_0.mcap");
  const std::size_t chunk = findRecord(bytes, mcap::kChunk);
  const std::size_t data_end = findRecord(bytes, mcap::kDataEnd);
  ASSERT_NE(chunk, std::string::npos);
  ASSERT_NE(data_end, std::string::npos);
  // A flipped byte in a message: the data section's CRC, then (without it) the chunk's.
  std::string flipped = bytes;
  flipped[chunk + 200] = static_cast<char>(flipped[chunk + 200] ^ 0x40);
  expectError("flipped.mcap", flipped,
              "is corrupted at byte " + std::to_string(data_end) +
                  ": the data section's CRC does not match");
  std::memset(&flipped[data_end + 9], 0, 4);
  expectError("flipped_chunk.mcap", flipped,
              "is corrupted at byte " + std::to_string(chunk) + ": its chunk's CRC does not match");
  // A forged record length within an intact footer: refused, not read in part.
  std::string forged = bytes;
  forged[chunk + 8] = '\x7f';
  expectError("forged.mcap", forged, "runs past the end of the data section");
  // A zstd chunk that does not decompress.
  std::string zstd = readFile(writeBag("zstd") + "/zstd_0.mcap");
  const std::size_t zstd_chunk = findRecord(zstd, mcap::kChunk);
  std::memset(&zstd[findRecord(zstd, mcap::kDataEnd) + 9], 0, 4);
  std::memset(&zstd[zstd_chunk + 9 + 8 + 8 + 8 + 4 + 4 + 4 + 8], 0, 16);
  expectError("zstd.mcap", zstd, "its chunk does not decompress: zstd: ");
  // The summary's CRC.
  std::string summary = bytes;
  summary[data_end + 13 + 3] = static_cast<char>(summary[data_end + 13 + 3] ^ 1);
  expectError("summary.mcap", summary, "the summary's CRC does not match");
  // A topic asked for in another serialisation.
  const std::string folder = directory_ + "/json";
  fs::create_directory(folder);
  Rosbag2McapWriter writer(folder, "json");
  writer.writeSerialized("/scan", "sensor_msgs/msg/LaserScan", 5, {1, 2, 3});
  writer.close();
  std::string json = readFile(folder + "/json_0.mcap");
  const std::size_t cdr = json.rfind("cdr");  // the summary's channel
  json.replace(cdr, 3, "jsn");
  expectError("json.mcap", json, "the summary's CRC does not match");
  std::memset(&json[json.size() - 12], 0, 4);  // no summary CRC: the summary's channel taken
  writeBytes(directory_ + "/json.mcap", json);
  const std::string text = readingError(directory_ + "/json.mcap");
  EXPECT_NE(text.find("'/scan' is serialised as 'jsn'; only 'cdr' is read"), std::string::npos)
      << text;
}

TEST_F(Mcap, MessagesOutsideChunksWithoutSummaryAreRead)
{
  // As the format allows: schema, channel and messages in the data section, no chunk, no Data
  // End, a footer without summary; the scans written later in time first.
  std::vector<std::uint8_t> bytes(mcap::kMagic, mcap::kMagic + mcap::kMagicSize);
  mcap::Appender out(bytes);
  std::size_t record = out.beginRecord(mcap::kHeader);
  out.text("ros2");
  out.text("hand");
  out.finishRecord(record);
  record = out.beginRecord(mcap::kSchema);
  out.u16(7);
  out.text("sensor_msgs/msg/LaserScan");
  out.text("ros2msg");
  out.u32(0);
  out.finishRecord(record);
  record = out.beginRecord(mcap::kChannel);
  out.u16(3);
  out.u16(7);
  out.text("/scan");
  out.text("cdr");
  out.u32(0);
  out.finishRecord(record);
  for (const int k : {2, 1, 3}) {
    sensor_msgs::LaserScan scan;
    scan.ranges.assign(3, static_cast<float>(k));
    const std::vector<std::uint8_t> cdr = writeCdr(scan);
    record = out.beginRecord(mcap::kMessage);
    out.u16(3);
    out.u32(static_cast<std::uint32_t>(k));
    out.u64(1000u * static_cast<std::uint64_t>(k));
    out.u64(1000u * static_cast<std::uint64_t>(k));
    out.bytes(cdr.data(), cdr.size());
    out.finishRecord(record);
  }
  out.u8(mcap::kFooter);
  out.u64(20);
  out.u64(0);
  out.u64(0);
  out.u32(0);
  out.bytes(mcap::kMagic, mcap::kMagicSize);
  const std::string path = directory_ + "/loose.mcap";
  writeBytes(path, std::string(bytes.begin(), bytes.end()));
  McapMessages messages({path}, {"/scan"});
  EXPECT_EQ(messages.firstTime_ns(), 1000);
  EXPECT_EQ(messages.lastTime_ns(), 3000);
  for (const int k : {1, 2, 3}) {
    ASSERT_TRUE(messages.next());
    sensor_msgs::LaserScan scan;
    ASSERT_TRUE(messages.read(scan));
    EXPECT_EQ(scan.ranges, std::vector<float>(3, static_cast<float>(k)));
    EXPECT_NEAR(messages.recordTime_s(), 1e-6 * k, 1e-12);
  }
  EXPECT_FALSE(messages.next());
  EXPECT_TRUE(messages.partialReads().empty());
}

TEST(McapRecords, ChunksRoundTripAndBadOnesAreRefused)
{
  std::vector<std::uint8_t> records(5000);
  for (std::size_t k = 0; k < records.size(); ++k)
    records[k] = static_cast<std::uint8_t>(k * 7 % 13);
  for (const std::string compression : {"", "zstd", "lz4"}) {
    const std::vector<std::uint8_t> packed = mcap::compressChunk(compression, records);
    std::vector<std::uint8_t> out;
    mcap::decompressChunk(compression, packed.data(), packed.size(), records.size(), out);
    EXPECT_EQ(out, records) << compression;
    if (compression.empty())
      continue;
    EXPECT_LT(packed.size(), records.size()) << compression;
    // A wrong size is refused, not truncated or padded.
    EXPECT_THROW(
        mcap::decompressChunk(compression, packed.data(), packed.size(), records.size() + 1, out),
        std::runtime_error);
    EXPECT_THROW(
        mcap::decompressChunk(compression, packed.data(), packed.size() / 2, records.size(), out),
        std::runtime_error);
  }
  std::vector<std::uint8_t> out;
  EXPECT_THROW(mcap::decompressChunk("zstd", records.data(), 10, mcap::kMaxChunkSize + 1, out),
               std::runtime_error);
  EXPECT_THROW(mcap::decompressChunk("brotli", records.data(), 10, 10, out), std::runtime_error);
  // The CRC-32 of "123456789", the check value of the IEEE polynomial.
  const std::uint8_t check[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(mcap::crc32(check, sizeof(check)), 0xCBF43926u);
}

}  // namespace
}  // namespace odometry_calibration
