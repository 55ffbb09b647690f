// The one input adapter (ros/message_adapter.h) on malformed messages: the same messages written
// into a bag and run through runBags (calibrate_bag's path), and fed message by message through
// the adapter into a JointCalibrationSession (the live node's callbacks), give the same counts
// and outcomes; a pose with a zero quaternion is skipped and counted in both (not taken for a
// corrupted bag).
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <limits>
#include <memory>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include <gtest/gtest.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>
#include <pcl_conversions/pcl_conversions.h>
#include <rosbag/bag.h>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/ros/message_adapter.h"
#include "odometry_calibration/session/converted_input.h"
#include "odometry_calibration/session/joint_calibration_session.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();
constexpr double kStart_s = 100.0;

using AnyMessage =
    std::variant<sensor_msgs::JointState, sensor_msgs::LaserScan, sensor_msgs::PointCloud2,
                 nav_msgs::Odometry, geometry_msgs::PoseStamped>;

/// One recorded message: its topic and the message (stamped as recorded).
struct Recorded
{
  std::string topic;
  double stamp_s;
  AnyMessage message;
};

sensor_msgs::JointState joints(const std::vector<std::string>& names,
                               const std::vector<double>& positions)
{
  sensor_msgs::JointState message;
  message.name = names;
  message.position = positions;
  return message;
}

/// A scan of `rays` rays of `range_m` over 360 degrees.
sensor_msgs::LaserScan laserScan(std::size_t rays, float range_m, double increment_rad)
{
  sensor_msgs::LaserScan message;
  message.header.frame_id = "laser";
  message.angle_min = -M_PI;
  message.angle_increment = static_cast<float>(increment_rad);
  message.angle_max = static_cast<float>(-M_PI + increment_rad * (rays > 0 ? rays - 1 : 0));
  message.range_min = 0.1f;
  message.range_max = 30.0f;
  message.ranges.assign(rays, range_m);
  return message;
}

/// A cloud of the points `xyz` (x, y, z triples) in `frame`.
sensor_msgs::PointCloud2 cloud(const std::vector<float>& xyz, const std::string& frame)
{
  pcl::PointCloud<pcl::PointXYZ> points;
  for (std::size_t i = 0; i + 2 < xyz.size(); i += 3)
    points.push_back(pcl::PointXYZ(xyz[i], xyz[i + 1], xyz[i + 2]));
  sensor_msgs::PointCloud2 message;
  pcl::toROSMsg(points, message);
  message.header.frame_id = frame;
  return message;
}

/// A room's walls around the lidar: a ring of 3 m radius at three heights in the band.
std::vector<float> ring()
{
  std::vector<float> xyz;
  for (int i = 0; i < 900; ++i) {
    const double bearing = 2.0 * M_PI * i / 900.0;
    for (float z : {-0.1f, 0.0f, 0.1f})
      xyz.insert(xyz.end(), {static_cast<float>(3.0 * std::cos(bearing)),
                             static_cast<float>(3.0 * std::sin(bearing)), z});
  }
  return xyz;
}

geometry_msgs::Pose pose(double x, double qw)
{
  geometry_msgs::Pose message;
  message.position.x = x;
  message.orientation.w = qw;
  return message;
}

nav_msgs::Odometry odometry(const geometry_msgs::Pose& pose)
{
  nav_msgs::Odometry message;
  message.child_frame_id = "tracker";
  message.pose.pose = pose;
  return message;
}

geometry_msgs::PoseStamped poseStamped(const geometry_msgs::Pose& pose)
{
  geometry_msgs::PoseStamped message;
  message.pose = pose;
  return message;
}

/// 2 s of joint states at 50 Hz (three of them malformed: NaN, mismatched arrays, empty
/// arrays) and an ego-motion message every 0.1 s, `bad` first after 0.5 s, the others `good`.
std::vector<Recorded> recording(const std::string& ego_topic, const AnyMessage& good,
                                const std::vector<AnyMessage>& bad)
{
  const std::vector<std::string> wheels = {"left_wheel", "right_wheel"};
  std::vector<Recorded> messages;
  for (int i = 0; i < 100; ++i) {
    sensor_msgs::JointState message = joints(wheels, {10.0 * i, 10.0 * i});
    if (i == 20)
      message.position[1] = kNaN;
    if (i == 40)
      message.position.pop_back();
    if (i == 60)
      message = joints({}, {});
    messages.push_back({"/joint_states", kStart_s + 0.02 * i, message});
    if (i % 5 != 2)
      continue;
    const std::size_t ego = static_cast<std::size_t>(i / 5);
    const bool is_bad = ego >= 5 && ego - 5 < bad.size();
    messages.push_back({ego_topic, kStart_s + 0.02 * i, is_bad ? bad[ego - 5] : good});
  }
  for (Recorded& recorded : messages)
    std::visit([&](auto& m) { m.header.stamp = ros::Time(recorded.stamp_s); }, recorded.message);
  return messages;
}

/// The messages into `path`, in order.
void writeBag(const std::string& path, const std::vector<Recorded>& messages)
{
  rosbag::Bag bag(path, rosbag::bagmode::Write);
  for (const Recorded& recorded : messages) {
    std::visit([&](const auto& m) { bag.write(recorded.topic, ros::Time(recorded.stamp_s), m); },
               recorded.message);
  }
}

/// The messages through the node's path: each converted by the adapter, then fed.
SessionCounts feedAsTheNode(const CalibrationConfig& config, const std::vector<Recorded>& messages)
{
  SessionOptions options;
  options.load_saved_calibration = false;
  options.resume_pairs = false;
  options.assistant = false;
  JointCalibrationSession sessions(config, "", "test", options,
                                   [](std::size_t) { return SessionListener{}; });
  const MessageAdapter adapter(config);
  for (const Recorded& recorded : messages) {
    std::visit(
        [&](const auto& m) {
          if constexpr (std::is_same_v<std::decay_t<decltype(m)>, sensor_msgs::JointState>)
            feedInput(sessions, adapter.convert(m, ""));
          else
            feedInput(sessions, adapter.convert(m, 0, ""));
        },
        recorded.message);
  }
  sessions.flush();
  return sessions.source(0).counts();
}

class MessageAdapterParity : public ::testing::Test
{
protected:
  void SetUp() override
  {
    directory_ = fs::temp_directory_path() /
                 ("message_adapter_" + std::to_string(::getpid()) + "_" +
                  ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// Both paths' counts, checked equal field by field; the bag path's are returned.
  SessionCounts bothPaths(const CalibrationConfig& config, const std::vector<Recorded>& messages)
  {
    const std::string bag = (directory_ / "malformed.bag").string();
    writeBag(bag, messages);
    const BagRunResult run = runBags({bag}, config);
    const SessionCounts from_bag = run.counts;
    const SessionCounts from_node = feedAsTheNode(config, messages);
    EXPECT_EQ(from_bag.encoder_messages, from_node.encoder_messages);
    EXPECT_EQ(from_bag.ego_messages, from_node.ego_messages);
    EXPECT_EQ(from_bag.bad_encoder_messages, from_node.bad_encoder_messages);
    EXPECT_EQ(from_bag.bad_ego_messages, from_node.bad_ego_messages);
    EXPECT_EQ(from_bag.first_bad_encoder_message, from_node.first_bad_encoder_message);
    EXPECT_EQ(from_bag.first_bad_ego_message, from_node.first_bad_ego_message);
    EXPECT_EQ(from_bag.clouds_without_times, from_node.clouds_without_times);
    EXPECT_EQ(from_bag.first_cloud_time_problem, from_node.first_cloud_time_problem);
    EXPECT_EQ(from_bag.statistics.scans, from_node.statistics.scans);
    EXPECT_EQ(from_bag.restart_count, from_node.restart_count);
    EXPECT_EQ(run.pairs.size(), from_node.pairs);
    // Every JointState and ego-motion message reached the session, the bad ones counted.
    EXPECT_EQ(from_bag.encoder_messages, 100u);
    EXPECT_EQ(from_bag.ego_messages, 20u);
    EXPECT_EQ(from_bag.bad_encoder_messages, 3u);
    EXPECT_EQ(from_bag.first_bad_encoder_message,
              "JointState position of joint 'right_wheel' is not a finite number");
    return from_bag;
  }

  fs::path directory_;
};

TEST_F(MessageAdapterParity, LaserScansSkippedAlikeInBothPaths)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  const double increment_rad = 2.0 * M_PI / 360.0;
  const std::vector<AnyMessage> bad = {
      laserScan(360, 2.0f, 0.0),                         // angle_increment 0
      laserScan(360, kNaN, increment_rad),               // NaN ranges only
      laserScan(0, 2.0f, increment_rad),                 // no ranges at all
      laserScan(config.max_scan_rays + 1, 2.0f, 1e-4)};  // too many rays
  const SessionCounts counts =
      bothPaths(config, recording("/scan", laserScan(360, 2.0f, increment_rad), bad));
  EXPECT_EQ(counts.bad_ego_messages, 4u);
  EXPECT_NE(counts.first_bad_ego_message.find("angle_increment"), std::string::npos)
      << counts.first_bad_ego_message;
  EXPECT_EQ(counts.statistics.scans, 16u);
}

TEST_F(MessageAdapterParity, CloudsSkippedAlikeInBothPathsWithTheSessionsFrameRule)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive_lidar3d.yaml");
  const std::vector<AnyMessage> bad = {
      cloud(ring(), "another_lidar"),  // not the first cloud's frame
      cloud(ring(), ""),               // no frame
      cloud({}, "lidar"),              // no points
      cloud({kNaN, kNaN, kNaN}, "lidar")};
  const SessionCounts counts = bothPaths(config, recording("/points", cloud(ring(), "lidar"), bad));
  EXPECT_EQ(counts.bad_ego_messages, 4u);
  EXPECT_EQ(counts.first_bad_ego_message,
            "PointCloud2 in frame 'another_lidar', not the sensor's frame 'lidar' (the first "
            "cloud's)");
  EXPECT_EQ(counts.statistics.scans, 16u);
}

TEST_F(MessageAdapterParity, ZeroQuaternionOdometrySkippedAndCountedInBothPaths)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  config.ego_motion = EgoMotionSource::kOdometry;
  config.ego_motion_topic = "/odom";
  const std::vector<AnyMessage> bad = {odometry(pose(0.0, 0.0)), odometry(pose(0.0, kNaN))};
  const SessionCounts counts = bothPaths(config, recording("/odom", odometry(pose(0, 1)), bad));
  EXPECT_EQ(counts.bad_ego_messages, 2u);
  EXPECT_EQ(counts.first_bad_ego_message, "transform rotation is not a valid quaternion");
}

TEST_F(MessageAdapterParity, ZeroQuaternionPoseSkippedAndCountedInBothPaths)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  config.ego_motion = EgoMotionSource::kPose;
  config.ego_motion_topic = "/tracker/pose";
  const std::vector<AnyMessage> bad = {poseStamped(pose(0.0, 0.0)), poseStamped(pose(0.0, kNaN))};
  const SessionCounts counts =
      bothPaths(config, recording("/tracker/pose", poseStamped(pose(0, 1)), bad));
  EXPECT_EQ(counts.bad_ego_messages, 2u);
  EXPECT_EQ(counts.first_bad_ego_message, "transform rotation is not a valid quaternion");
}

/// A session for `config` as feedAsTheNode makes it.
std::unique_ptr<JointCalibrationSession> quietSession(const CalibrationConfig& config)
{
  SessionOptions options;
  options.load_saved_calibration = false;
  options.resume_pairs = false;
  options.assistant = false;
  options.keep_encoder_history = true;
  return std::make_unique<JointCalibrationSession>(config, "", "test", options,
                                                   [](std::size_t) { return SessionListener{}; });
}

TEST(MessageAdapterWheels, VelocityOnlyJointStatesAreIntegratedAndPositionsOnlyOnesNamed)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  config.wheels.source = WheelSource::kJointVelocity;
  config.joints[1].sign = -1.0;
  const MessageAdapter adapter(config);
  sensor_msgs::JointState message;
  message.name = {"right_wheel", "left_wheel"};
  message.velocity = {-200.0, 100.0};  // ticks/s
  const ConvertedInput input = adapter.convert(message, "");
  ASSERT_EQ(input.kind, ConvertedInput::Kind::kJointVelocities) << input.problem;
  EXPECT_EQ(input.raw(0), 100.0);  // the joints' order, no signs yet
  EXPECT_EQ(input.raw(1), -200.0);
  const ConvertedInput positions =
      adapter.convert(joints({"left_wheel", "right_wheel"}, {1, 2}), "");
  EXPECT_EQ(positions.kind, ConvertedInput::Kind::kBadJoints);
  EXPECT_NE(positions.problem.find("set wheels.source joint_state"), std::string::npos)
      << positions.problem;
  // Through the session: 0.5 s at these speeds, the sign applied after the integration.
  const auto sessions = quietSession(config);
  for (int k = 0; k <= 25; ++k) {
    message.header.stamp = ros::Time(kStart_s + 0.02 * k);
    feedInput(*sessions, adapter.convert(message, ""));
  }
  feedInput(*sessions, positions);
  sessions->flush();
  const SessionCounts counts = sessions->source(0).counts();
  EXPECT_EQ(counts.encoder_messages, 27u);
  EXPECT_EQ(counts.bad_encoder_messages, 1u);
  const Eigen::VectorXd last = sessions->source(0).encoderHistory().back().values;
  EXPECT_NEAR(last(0), 50.0, 1e-9);   // 100 ticks/s for 0.5 s
  EXPECT_NEAR(last(1), 100.0, 1e-9);  // -200 ticks/s, sign -1
}

TEST(MessageAdapterWheels, BaseOdometryBecomesItsPathAndHeadingJoints)
{
  const CalibrationConfig config =
      loadCalibrationConfig(kConfig + "/base_odometry.yaml");  // wheels.source odometry
  ASSERT_EQ(config.joints.size(), 3u);
  const MessageAdapter adapter(config);
  const auto sessions = quietSession(config);
  // Driving along the odom frame's +y (yaw pi/2) at 0.5 m/s, turning 0.2 rad/s, for 0.5 s.
  for (int k = 0; k <= 25; ++k) {
    const double t = 0.02 * k, yaw = M_PI / 2 + 0.2 * t;
    geometry_msgs::Pose base;
    base.position.x = 3.0 + 2.5 * (std::sin(yaw) - 1.0);  // the arc of radius 2.5 m
    base.position.y = 1.0 - 2.5 * std::cos(yaw);
    base.orientation.z = std::sin(yaw / 2);
    base.orientation.w = std::cos(yaw / 2);
    nav_msgs::Odometry message = odometry(base);
    message.header.stamp = ros::Time(kStart_s + t);
    const ConvertedInput input = adapter.convertBaseOdometry(message, "base");
    ASSERT_EQ(input.kind, ConvertedInput::Kind::kBaseOdometry) << input.problem;
    feedInput(*sessions, input);
  }
  nav_msgs::Odometry broken = odometry(pose(0.0, 0.0));  // a zero quaternion
  broken.header.stamp = ros::Time(kStart_s + 0.6);
  const ConvertedInput refused = adapter.convertBaseOdometry(broken, "base");
  EXPECT_EQ(refused.kind, ConvertedInput::Kind::kBadJoints);
  feedInput(*sessions, refused);
  sessions->flush();
  const SessionCounts counts = sessions->source(0).counts();
  EXPECT_EQ(counts.encoder_messages, 27u);
  EXPECT_EQ(counts.bad_encoder_messages, 1u);
  EXPECT_NE(counts.first_bad_encoder_message.find("base odometry"), std::string::npos)
      << counts.first_bad_encoder_message;
  // In base_link, whatever the odom frame: each 20 ms chord of the arc, R sin(w dt) forward
  // and 2 R sin^2(w dt / 2) to the left, summed over 25 messages; the turn.
  const Eigen::VectorXd last = sessions->source(0).encoderHistory().back().values;
  EXPECT_NEAR(last(0), 25 * 2.5 * std::sin(0.004), 1e-9);
  EXPECT_NEAR(last(1), 25 * 5.0 * std::pow(std::sin(0.002), 2), 1e-9);
  EXPECT_NEAR(last(2), 0.1, 1e-9);
}

TEST(MessageAdapterWheels, TicksOfTwoTopicsBecomeJointSamplesAndAliasingIsCounted)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  config.wheels.source = WheelSource::kTicks;
  config.wheels.topics = {"/lwheel", "/rwheel"};
  config.wheels.message_type = "std_msgs/Int16";
  config.joints[0].counter_bits = config.joints[1].counter_bits = 8;
  const MessageAdapter adapter(config);
  EXPECT_EQ(adapter.convertWheelTick(std::nan(""), 1, kStart_s, "").kind,
            ConvertedInput::Kind::kBadJoints);
  const auto sessions = quietSession(config);
  for (int k = 0; k < 50; ++k) {  // 50 ticks per 31.25 ms on both wheels, right 7 ms later
    const double t = kStart_s + 0.03125 * k;
    feedInput(*sessions, adapter.convertWheelTick((50 * k) % 256, 0, t, ""));
    feedInput(*sessions, adapter.convertWheelTick((50 * k + 11) % 256 - 128, 1, t + 0.007, ""));
  }
  sessions->flush();
  SessionCounts counts = sessions->source(0).counts();
  EXPECT_EQ(counts.bad_encoder_messages, 0u) << counts.first_bad_encoder_message;
  EXPECT_EQ(counts.encoder_messages, 49u);  // the first left instant precedes the right wheel
  // Counted from the first joint sample (k = 1), taken at the left wheel's instants.
  const EncoderSample last = sessions->source(0).encoderHistory().back();
  EXPECT_DOUBLE_EQ(last.stamp_s, kStart_s + 0.03125 * 49);
  EXPECT_NEAR(last.values(0), 50.0 * 48, 1e-9);  // across 9 wraps of the 8-bit counter
  EXPECT_NEAR(last.values(1), 50.0 * 48, 1e-9);
  // A jump of 150 ticks in one message (more than half of 256): refused, named, counted.
  feedInput(*sessions, adapter.convertWheelTick((50 * 49 + 150) % 256, 0, kStart_s + 1.6, ""));
  counts = sessions->source(0).counts();
  EXPECT_EQ(counts.bad_encoder_messages, 1u);
  EXPECT_NE(counts.first_bad_encoder_message.find("joints[0].counter_bits 8"), std::string::npos)
      << counts.first_bad_encoder_message;
}

}  // namespace
}  // namespace odometry_calibration
