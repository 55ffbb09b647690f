// rostest (test/live_node/node_lost_pairs.test, issue 32): the live node whose pairs file cannot
// grow beyond its first rows (RLIMIT_FSIZE, which fails writes as a full disk does, also as root)
// keeps the other pairs in memory; stopped with SIGINT it names how many were lost and exits 3.
// Every pair it published on ~pairs is either a row of pairs.csv or counted as lost.
// Also: the node knows who publishes the scans (issue 32): with `ego_motion.publisher` naming the
// bag player it takes the player's scans (a node that lost the connection's caller id would
// ignore every scan as another publisher's and collect nothing).
#include <fcntl.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <csignal>
#include <cstdlib>
#include <fstream>
#include <string>

#include <gtest/gtest.h>
#include <ros/ros.h>

#include "node_test_support.h"
#include "odometry_calibration/CalibrationPair.h"

namespace odometry_calibration {
namespace {

using test::readText;
using test::waitFor;

/// pairs.csv may not grow beyond this [bytes]: its three header lines and a few rows (a row
/// holds its encoder samples: about 1.5 kB at 50 Hz and 0.5 s keyframes).
constexpr rlim_t kFileSizeLimit = 8000;

/// Starts the node as /lost_pairs with its files limited to kFileSizeLimit bytes (unless
/// `unlimited`), its output into `log_path`; returns its process id. (Between fork and exec only
/// system calls: the parent's ROS threads may hold the allocator's lock.)
pid_t startLimitedNode(const std::string& log_path, bool unlimited = false)
{
  const std::string node =
      std::string(ODOMETRY_CALIBRATION_TOOLS_DIR) + "/odometry_calibration_node";
  const pid_t pid = ::fork();
  if (pid != 0)
    return pid;
  const int log = ::open(log_path.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  ::dup2(log, STDOUT_FILENO);
  ::dup2(log, STDERR_FILENO);
  const rlimit limit{kFileSizeLimit, kFileSizeLimit};
  if (!unlimited)
    ::setrlimit(RLIMIT_FSIZE, &limit);
  ::execl(node.c_str(), node.c_str(), "__name:=lost_pairs", static_cast<char*>(nullptr));
  ::_exit(127);
}

/// The exit status of `pid` within `timeout_s` (-1: still running, then killed).
int waitExit(pid_t pid, double timeout_s)
{
  int status = 0;
  bool exited = false;  // (waitpid reaps once: a second call would say ECHILD)
  waitFor([&] { return exited = exited || ::waitpid(pid, &status, WNOHANG) == pid; }, timeout_s);
  if (!exited) {
    ::kill(pid, SIGKILL);
    ::waitpid(pid, &status, 0);
    return -1;
  }
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

/// Starts the node (startLimitedNode, its log `output_directory`/node.log), plays the first
/// `play_s` seconds of `bag` at 4x with `player_arguments` appended, waits until no new pair
/// came on ~pairs (`pairs`, counted into `published`) for 2 s, then stops the node with SIGINT;
/// returns its exit status (-1 when a step failed, which is reported).
int playToStoppedNode(const std::string& bag, const std::string& output_directory, int play_s,
                      const std::string& player_arguments, bool unlimited,
                      const ros::Subscriber& pairs, const std::atomic<std::size_t>& published)
{
  const std::string log_path = output_directory + "/node.log";
  const pid_t node = startLimitedNode(log_path, unlimited);
  if (node <= 0) {
    ADD_FAILURE() << "fork failed";
    return -1;
  }
  if (!ros::service::waitForService("/lost_pairs/calibrate", ros::Duration(20)) ||
      !waitFor([&] { return pairs.getNumPublishers() > 0; }, 10)) {
    ADD_FAILURE() << "the node did not come up:\n" << readText(log_path);
    ::kill(node, SIGKILL);
    waitExit(node, 5.0);
    return -1;
  }
  const std::string play = "rosbag play --quiet -r 4 -u " + std::to_string(play_s) + " " + bag +
                           " --wait-for-subscribers --topics /joint_states /scan " +
                           player_arguments + " > " + output_directory + "/play.log 2>&1";
  if (std::system(play.c_str()) != 0)
    ADD_FAILURE() << play;
  // Until the matching queue is done: no new pair for 2 s.
  test::waitUntilSettled<std::size_t>([&] { return published.load(); }, 2, 120);
  if (::kill(node, SIGINT) != 0) {
    ADD_FAILURE() << "cannot signal the node";
    return -1;
  }
  return waitExit(node, 20.0);
}

TEST(NodeLostPairs, SigintNamesThePairsTheDiskDidNotTakeAndExitsNonzero)
{
  ros::NodeHandle handle, private_handle("~");
  std::string bag, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  ASSERT_EQ(std::system(("mkdir -p " + output_directory).c_str()), 0);
  std::atomic<std::size_t> published{0};
  // (No spinner: the pairs wait in the queue while the bag plays.)
  ros::Subscriber pairs = handle.subscribe<odometry_calibration::CalibrationPair>(
      "/lost_pairs/pairs", 1000,
      [&](const odometry_calibration::CalibrationPair::ConstPtr&) { ++published; });

  const int status = playToStoppedNode(bag, output_directory, 24, "", false, pairs, published);
  const std::string log = readText(output_directory + "/node.log");
  EXPECT_EQ(status, 3) << log;

  // pairs.csv: three header lines, whole rows only, within the limit.
  const std::string csv = readText(output_directory + "/pairs.csv");
  ASSERT_FALSE(csv.empty());
  EXPECT_LE(csv.size(), kFileSizeLimit);
  EXPECT_EQ(csv.back(), '\n');
  const std::size_t lines = static_cast<std::size_t>(std::count(csv.begin(), csv.end(), '\n'));
  ASSERT_GE(lines, 3u);
  const std::size_t rows = lines - 3;
  EXPECT_GT(rows, 0u);
  ASSERT_GT(published, rows + 5) << "too few pairs to lose: " << published;
  const std::size_t lost = published - rows;
  EXPECT_NE(log.find(std::to_string(lost) + " pairs lost (never written to the pairs file)"),
            std::string::npos)
      << "published " << published << ", rows " << rows << ", log:\n"
      << log;
  RecordProperty("pairs_published", static_cast<int>(published));
  RecordProperty("pairs_lost", static_cast<int>(lost));
}

TEST(NodeLostPairs, TheConfiguredScanPublisherIsTaken)
{
  ros::NodeHandle handle, private_handle("~");
  std::string bag, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  output_directory += "/chosen_publisher";
  ASSERT_EQ(std::system(("mkdir -p " + output_directory).c_str()), 0);
  // diff_drive.yaml with both inputs' publisher chosen: the bag player, named below.
  std::string config = readText(ODOMETRY_CALIBRATION_CONFIG_DIR "/diff_drive.yaml");
  const std::size_t ego = config.find("\nego_motion:\n");
  ASSERT_NE(ego, std::string::npos);
  config.insert(ego + 13, "  publisher: /bag_player\n");
  config += "joint_state_publisher: /bag_player\n";
  const std::string config_path = output_directory + "/chosen.yaml";
  std::ofstream(config_path) << config;
  ros::param::set("/lost_pairs/config", config_path);
  ros::param::set("/lost_pairs/output_directory", output_directory);
  std::atomic<std::size_t> published{0};
  ros::Subscriber pairs = handle.subscribe<odometry_calibration::CalibrationPair>(
      "/lost_pairs/pairs", 1000,
      [&](const odometry_calibration::CalibrationPair::ConstPtr&) { ++published; });

  EXPECT_EQ(
      playToStoppedNode(bag, output_directory, 12, "__name:=bag_player", true, pairs, published),
      0);
  const std::string log = readText(output_directory + "/node.log");
  // 12 s of the bag at 0.5 s keyframes: about 20 pairs, every scan taken.
  EXPECT_GE(published, 15u) << log;
  EXPECT_EQ(log.find("ignoring"), std::string::npos) << log;
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_lost_pairs_test");
  return RUN_ALL_TESTS();
}
