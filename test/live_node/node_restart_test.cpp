// rostest (test/node_restart.test): the node is killed with SIGKILL in the middle of a replay
// and respawned by roslaunch. Every pair it had published before is still in the pairs file,
// the new process resumes them and the calibration saved before the crash, and ~calibrate fits
// all the pairs. The new process then meets a full disk (a file-size limit set with prlimit):
// it keeps collecting, keeps the pairs in memory, and writes every one once there is room.
#include <signal.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <set>
#include <string>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <std_srvs/Trigger.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"
#include "odometry_calibration/CalibrationPair.h"
#include "odometry_calibration/data/pairs_csv.h"

namespace odometry_calibration {
namespace {

using test::waitFor;
const std::string kNode = "/odometry_calibration";

TEST(NodeRestart, KilledMidRunLosesNoPair)
{
  ros::NodeHandle handle, private_handle("~");
  std::string output_directory;
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  std::vector<std::pair<double, double>> published;  // (start, end) of every pair seen
  auto on_pair = [&](const odometry_calibration::CalibrationPair::ConstPtr& m) {
    published.emplace_back(m->start.toSec(), m->end.toSec());
  };
  ros::Subscriber subscriber =
      handle.subscribe<odometry_calibration::CalibrationPair>(kNode + "/pairs", 1000, on_pair);

  std::string model_state;
  std::size_t most_unwritten = 0;
  auto on_diagnostics = [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
    for (const auto& status : m->status)
      for (const auto& value : status.values) {
        if (value.key == "model")
          model_state = value.value;
        if (value.key == "pairs not yet in the pairs file")
          most_unwritten = std::max<std::size_t>(most_unwritten, std::stoul(value.value));
      }
  };
  ros::Subscriber diagnostics =
      handle.subscribe<diagnostic_msgs::DiagnosticArray>("/diagnostics", 10, on_diagnostics);

  ASSERT_TRUE(waitFor([&] { return published.size() >= 40; }, 120));
  // A calibration saved before the crash is the one the new process starts with.
  odometry_calibration::Calibrate first;
  first.request.model = "diff_drive";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", first));
  ASSERT_TRUE(first.response.success) << first.response.message;
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call(kNode + "/save", save));
  ASSERT_TRUE(save.response.success) << save.response.message;
  EXPECT_TRUE(std::filesystem::exists(output_directory + "/result.yaml"));
  EXPECT_TRUE(std::filesystem::exists(output_directory + "/laser_joint.urdf"));
  EXPECT_TRUE(std::filesystem::exists(output_directory + "/last_fit.yaml"));
  // Issue 17: the diff_drive fit as diff_drive_controller takes it, beside result.yaml.
  EXPECT_NE(save.response.message.find("controller.yaml"), std::string::npos);
  std::ifstream controller(output_directory + "/controller.yaml");
  const std::string controller_text((std::istreambuf_iterator<char>(controller)),
                                    std::istreambuf_iterator<char>());
  EXPECT_NE(controller_text.find("wheel_separation_multiplier: "), std::string::npos);
  const int pid = test::nodePid(kNode);
  ASSERT_GT(pid, 0);
  ASSERT_EQ(kill(pid, SIGKILL), 0);
  const std::size_t before_kill = published.size();
  // roslaunch respawns it; it resumes the file and goes on collecting.
  ASSERT_TRUE(waitFor([&] { return test::nodePid(kNode) > 0 && test::nodePid(kNode) != pid; }, 30));
  model_state.clear();
  ASSERT_TRUE(waitFor([&] { return model_state.find("saved") != std::string::npos; }, 30))
      << "model after the restart: " << model_state;
  EXPECT_EQ(model_state.rfind("diff_drive", 0), 0u) << model_state;

  // Then the disk is full (a file-size limit at the pairs file's size): the node keeps
  // collecting, keeps the pairs in memory and writes them all once there is room again.
  const int new_pid = test::nodePid(kNode);
  const std::string pairs_path = output_directory + "/pairs.csv";
  const std::string limit = "prlimit --pid " + std::to_string(new_pid) + " --fsize=";
  ASSERT_EQ(
      std::system((limit + std::to_string(std::filesystem::file_size(pairs_path)) + ":").c_str()),
      0);
  const std::size_t size_when_full = std::filesystem::file_size(pairs_path);
  const std::size_t before_full = published.size();
  ASSERT_TRUE(waitFor([&] { return published.size() >= before_full + 8; }, 60));
  EXPECT_EQ(std::filesystem::file_size(pairs_path), size_when_full) << "a row written while full";
  EXPECT_TRUE(waitFor([&] { return most_unwritten >= 5; }, 10))
      << "unwritten pairs on /diagnostics: " << most_unwritten;
  ASSERT_EQ(std::system((limit + "unlimited:").c_str()), 0);
  EXPECT_TRUE(test::nodeRunning(kNode));
  ASSERT_TRUE(waitFor([&] { return !test::nodeRunning("/player"); }, 180));
  waitFor([] { return false; }, 2.0);
  ASSERT_GT(published.size(), before_kill + 20) << "the respawned node collected nothing";
  EXPECT_EQ(test::nodePid(kNode), new_pid) << "the full disk killed the node";

  const PairsFile file = readPairsCsv(output_directory + "/pairs.csv");
  std::set<std::pair<double, double>> in_file;
  for (const MotionPair& pair : file.pairs)
    in_file.emplace(pair.start_stamp_s, pair.end_stamp_s);
  EXPECT_EQ(in_file.size(), file.pairs.size()) << "a pair was written twice";
  for (const auto& interval : published)
    EXPECT_EQ(in_file.count(interval), 1u) << "pair " << interval.first << " lost";
  // A pair written just before the kill may not have reached this subscriber.
  EXPECT_LE(file.pairs.size(), published.size() + 1);

  odometry_calibration::Calibrate fit;
  fit.request.model = "diff_drive";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  EXPECT_TRUE(fit.response.success) << fit.response.message;
  // The respawned process holds the resumed pairs and its own.
  EXPECT_EQ(fit.response.report.pairs_collected, file.pairs.size());
  std::filesystem::remove_all(output_directory);
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_restart_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
