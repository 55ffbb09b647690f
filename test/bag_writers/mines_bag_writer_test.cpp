#include "odometry_calibration/bag_writers/mines_bag_writer.h"

#include <cmath>
#include <filesystem>
#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

MinesRecord record(std::size_t line, double stamp_s, double left, double right)
{
  MinesRecord r;
  r.line = line;
  r.stamp_s = stamp_s;
  r.left_ticks = left;
  r.right_ticks = right;
  r.ranges_m.assign(kMinesRayCount, 2.0);
  r.ranges_m[5] = std::numeric_limits<double>::infinity();
  return r;
}

class MinesBag : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/mines_bag_writer_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }
  void TearDown() override { fs::remove_all(directory_); }
  std::string directory_;
};

TEST_F(MinesBag, WritesOneJointStateAndOneScanPerRecord)
{
  const std::string path = directory_ + "/mines.bag";
  writeMinesBag({record(1, 100.0, 10, 20), record(2, 100.1, 15, 27)}, path);
  EXPECT_FALSE(fs::exists(path + ".partial"));
  rosbag::Bag bag(path, rosbag::bagmode::Read);
  std::vector<sensor_msgs::JointState> joints;
  std::vector<sensor_msgs::LaserScan> scans;
  for (const rosbag::MessageInstance& message : rosbag::View(bag)) {
    if (auto j = message.instantiate<sensor_msgs::JointState>()) {
      EXPECT_EQ(message.getTopic(), "/joint_states");
      joints.push_back(*j);
    } else if (auto s = message.instantiate<sensor_msgs::LaserScan>()) {
      EXPECT_EQ(message.getTopic(), "/scan");
      scans.push_back(*s);
    }
  }
  ASSERT_EQ(joints.size(), 2u);
  ASSERT_EQ(scans.size(), 2u);
  EXPECT_EQ(joints[1].name, (std::vector<std::string>{"left_wheel", "right_wheel"}));
  EXPECT_EQ(joints[1].position, (std::vector<double>{15, 27}));
  EXPECT_EQ(joints[1].header.seq, 1u);
  EXPECT_NEAR(joints[1].header.stamp.toSec(), 100.1, 1e-6);
  EXPECT_EQ(scans[0].header.frame_id, "laser");
  EXPECT_EQ(scans[0].header.stamp, joints[0].header.stamp);
  ASSERT_EQ(scans[0].ranges.size(), static_cast<std::size_t>(kMinesRayCount));
  EXPECT_FLOAT_EQ(scans[0].ranges[0], 2.0f);
  EXPECT_TRUE(std::isinf(scans[0].ranges[5]));
  EXPECT_FLOAT_EQ(scans[0].time_increment, static_cast<float>(kMinesTimePerRayS));
  EXPECT_FLOAT_EQ(scans[0].range_max, static_cast<float>(kMinesRangeMaxM));
}

TEST_F(MinesBag, FailsWithoutRecordsOrWritableFolderAndLeavesNothing)
{
  EXPECT_THROW(writeMinesBag({}, directory_ + "/empty.bag"), std::runtime_error);
  EXPECT_FALSE(fs::exists(directory_ + "/empty.bag"));
  const std::string path = directory_ + "/no/such/folder/mines.bag";
  EXPECT_ANY_THROW(writeMinesBag({record(1, 100.0, 0, 0)}, path));
  EXPECT_FALSE(fs::exists(path));
  EXPECT_FALSE(fs::exists(path + ".partial"));
}

}  // namespace
}  // namespace odometry_calibration
