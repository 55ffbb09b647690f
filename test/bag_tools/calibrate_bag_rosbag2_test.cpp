// End-to-end: one simulated drive written as a ROS 1 bag and as rosbag2 bag folders (SQLite,
// plain and zstd-compressed; MCAP with zstd, lz4 and uncompressed chunks): calibrate_bag reads
// each and gives the same pairs and the same result (only the source path differs); a cut
// message in a rosbag2 bag is skipped and counted; an MCAP file cut off while recording is
// calibrated from its part, saying so on stderr and in the report.
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>
#include <sqlite3.h>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kTool = CALIBRATE_BAG_PROGRAM;

using test_support::readFile;

class CalibrateBagRosbag2 : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/calibrate_bag_rosbag2_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 30.0;
    simulateToBag(scenario, directory_ + "/drive.bag", "");
    simulateToBag(scenario, directory_ + "/drive_db3", "", nullptr, BagFormat::kDb3);
    simulateToBag(scenario, directory_ + "/drive_zstd", "", nullptr, BagFormat::kDb3Zstd);
    simulateToBag(scenario, directory_ + "/drive_mcap", "", nullptr, BagFormat::kMcapZstd);
    simulateToBag(scenario, directory_ + "/drive_lz4", "", nullptr, BagFormat::kMcapLz4);
    simulateToBag(scenario, directory_ + "/drive_plain", "", nullptr, BagFormat::kMcap);
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  /// calibrate_bag on `bag` into `output`; returns its exit status (stdout in output/stdout.txt).
  static int run(const std::string& bag, const std::string& output)
  {
    const std::string command = kTool + " --config " + kConfig + "/diff_drive.yaml " + bag +
                                " --quiet --output-dir " + output + " > " + directory_ + "/" +
                                output.substr(output.rfind('/') + 1) + ".txt 2>&1";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  static std::string printed(const std::string& output)
  {
    return readFile(directory_ + "/" + output + ".txt");
  }

  /// result.yaml without its `source:` line (the bag's path).
  static std::string resultWithoutSource(const std::string& output)
  {
    std::istringstream in(readFile(output + "/result.yaml"));
    std::string kept;
    for (std::string line; std::getline(in, line);) {
      if (line.find("source:") == std::string::npos)
        kept += line + "\n";
    }
    return kept;
  }

  static std::string directory_;
};

std::string CalibrateBagRosbag2::directory_;

TEST_F(CalibrateBagRosbag2, Rosbag2GivesTheSamePairsAndResultAsTheRos1Bag)
{
  const int ros1 = run(directory_ + "/drive.bag", directory_ + "/out_bag");
  ASSERT_TRUE(ros1 == 0 || ros1 == 4) << printed("out_bag");
  const std::string pairs = readFile(directory_ + "/out_bag/pairs.csv");
  const std::string result = resultWithoutSource(directory_ + "/out_bag");
  ASSERT_GT(std::count(pairs.begin(), pairs.end(), '\n'), 10) << pairs;
  EXPECT_NE(result.find("wheel_radius"), std::string::npos) << result;
  const std::pair<const char*, const char*> runs[] = {
      {"drive_db3", "out_db3"},
      {"drive_zstd", "out_zstd"},
      {"drive_db3/drive_db3_0.db3", "out_file"},
      {"drive_mcap", "out_mcap"},
      {"drive_lz4", "out_lz4"},
      {"drive_plain", "out_plain"},
      {"drive_mcap/drive_mcap_0.mcap", "out_mcap_file"}};
  for (const auto& [bag, name] : runs) {
    SCOPED_TRACE(bag);
    const std::string output = directory_ + "/" + name;
    EXPECT_EQ(run(directory_ + "/" + bag, output), ros1) << printed(name);
    EXPECT_EQ(readFile(output + "/pairs.csv"), pairs);
    EXPECT_EQ(resultWithoutSource(output), result);
    EXPECT_NE(readFile(output + "/result.yaml").find(bag), std::string::npos);
  }
}

TEST_F(CalibrateBagRosbag2, ACutScanIsSkippedAndCounted)
{
  const std::string bag = directory_ + "/cut";
  fs::copy(directory_ + "/drive_db3", bag);
  fs::rename(bag + "/drive_db3_0.db3", bag + "/cut.db3");
  sqlite3* db = nullptr;
  ASSERT_EQ(sqlite3_open((bag + "/cut.db3").c_str(), &db), SQLITE_OK);
  ASSERT_EQ(sqlite3_exec(db,
                         "UPDATE messages SET data = substr(data, 1, 100) WHERE id = (SELECT "
                         "m.id FROM messages m JOIN topics t ON t.id = m.topic_id WHERE t.name "
                         "= '/scan' ORDER BY m.timestamp LIMIT 1 OFFSET 20)",
                         nullptr, nullptr, nullptr),
            SQLITE_OK);
  sqlite3_close(db);
  EXPECT_EQ(run(bag + "/cut.db3", directory_ + "/out_cut"), 0) << printed("out_cut");
  const std::string text = printed("out_cut");
  EXPECT_NE(text.find("skipped 1 LaserScan messages, first: a message on '/scan'"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("sensor_msgs/LaserScan of 100 bytes"), std::string::npos) << text;
  EXPECT_NE(text.find(" at byte "), std::string::npos) << text;
}

TEST_F(CalibrateBagRosbag2, AnMcapFileCutOffWhileRecordingIsCalibratedFromItsPartSayingSo)
{
  const std::string bytes = readFile(directory_ + "/drive_mcap/drive_mcap_0.mcap");
  const std::string cut = directory_ + "/cut.mcap";
  std::ofstream(cut, std::ios::binary) << bytes.substr(0, bytes.size() * 3 / 4);
  const std::string output = directory_ + "/out_cut_mcap";
  const int status = run(cut, output);
  ASSERT_TRUE(status == 0 || status == 4) << printed("out_cut_mcap");
  const std::string warning = "warning: MCAP file '" + cut +
                              "' has no intact footer (a recording cut off or damaged) and is "
                              "read only up to byte ";
  const std::string text = printed("out_cut_mcap");
  // On stderr before the files are written, and in the text report.
  EXPECT_NE(text.find(warning), std::string::npos) << text;
  EXPECT_NE(readFile(output + "/report.txt").find(warning), std::string::npos);
  // Fewer pairs than the whole drive gave.
  const std::string pairs = readFile(output + "/pairs.csv");
  const std::string whole = readFile(directory_ + "/out_bag/pairs.csv");
  EXPECT_LT(std::count(pairs.begin(), pairs.end(), '\n'),
            std::count(whole.begin(), whole.end(), '\n'));
  EXPECT_GT(std::count(pairs.begin(), pairs.end(), '\n'), 5);
}

TEST_F(CalibrateBagRosbag2, MixedFormatsAndMissingTopicsAreRefusedClearly)
{
  EXPECT_EQ(run(directory_ + "/drive.bag " + directory_ + "/drive_db3", directory_ + "/out_mix"),
            1);
  EXPECT_NE(printed("out_mix").find("cannot be read in one run"), std::string::npos)
      << printed("out_mix");
  EXPECT_EQ(run(directory_ + "/drive_mcap " + directory_ + "/drive_db3", directory_ + "/out_mix2"),
            1);
  EXPECT_NE(printed("out_mix2").find("SQLite and in MCAP storage cannot be read in one run"),
            std::string::npos)
      << printed("out_mix2");
  // A topic the recording lacks: the error lists the topics it records.
  const std::string config = directory_ + "/other_topics.yaml";
  std::system(("sed 's|^\\(\\s*joint_state_topic:\\).*|\\1 /wheels|' " + kConfig +
               "/diff_drive.yaml > " + config)
                  .c_str());
  const std::string command = kTool + " --config " + config + " " + directory_ +
                              "/drive_db3 --quiet --output-dir " + directory_ + "/out_topics > " +
                              directory_ + "/out_topics.txt 2>&1";
  std::system(command.c_str());
  const std::string text = printed("out_topics");
  EXPECT_NE(text.find("no topic '/wheels'"), std::string::npos) << text;
  EXPECT_NE(text.find("'/joint_states' (sensor_msgs/msg/JointState, "), std::string::npos) << text;
}

}  // namespace
}  // namespace odometry_calibration
