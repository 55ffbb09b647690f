// The session's record of its collectors' inputs: everything replayed exactly, in order (scans
// read back from the scratch file with their ranges as float when that is exact, else as
// double), a view from a later input, and a cleared record.
#include "odometry_calibration/session/input_record.h"

#include <cmath>
#include <limits>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

/// What a replay saw, in order, as text and values.
struct Replayed
{
  std::vector<std::string> kinds;
  std::vector<Eigen::VectorXd> encoders;
  std::vector<Scan> scans;
  std::vector<Pose2> poses;
  std::vector<double> stamps_s;
};

Replayed replay(const InputRecordView& view)
{
  Replayed seen;
  RecordedInputVisitor visitor;
  visitor.encoders = [&](double stamp_s, const Eigen::VectorXd& raw) {
    seen.kinds.push_back("encoders");
    seen.encoders.push_back(raw);
    seen.stamps_s.push_back(stamp_s);
  };
  visitor.scan = [&](double stamp_s, const Scan& scan) {
    seen.kinds.push_back("scan");
    seen.scans.push_back(scan);
    seen.stamps_s.push_back(stamp_s);
  };
  visitor.sensor_pose = [&](double stamp_s, const Pose2& pose, const Eigen::Matrix3d&) {
    seen.kinds.push_back("pose");
    seen.poses.push_back(pose);
    seen.stamps_s.push_back(stamp_s);
  };
  visitor.flush = [&] { seen.kinds.push_back("flush"); };
  view.replay(visitor);
  return seen;
}

/// A scan whose ranges are all float values (a LaserScan's), with a NaN and an inf.
Scan floatScan()
{
  Scan scan;
  scan.ranges_m = {1.25, static_cast<double>(2.7f), std::nan(""),
                   std::numeric_limits<double>::infinity()};
  std::tie(scan.angle_min_rad, scan.angle_increment_rad) = std::make_pair(-1.5, 0.01);
  std::tie(scan.range_min_m, scan.range_max_m) = std::make_pair(0.1, 30.0);
  scan.time_increment_s = 1e-4;
  scan.valid = {1, 0, 1, 1};
  return scan;
}

/// A scan made from a cloud: double ranges, per-ray times and bearings.
Scan cloudScan()
{
  Scan scan = floatScan();
  scan.ranges_m = {1.0 / 3.0, 2.0 / 7.0, 0.1, 5.0};
  scan.valid.clear();
  scan.ray_times_s = {0.0, 0.001, 0.002, 0.0031};
  scan.ray_angles_rad = {-1.5, -1.49, -1.4801, -1.47};
  return scan;
}

void expectSameScan(const Scan& a, const Scan& b)
{
  EXPECT_EQ(a.angle_min_rad, b.angle_min_rad);
  EXPECT_EQ(a.angle_increment_rad, b.angle_increment_rad);
  EXPECT_EQ(a.range_min_m, b.range_min_m);
  EXPECT_EQ(a.range_max_m, b.range_max_m);
  EXPECT_EQ(a.time_increment_s, b.time_increment_s);
  ASSERT_EQ(a.ranges_m.size(), b.ranges_m.size());
  for (std::size_t i = 0; i < a.ranges_m.size(); ++i) {
    if (std::isnan(a.ranges_m[i]))
      EXPECT_TRUE(std::isnan(b.ranges_m[i])) << i;
    else
      EXPECT_EQ(a.ranges_m[i], b.ranges_m[i]) << i;  // bit for bit, not rounded to float
  }
  EXPECT_EQ(a.valid, b.valid);
  EXPECT_EQ(a.ray_times_s, b.ray_times_s);
  EXPECT_EQ(a.ray_angles_rad, b.ray_angles_rad);
}

TEST(InputRecord, ReplaysEveryInputExactlyAndInOrder)
{
  InputRecord record("");
  record.addEncoders(1.0, Eigen::Vector2d(10.0, -3.5));
  record.addScan(1.05, floatScan());
  record.addEncoders(1.1, Eigen::Vector2d(11.0, -2.5));
  record.addSensorPose(1.15, Pose2(0.5, -0.25, 0.1), Eigen::Matrix3d::Identity());
  record.addScan(1.2, cloudScan());
  record.addFlush();
  EXPECT_EQ(record.size(), 6u);
  EXPECT_GT(record.spilledBytes(), 0u);
  const Replayed seen = replay(record.view());
  EXPECT_EQ(seen.kinds,
            (std::vector<std::string>{"encoders", "scan", "encoders", "pose", "scan", "flush"}));
  EXPECT_EQ(seen.stamps_s, (std::vector<double>{1.0, 1.05, 1.1, 1.15, 1.2}));
  ASSERT_EQ(seen.encoders.size(), 2u);
  EXPECT_EQ(seen.encoders[1], Eigen::Vector2d(11.0, -2.5));
  ASSERT_EQ(seen.scans.size(), 2u);
  expectSameScan(floatScan(), seen.scans[0]);
  expectSameScan(cloudScan(), seen.scans[1]);
  ASSERT_EQ(seen.poses.size(), 1u);
  EXPECT_EQ(seen.poses[0].y(), -0.25);
}

TEST(InputRecord, AViewFromALaterInputHoldsOnlyTheRest)
{
  InputRecord record("");
  for (int k = 0; k < 5; ++k) {
    record.addEncoders(k, Eigen::Vector2d(k, 2.0 * k));
    Scan scan = floatScan();
    scan.ranges_m[0] = 1.0 + k;
    record.addScan(k + 0.5, scan);
  }
  const InputRecordView all = record.view();
  record.addEncoders(5.0, Eigen::Vector2d(5.0, 10.0));  // after the view: not in it
  EXPECT_EQ(all.size(), 10u);
  EXPECT_EQ(replay(all).kinds.size(), 10u);
  const Replayed rest = replay(record.view(7));  // the 4th scan on
  EXPECT_EQ(rest.kinds, (std::vector<std::string>{"scan", "encoders", "scan", "encoders"}));
  ASSERT_EQ(rest.scans.size(), 2u);
  EXPECT_EQ(rest.scans[0].ranges_m[0], 4.0);
  EXPECT_EQ(rest.scans[1].ranges_m[0], 5.0);
  ASSERT_EQ(rest.encoders.size(), 2u);
  EXPECT_EQ(rest.encoders[0], Eigen::Vector2d(4.0, 8.0));
  EXPECT_EQ(rest.encoders[1], Eigen::Vector2d(5.0, 10.0));
  // A view taken before clear() still replays from its own file; the record starts empty.
  record.clear();
  EXPECT_EQ(record.size(), 0u);
  EXPECT_EQ(record.spilledBytes(), 0u);
  EXPECT_EQ(replay(all).scans.size(), 5u);
  record.addEncoders(6.0, Eigen::Vector2d(6.0, 12.0));
  EXPECT_THROW(record.addEncoders(6.1, Eigen::Vector3d(1.0, 2.0, 3.0)), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
