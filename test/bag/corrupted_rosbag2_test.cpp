// Damaged rosbag2 storage files, .db3 (SQLite) and .mcap, read in-process by the readers
// calibrate_bag uses (every message deserialised): truncations at 50 points, 200 flipped bytes,
// zeroed blocks, forged lengths, a chunk that does not decompress, a CRC that does not match
// (a fixed seed, so that a failure replays); the MCAP file holds the .db3's messages. Never a crash
// and never longer than 10 s a file; each refusal names the file and the cause; an MCAP file that
// lost messages says it was read only in part; damage an MCAP file's CRCs cover is refused.
#include <stdlib.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <random>

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "odometry_calibration/bag/mcap_messages.h"
#include "odometry_calibration/bag/mcap_records.h"
#include "odometry_calibration/bag/rosbag2_sqlite_messages.h"
#include "odometry_calibration/bag_writers/rosbag2_mcap_writer.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::vector<std::string> kTopics = {"/joint_states", "/scan"};
constexpr double kMaxSecondsPerFile = 10.0;

using test_support::readFile;

/// What reading one damaged file gave.
struct Outcome
{
  bool refused = false;
  std::string error;                 ///< the refusal's text
  std::size_t messages = 0;          ///< read (skipped ones included)
  std::size_t skipped = 0;           ///< UnreadableMessage
  std::vector<std::string> partial;  ///< McapMessages::partialReads
  double seconds = 0.0;
};

class CorruptedRosbag2 : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/corrupted_rosbag2_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 3.0;
    simulateToBag(scenario, directory_ + "/db3", "", nullptr, BagFormat::kDb3);
    db3_ = readFile(directory_ + "/db3/db3_0.db3");
    mcap_ = copyToMcap(directory_ + "/db3/db3_0.db3", directory_ + "/mcap");
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  /// Writes `bytes` as `name` (.db3 or .mcap) and reads every message of it.
  static Outcome read(const std::string& name, const std::string& bytes)
  {
    const std::string path = directory_ + "/" + name;
    std::ofstream(path, std::ios::binary | std::ios::trunc) << bytes;
    const auto start = std::chrono::steady_clock::now();
    Outcome outcome;
    try {
      std::unique_ptr<RecordedMessages> messages;
      if (isMcapPath(path))
        messages = std::make_unique<McapMessages>(std::vector<std::string>{path}, kTopics);
      else
        messages = std::make_unique<Rosbag2SqliteMessages>(std::vector<std::string>{path}, kTopics);
      while (messages->next()) {
        ++outcome.messages;
        sensor_msgs::JointState joints;
        sensor_msgs::LaserScan scan;
        try {
          if (!messages->read(joints))
            messages->read(scan);
        } catch (const UnreadableMessage&) {
          ++outcome.skipped;
        }
      }
      outcome.partial = messages->partialReads();
    } catch (const std::runtime_error& error) {
      outcome.refused = true;
      outcome.error = error.what();
    }
    outcome.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    fs::remove(path);
    return outcome;
  }

  /// The checks every damaged file passes: in time; a refusal names the file and a cause; an
  /// MCAP file that lost messages says so.
  static void expectNamed(const Outcome& outcome, const std::string& name, std::size_t whole)
  {
    EXPECT_LT(outcome.seconds, kMaxSecondsPerFile) << name;
    if (outcome.refused) {
      EXPECT_NE(outcome.error.find("'" + directory_ + "/" + name + "'"), std::string::npos)
          << outcome.error;
      EXPECT_GT(outcome.error.size(), directory_.size() + name.size() + 20) << outcome.error;
    } else if (name.find(".mcap") != std::string::npos && outcome.messages < whole) {
      ASSERT_EQ(outcome.partial.size(), 1u)
          << name << ": " << outcome.messages << " of " << whole << " read without saying so";
      EXPECT_NE(outcome.partial[0].find(name), std::string::npos) << outcome.partial[0];
    }
  }

  /// The messages of the .db3 `db3` written into the bag folder `folder` in MCAP storage, in
  /// zstd chunks of 16 kB (many chunks from a short drive); returns the .mcap file's bytes.
  static std::string copyToMcap(const std::string& db3, const std::string& folder)
  {
    fs::create_directory(folder);
    Rosbag2McapWriter writer(folder, "mcap", "zstd", 16 * 1024);
    sqlite3* db = nullptr;
    EXPECT_EQ(sqlite3_open(db3.c_str(), &db), SQLITE_OK);
    sqlite3_stmt* rows = nullptr;
    EXPECT_EQ(sqlite3_prepare_v2(db,
                                 "SELECT t.name, t.type, m.timestamp, m.data FROM messages m "
                                 "JOIN topics t ON t.id = m.topic_id ORDER BY m.timestamp, m.id",
                                 -1, &rows, nullptr),
              SQLITE_OK);
    while (sqlite3_step(rows) == SQLITE_ROW) {
      const auto* data = static_cast<const std::uint8_t*>(sqlite3_column_blob(rows, 3));
      writer.writeSerialized(reinterpret_cast<const char*>(sqlite3_column_text(rows, 0)),
                             reinterpret_cast<const char*>(sqlite3_column_text(rows, 1)),
                             sqlite3_column_int64(rows, 2),
                             std::vector<std::uint8_t>(data, data + sqlite3_column_bytes(rows, 3)));
    }
    sqlite3_finalize(rows);
    sqlite3_close(db);
    writer.close();
    return readFile(folder + "/mcap_0.mcap");
  }

  static std::string directory_, db3_, mcap_;
};

std::string CorruptedRosbag2::directory_, CorruptedRosbag2::db3_, CorruptedRosbag2::mcap_;

/// Where the MCAP file's footer record starts.
std::size_t footerStart(const std::string& mcap)
{
  return mcap.size() - mcap::kMagicSize - (mcap::kRecordPrefixSize + 20);
}

TEST_F(CorruptedRosbag2, TheCleanFilesReadWhole)
{
  const Outcome db3 = read("clean.db3", db3_), mcap = read("clean.mcap", mcap_);
  ASSERT_FALSE(db3.refused) << db3.error;
  ASSERT_FALSE(mcap.refused) << mcap.error;
  EXPECT_GT(db3.messages, 100u);
  EXPECT_EQ(mcap.messages, db3.messages);
  EXPECT_EQ(mcap.skipped + db3.skipped, 0u);
  EXPECT_TRUE(mcap.partial.empty());
  // Many chunks, so that a cut file keeps some.
  std::size_t chunks = 0;
  for (std::size_t at = mcap::kMagicSize; at + mcap::kRecordPrefixSize <= mcap_.size() - 8;) {
    std::uint64_t length = 0;
    std::memcpy(&length, mcap_.data() + at + 1, 8);
    chunks += mcap_[at] == mcap::kChunk ? 1 : 0;
    at += mcap::kRecordPrefixSize + length;
  }
  EXPECT_GT(chunks, 10u);
}

TEST_F(CorruptedRosbag2, TruncationsAt50PointsAreRefusedOrReadInPartSayingSo)
{
  const std::size_t whole = read("clean.mcap", mcap_).messages;
  for (const bool is_mcap : {false, true}) {
    const std::string& clean = is_mcap ? mcap_ : db3_;
    std::size_t previous = 0;
    for (int k = 0; k < 50; ++k) {
      const std::string name = "cut" + std::to_string(k) + (is_mcap ? ".mcap" : ".db3");
      const Outcome outcome = read(name, clean.substr(0, clean.size() * k / 50));
      expectNamed(outcome, name, whole);
      if (!is_mcap) {  // SQLite: refused (the header's page count), never fewer rows silently
        EXPECT_TRUE(outcome.refused) << name << ": " << outcome.messages;
        continue;
      }
      // No footer: read up to the cut (more the later the cut) and said, or refused; a cut in
      // the summary loses no message.
      EXPECT_TRUE(outcome.refused || !outcome.partial.empty() || outcome.messages == whole) << name;
      EXPECT_GE(outcome.messages, previous) << name;
      previous = std::max(previous, outcome.messages);
    }
    if (is_mcap) {
      EXPECT_GT(previous, whole / 2);
    }
  }
}

TEST_F(CorruptedRosbag2, TwoHundredFlippedBytesAreRefusedWhereTheCrcsCoverThem)
{
  const std::size_t whole = read("clean.mcap", mcap_).messages;
  std::mt19937 random(49);
  for (const bool is_mcap : {false, true}) {
    const std::string& clean = is_mcap ? mcap_ : db3_;
    std::uniform_int_distribution<std::size_t> where(0, clean.size() - 1);
    std::uniform_int_distribution<int> bit(0, 7);
    for (int k = 0; k < 200; ++k) {
      std::string bytes = clean;
      const std::size_t at = where(random);
      bytes[at] = static_cast<char>(bytes[at] ^ (1 << bit(random)));
      const std::string name = "flip" + std::to_string(k) + (is_mcap ? ".mcap" : ".db3");
      const Outcome outcome = read(name, bytes);
      expectNamed(outcome, name, whole);
      // Everything before the footer is under the data section's or the summary's CRC.
      if (is_mcap && at < footerStart(clean)) {
        EXPECT_TRUE(outcome.refused) << name << " (byte " << at << ")";
      }
    }
  }
}

TEST_F(CorruptedRosbag2, ZeroedBlocksAreRefusedOrNamed)
{
  const std::size_t whole = read("clean.mcap", mcap_).messages;
  std::mt19937 random(4949);
  for (const bool is_mcap : {false, true}) {
    const std::string& clean = is_mcap ? mcap_ : db3_;
    std::uniform_int_distribution<std::size_t> where(0, clean.size() - 512);
    for (int k = 0; k < 20; ++k) {
      std::string bytes = clean;
      const std::size_t at = where(random);
      std::memset(&bytes[at], 0, 512);
      const std::string name = "zeroed" + std::to_string(k) + (is_mcap ? ".mcap" : ".db3");
      const Outcome outcome = read(name, bytes);
      expectNamed(outcome, name, whole);
      if (is_mcap && bytes != clean) {
        EXPECT_TRUE(outcome.refused) << name << " (byte " << at << ")";
      }
    }
  }
}

TEST_F(CorruptedRosbag2, ForgedLengthsAreRefusedNamingTheByte)
{
  const std::size_t whole = read("clean.mcap", mcap_).messages;
  // Each top-level record's length: huge, one past the file, one short.
  int forged = 0;
  for (std::size_t at = mcap::kMagicSize; at + mcap::kRecordPrefixSize <= mcap_.size() - 8;) {
    std::uint64_t length = 0;
    std::memcpy(&length, mcap_.data() + at + 1, 8);
    for (const std::uint64_t wrong :
         {std::uint64_t{1} << 62, std::uint64_t{mcap_.size()}, length - 1}) {
      std::string bytes = mcap_;
      std::memcpy(&bytes[at + 1], &wrong, 8);
      const std::string name = "forged" + std::to_string(forged++) + ".mcap";
      const Outcome outcome = read(name, bytes);
      expectNamed(outcome, name, whole);
      if (at < footerStart(mcap_)) {
        EXPECT_TRUE(outcome.refused) << name << " (record at byte " << at << ")";
      }
      if (outcome.refused) {
        EXPECT_NE(outcome.error.find("is corrupted at byte "), std::string::npos) << outcome.error;
      }
    }
    at += mcap::kRecordPrefixSize + length;
  }
  EXPECT_GE(forged, 30);
  // SQLite: the header's page size and count, the first page's cell count.
  const std::pair<std::size_t, std::string> fields[] = {{16, std::string("\x02\x00", 2)},
                                                        {16, "\xff\xff"},
                                                        {28, "\x7f\xff\xff\xff"},
                                                        {103, "\xff\xff"}};
  for (const auto& [offset, value] : fields) {
    std::string bytes = db3_;
    bytes.replace(offset, value.size(), value);
    const std::string name = "forged" + std::to_string(offset) + value.substr(0, 1) + ".db3";
    expectNamed(read(name, bytes), name, whole);
  }
}

TEST_F(CorruptedRosbag2, AChunkThatDoesNotDecompressAndACrcMismatchAreRefused)
{
  // Without the data section's CRC (a writer may leave it 0), the chunk's own checks.
  std::string bytes = mcap_;
  std::size_t chunk = mcap::kMagicSize, data_end = 0;
  for (std::size_t at = mcap::kMagicSize; at < mcap_.size() - 8;) {
    std::uint64_t length = 0;
    std::memcpy(&length, mcap_.data() + at + 1, 8);
    if (mcap_[at] == mcap::kChunk && chunk == mcap::kMagicSize)
      chunk = at;
    if (mcap_[at] == mcap::kDataEnd)
      data_end = at;
    at += mcap::kRecordPrefixSize + length;
  }
  ASSERT_GT(data_end, chunk);
  std::memset(&bytes[data_end + mcap::kRecordPrefixSize], 0, 4);
  std::string undecompressable = bytes;
  // The chunk's records start after its times, sizes, CRC, "zstd" and their length.
  std::memset(&undecompressable[chunk + 9 + 8 + 8 + 8 + 4 + 4 + 4 + 8], 0xAB, 64);
  Outcome outcome = read("undecompressable.mcap", undecompressable);
  ASSERT_TRUE(outcome.refused);
  EXPECT_NE(outcome.error.find("undecompressable.mcap' is corrupted at byte " +
                               std::to_string(chunk) + ": its chunk does not decompress"),
            std::string::npos)
      << outcome.error;
  std::string crc = bytes;
  crc[chunk + 9 + 8 + 8 + 8] = static_cast<char>(crc[chunk + 9 + 8 + 8 + 8] ^ 1);
  outcome = read("crc.mcap", crc);
  ASSERT_TRUE(outcome.refused);
  EXPECT_NE(outcome.error.find("crc.mcap' is corrupted at byte " + std::to_string(chunk) +
                               ": its chunk's CRC does not match"),
            std::string::npos)
      << outcome.error;
}

}  // namespace
}  // namespace odometry_calibration
