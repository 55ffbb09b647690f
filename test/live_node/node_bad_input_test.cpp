// rostest (test/node_bad_input.test): each kind of bad input gets its message from the node,
// which keeps running (its services still answer at the end).
#include <cmath>
#include <filesystem>
#include <map>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <nav_msgs/Odometry.h>
#include <ros/ros.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <std_srvs/Trigger.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"

namespace odometry_calibration {
namespace {

using test::waitFor;
const std::string kNode = "/odometry_calibration";

class NodeBadInput : public testing::Test
{
protected:
  void SetUp() override
  {
    log_ = std::make_unique<test::LogCapture>(handle_, kNode);
    joints_ = handle_.advertise<sensor_msgs::JointState>("/joint_states", 100);
    scans_ = handle_.advertise<sensor_msgs::LaserScan>("/scan", 100);
    ASSERT_TRUE(ros::service::waitForService(kNode + "/calibrate", ros::Duration(30)));
    ASSERT_TRUE(waitFor(
        [&] { return joints_.getNumSubscribers() > 0 && scans_.getNumSubscribers() > 0; }, 10));
    waitFor([] { return false; }, 0.5);  // the /rosout connection
  }

  sensor_msgs::JointState joints(double stamp_s, double left, double right)
  {
    sensor_msgs::JointState m;
    m.header.stamp = ros::Time(stamp_s);
    m.name = {"left_wheel", "right_wheel"};
    m.position = {left, right};
    return m;
  }

  /// Publishes until the node logs `text` (the node's /rosout publisher may connect late).
  bool expectLog(const std::function<void()>& publish, const std::string& text)
  {
    return waitFor(
        [&] {
          publish();
          return log_->contains(text);
        },
        15);
  }

  ros::NodeHandle handle_;
  std::unique_ptr<test::LogCapture> log_;
  ros::Publisher joints_, scans_;
};

TEST_F(NodeBadInput, EachProblemIsNamedAndTheNodeSurvives)
{
  // Silent topics: named after the 1 s timeout (two log lines, which may reach /rosout apart).
  EXPECT_TRUE(waitFor(
      [&] {
        return log_->contains("no message on '/joint_states'") &&
               log_->contains("no message on '/scan'");
      },
      15))
      << log_->all();

  // JointState without the configured joints.
  sensor_msgs::JointState other = joints(100.0, 0, 0);
  other.name = {"front_wheel", "rear_wheel"};
  EXPECT_TRUE(
      expectLog([&] { joints_.publish(other); },
                "lacks the configured joint 'left_wheel': it has 'front_wheel', 'rear_wheel'"))
      << log_->all();

  // Mismatched arrays.
  sensor_msgs::JointState mismatched = joints(100.0, 0, 0);
  mismatched.position = {1.0};
  EXPECT_TRUE(expectLog([&] { joints_.publish(mismatched); }, "JointState has 2 names"))
      << log_->all();

  // NaN positions.
  EXPECT_TRUE(
      expectLog([&] { joints_.publish(joints(100.0, std::nan(""), 0)); }, "is not a finite number"))
      << log_->all();

  // A scan of NaN ranges.
  sensor_msgs::LaserScan scan;
  scan.header.stamp = ros::Time(100.0);
  scan.header.frame_id = "laser";
  scan.angle_min = -2.0;
  scan.angle_increment = 4.0 / 681;
  scan.angle_max = 2.0;
  scan.range_min = 0.05;
  scan.range_max = 20.0;
  scan.ranges.assign(682, std::nanf(""));
  EXPECT_TRUE(expectLog([&] { scans_.publish(scan); }, "only 0 of 682 ranges are usable"))
      << log_->all();

  // A scan with an impossible geometry.
  sensor_msgs::LaserScan broken = scan;
  broken.ranges.assign(682, 3.0f);
  broken.angle_increment = 0.0;
  EXPECT_TRUE(expectLog([&] { scans_.publish(broken); }, "LaserScan on /scan skipped"))
      << log_->all();

  // Time going backwards (a looping bag).
  double t = 200.0;
  EXPECT_TRUE(expectLog(
      [&] {
        joints_.publish(joints(t, 1000, 1000));
        joints_.publish(joints(t - 50.0, 0, 0));
        t += 0.1;
      },
      "time went backwards"))
      << log_->all();

  // Services: too few pairs, unknown model, bad options, a model the joints cannot serve,
  // nothing to save.
  odometry_calibration::Calibrate fit;
  fit.request.model = "diff_drive";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  EXPECT_FALSE(fit.response.success);
  EXPECT_NE(fit.response.message.find("only 0 pairs collected"), std::string::npos)
      << fit.response.message;
  fit.request.model = "unicycle";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  EXPECT_FALSE(fit.response.success);
  EXPECT_NE(fit.response.message.find("unknown model 'unicycle'"), std::string::npos)
      << fit.response.message;
  fit.request.model = "gp";
  fit.request.options = "{joints: []}";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  EXPECT_FALSE(fit.response.success);
  EXPECT_NE(fit.response.message.find("'joints' cannot be changed per call"), std::string::npos)
      << fit.response.message;
  // A model the configuration's joints cannot serve: said before any fit.
  fit.request.model = "tricycle";
  fit.request.options = "";
  ASSERT_TRUE(ros::service::call(kNode + "/calibrate", fit));
  EXPECT_FALSE(fit.response.success);
  EXPECT_NE(fit.response.message.find("cannot fit tricycle"), std::string::npos)
      << fit.response.message;
  EXPECT_NE(fit.response.message.find("steering joint must be kind: absolute"), std::string::npos)
      << fit.response.message;
  std_srvs::Trigger save;
  ASSERT_TRUE(ros::service::call(kNode + "/save", save));
  EXPECT_FALSE(save.response.success);
  EXPECT_NE(save.response.message.find("nothing to save"), std::string::npos);

  // Still alive and answering.
  std_srvs::Trigger reset;
  ASSERT_TRUE(ros::service::call(kNode + "/reset", reset));
  EXPECT_TRUE(reset.response.success) << reset.response.message;
  EXPECT_TRUE(test::nodeRunning(kNode));
  std::string output_directory;
  if (ros::NodeHandle("~").getParam("output_directory", output_directory))
    std::filesystem::remove_all(output_directory);
}

TEST_F(NodeBadInput, EncoderGlitchesAreCountedAndDoNotMoveTheOdometry)
{
  nav_msgs::Odometry last_odom;
  std::map<std::string, std::string> diagnostics;
  ros::Subscriber odom = handle_.subscribe<nav_msgs::Odometry>(
      kNode + "/odom", 100, [&](const nav_msgs::Odometry::ConstPtr& m) { last_odom = *m; });
  ros::Subscriber status = handle_.subscribe<diagnostic_msgs::DiagnosticArray>(
      "/diagnostics", 10, [&](const diagnostic_msgs::DiagnosticArray::ConstPtr& m) {
        for (const auto& s : m->status)
          for (const auto& v : s.values)
            diagnostics[v.key] = v.value;
      });
  ASSERT_TRUE(waitFor([&] { return odom.getNumPublishers() > 0; }, 10));
  // Straight driving, 20 ticks per 20 ms on each wheel (0.5 turn/s), with a 1e300 position on
  // the left wheel and a 1e6-tick spike on the right one.
  const double start_s = 1000.0;
  for (int k = 0; k <= 40; ++k) {
    double left = 20.0 * k, right = 20.0 * k;
    if (k == 10)
      left = 1e300;
    if (k == 20)
      right += 1e6;
    joints_.publish(joints(start_s + 0.02 * k, left, right));
    ros::WallDuration(0.002).sleep();
  }
  ASSERT_TRUE(waitFor([&] { return last_odom.header.stamp.toSec() >= start_s + 0.79; }, 10));
  // 800 ticks of 2000 per turn on wheels of 0.077 m (config/diff_drive.yaml's nominal robot).
  const double expected_m = 800.0 / 2000.0 * 2.0 * M_PI * 0.077;
  EXPECT_NEAR(last_odom.pose.pose.position.x, expected_m, 0.005);
  EXPECT_NEAR(last_odom.pose.pose.position.y, 0.0, 0.005);
  EXPECT_TRUE(waitFor(
      [&] {
        return diagnostics["encoder glitches: left_wheel"] == "1" &&
               diagnostics["encoder glitches: right_wheel"] == "1";
      },
      10))
      << diagnostics["encoder glitches: left_wheel"] << " "
      << diagnostics["encoder glitches: right_wheel"];
  EXPECT_TRUE(log_->contains("encoder glitch on joint 'left_wheel'")) << log_->all();
  EXPECT_TRUE(test::nodeRunning(kNode));
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_bad_input_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
