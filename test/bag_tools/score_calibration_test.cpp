// Issue 17 acceptance, end to end on the built tools: the diff-drive calibration of one time
// window of the real Mines log (calibrate_bag) scored on another window (score_calibration)
// prints the saved model's row and the nominal row without refitting, and the tool exits 1 with
// a clear message on data whose joints are not the calibration's.
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/bag_writers/mines_bag_writer.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/datasets/mines_log.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"
#include "support/score_table.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
using test_support::readFile;
using test_support::scoreTableRow;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kLog = std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/mines/exp1.dat";

struct ToolResult
{
  int status = -1;
  std::string out, err;
};

class ScoreCalibration : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    if (!fs::exists(kLog))
      return;
    char pattern[] = "/tmp/score_calibration_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    bag_ = directory_ + "/mines.bag";
    writeMinesBag(loadMinesLog(kLog), bag_);
    // The first 45 s of the 75 s log calibrated once for all tests.
    calibration_ = run(CALIBRATE_BAG_PROGRAM, "--config " + kConfig + "/mines.yaml " + bag_ +
                                                  " --end 45 --quiet --output-dir " + directory_ +
                                                  "/calibration");
  }
  static void TearDownTestSuite()
  {
    if (!directory_.empty())
      fs::remove_all(directory_);
  }
  void SetUp() override
  {
    if (!fs::exists(kLog))
      GTEST_SKIP() << "no Mines log at " << kLog << " (../shared/data is not there)";
    ASSERT_TRUE(calibration_.status == 0 || calibration_.status == 4)
        << calibration_.out << calibration_.err;
  }

  static ToolResult run(const std::string& program, const std::string& arguments)
  {
    const std::string out = directory_ + "/out.txt", err = directory_ + "/err.txt";
    const int status =
        std::system((program + " " + arguments + " > " + out + " 2> " + err).c_str());
    return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, readFile(out), readFile(err)};
  }
  static ToolResult score(const std::string& arguments)
  {
    return run(SCORE_CALIBRATION_PROGRAM,
               "--result " + directory_ + "/calibration/result.yaml --quiet " + arguments);
  }

  static std::string directory_, bag_;
  static ToolResult calibration_;
};
std::string ScoreCalibration::directory_, ScoreCalibration::bag_;
ToolResult ScoreCalibration::calibration_;

TEST_F(ScoreCalibration, SavedDiffDriveAndNominalRowsOnAnotherWindowOfTheMinesLog)
{
  const ToolResult result = score("--config " + kConfig + "/mines.yaml " + bag_ + " --start 45");
  ASSERT_EQ(result.status, 0) << result.out << result.err;
  EXPECT_EQ(result.err, "");
  const std::vector<double> saved = scoreTableRow(result.out, "diff_drive");
  const std::vector<double> nominal = scoreTableRow(result.out, "nominal");
  ASSERT_EQ(saved.size(), 5u) << result.out;
  ASSERT_EQ(nominal.size(), 5u) << result.out;
  EXPECT_NE(result.out.find("diff_drive: the saved calibration, not refitted"), std::string::npos);
  EXPECT_NE(result.out.find("nominal: the configured nominal model, not fitted"),
            std::string::npos);
  // Scored, not refitted: the saved time offset is used and no fit time is shown.
  EXPECT_NE(result.out.find("time offset -0.1"), std::string::npos) << result.out;
  // The calibration (wheel radii, separation, laser pose and the -0.15 s encoder lead) carries
  // over to the unseen window: its per-pair errors are below the nominal robot's.
  EXPECT_LT(saved[4], nominal[4]) << result.out;
  EXPECT_LT(saved[2] + saved[3], nominal[2] + nominal[3]) << result.out;
  std::cout << result.out;  // the numbers for the docs
}

TEST_F(ScoreCalibration, ScoresAPairsFileToo)
{
  // calibrate_bag's own pairs (the first window) scored again: the saved model's row.
  const ToolResult result =
      score("--config " + kConfig + "/mines.yaml --pairs " + directory_ + "/calibration/pairs.csv");
  ASSERT_EQ(result.status, 0) << result.out << result.err;
  EXPECT_EQ(scoreTableRow(result.out, "diff_drive").size(), 5u) << result.out;
  EXPECT_EQ(scoreTableRow(result.out, "nominal").size(), 5u) << result.out;
}

TEST_F(ScoreCalibration, ExitsOneOnDataWhoseJointsAreNotTheCalibrations)
{
  // A configuration naming other joints than result.yaml's.
  std::string config = readFile(kConfig + "/mines.yaml");
  for (const std::string& joint : {std::string("left_wheel"), std::string("right_wheel")}) {
    for (std::size_t at = config.find(joint); at != std::string::npos;
         at = config.find(joint, at + 5)) {
      config.replace(at, joint.size(), "wheel_" + joint.substr(0, joint.find('_')));
    }
  }
  std::ofstream(directory_ + "/renamed.yaml") << config;
  ToolResult result = score("--config " + directory_ + "/renamed.yaml " + bag_ + " --start 45");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.err.find("carries the joints (wheel_left, wheel_right) but the calibration "
                            "was made with (left_wheel, right_wheel)"),
            std::string::npos)
      << result.err;
  EXPECT_EQ(result.out, "");

  // A bag whose JointState messages name other joints (a simulated robot's).
  sim::Scenario scenario = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_office.yaml",
                                                 kConfig + "/sim/worlds");
  scenario.duration_s = 5.0;
  scenario.encoders.joint_names = {"wheel_a", "wheel_b"};
  simulateToBag(scenario, directory_ + "/other_joints.bag", "");
  result = score("--config " + kConfig + "/mines.yaml " + directory_ + "/other_joints.bag");
  EXPECT_EQ(result.status, 1);
  EXPECT_NE(result.err.find("do not carry the calibration's joints (left_wheel, right_wheel)"),
            std::string::npos)
      << result.err;
  EXPECT_EQ(result.out, "");
}

}  // namespace
}  // namespace odometry_calibration
