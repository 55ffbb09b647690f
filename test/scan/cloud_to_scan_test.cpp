// A 3D lidar's cloud into a planar scan: the height band, the levelling of a tilted sensor,
// the per-point times, and the clouds that give no scan (each with its message).
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include "odometry_calibration/scan/cloud_to_scan.h"

namespace odometry_calibration {
namespace {

constexpr double kHeight = 0.5;  // sensor above the floor [m]

/// Horizontal distance from the sensor (at the origin) to the walls of a room centred on it,
/// 2 half_x by 2 half_y (10 m x 8 m unless said), along `bearing`.
double wallDistance(double bearing, double half_x = 5.0, double half_y = 4.0)
{
  const double c = std::abs(std::cos(bearing)), s = std::abs(std::sin(bearing));
  return std::min(c > 1e-12 ? half_x / c : 1e9, s > 1e-12 ? half_y / s : 1e9);
}

/// A 16-ring (+-15 deg) sweep of that room with a floor 0.5 m below the sensor: 900 columns,
/// column k taken at k * 0.1 ms. R_sensor_level turns each point from the level frame into the
/// sensor's (a tilted sensor).
TimedCloud roomCloud(const Eigen::Matrix3d& R_sensor_level = Eigen::Matrix3d::Identity(),
                     double half_x = 5.0, double half_y = 4.0)
{
  TimedCloud cloud;
  for (int k = 0; k < 900; ++k) {
    const double bearing = -M_PI + 2.0 * M_PI * (k + 0.5) / 900.0;
    for (int ring = 0; ring < 16; ++ring) {
      const double elevation = (-15.0 + 2.0 * ring) * M_PI / 180.0;
      double horizontal = wallDistance(bearing, half_x, half_y);
      if (elevation < 0.0)
        horizontal = std::min(horizontal, kHeight / std::tan(-elevation));  // the floor
      const Eigen::Vector3d level(horizontal * std::cos(bearing), horizontal * std::sin(bearing),
                                  horizontal * std::tan(elevation));
      const Eigen::Vector3d p = R_sensor_level * level;
      pcl::PointXYZI point;
      point.x = static_cast<float>(p.x());
      point.y = static_cast<float>(p.y());
      point.z = static_cast<float>(p.z());
      point.intensity = static_cast<float>(1e-4 * k);
      cloud.push_back(point);
    }
  }
  return cloud;
}

/// cloudToScan on a copy of `cloud`.
Scan cloudToScan(const TimedCloud& cloud, bool has_times, const CloudToScanOptions& options,
                 CloudToScanCounts* counts = nullptr)
{
  return odometry_calibration::cloudToScan(std::make_shared<TimedCloud>(cloud), has_times, options,
                                           counts);
}

/// Largest |range - wall distance| over the scan's rays, and how many rays hold a range.
std::pair<double, std::size_t> wallError(const Scan& scan, double half_x = 5.0, double half_y = 4.0)
{
  double worst = 0.0;
  std::size_t rays = 0;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    if (std::isnan(scan.ranges_m[i]))
      continue;
    ++rays;
    const double bearing = scan.angle_min_rad + scan.angle_increment_rad * static_cast<double>(i);
    worst = std::max(worst, std::abs(scan.ranges_m[i] - wallDistance(bearing, half_x, half_y)));
  }
  return {worst, rays};
}

TEST(CloudToScan, KeepsTheWallsInTheBandAndDropsTheFloor)
{
  CloudToScanOptions options;
  options.voxel_size_m = 0.0;
  options.angular_resolution_rad = 2.0 * M_PI / 900.0;
  CloudToScanCounts counts;
  const Scan scan = cloudToScan(roomCloud(), true, options, &counts);
  EXPECT_EQ(counts.input, 900u * 16u);
  EXPECT_EQ(counts.finite, counts.input);
  // In the +-0.3 m band: the +-1 deg rings everywhere (<= 6.4 m), +-3 deg within 5.7 m; the
  // floor (0.5 m below) never.
  EXPECT_GT(counts.band, 2u * 900u);
  EXPECT_LT(counts.band, 4u * 900u);
  const auto [worst, rays] = wallError(scan);
  EXPECT_EQ(rays, 900u);
  // A point lies in its bin up to half a bin off its centre: at 6.4 m, 6.4 * 0.0035 * tan(39 deg)
  EXPECT_LT(worst, 0.02);
  // The ray times are the points' (column k at 0.1 ms k).
  ASSERT_EQ(scan.ray_times_s.size(), 900u);
  EXPECT_NEAR(scan.ray_times_s[0], 0.0, 1e-6);
  EXPECT_NEAR(scan.ray_times_s[450], 0.045, 1e-6);
  EXPECT_NEAR(sweepDuration(scan), 0.0899, 1e-6);
}

TEST(CloudToScan, WithoutTimesTheScanHasNoRayTimes)
{
  const Scan scan = cloudToScan(roomCloud(), false, CloudToScanOptions());
  EXPECT_TRUE(scan.ray_times_s.empty());
  EXPECT_FALSE(hasRayTimes(scan));
}

TEST(CloudToScan, ATiltedSensorIsLevelledByItsConfiguredPitch)
{
  // Pitched 2 deg nose down in a 30 m x 30 m hall: the cloud in the sensor's frame is R^T
  // times the level one.
  const double pitch = 2.0 * M_PI / 180.0;
  const Eigen::Matrix3d R_level_sensor =
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const TimedCloud tilted = roomCloud(R_level_sensor.transpose(), 15.0, 15.0);
  CloudToScanOptions options;
  options.voxel_size_m = 0.0;
  options.angular_resolution_rad = 2.0 * M_PI / 900.0;
  // Not levelled, the sensor's -1 deg ring looks 3 deg down ahead and meets the floor 9.5 m
  // out, 0.17 m below the sensor's plane: inside its band, in front of the 15 m wall.
  EXPECT_GT(wallError(cloudToScan(tilted, true, options), 15.0, 15.0).first, 5.0);
  options.pitch_rad = pitch;
  const auto [worst, rays] = wallError(cloudToScan(tilted, true, options), 15.0, 15.0);
  EXPECT_GT(rays, 500u);  // towards the corners (21 m) the +-1 deg rings leave the band
  EXPECT_LT(worst, 0.1);  // half a bin at 15 m and 45 deg incidence: 15 * 0.0035
}

TEST(CloudToScan, TheVoxelGridThinsTheCloudAndKeepsTheWalls)
{
  CloudToScanOptions options;  // 5 cm voxels
  options.angular_resolution_rad = 2.0 * M_PI / 900.0;
  CloudToScanCounts counts;
  const Scan scan = cloudToScan(roomCloud(), true, options, &counts);
  EXPECT_LT(counts.voxels, counts.band);
  const auto [worst, rays] = wallError(scan);
  EXPECT_GT(rays, 600u);   // 5 cm voxels are wider than a 0.4 deg bin at 4 m: some bins stay empty
  EXPECT_LT(worst, 0.05);  // a voxel's centroid is within its 5 cm
}

TEST(CloudToScan, OutlierRemovalDropsIsolatedPoints)
{
  TimedCloud cloud = roomCloud();
  for (int k = 0; k < 5; ++k) {  // specks floating in the room, in the band
    pcl::PointXYZI speck;
    speck.x = 1.0f + 0.5f * static_cast<float>(k);
    speck.y = -1.5f;
    speck.z = 0.1f;
    speck.intensity = 0.0f;
    cloud.push_back(speck);
  }
  CloudToScanOptions options;
  options.voxel_size_m = 0.0;
  options.angular_resolution_rad = 2.0 * M_PI / 900.0;
  EXPECT_GT(wallError(cloudToScan(cloud, true, options)).first, 1.0);  // the specks are rays
  options.outlier_neighbours = 8;
  CloudToScanCounts counts;
  const Scan scan = cloudToScan(cloud, true, options, &counts);
  EXPECT_LE(counts.kept, counts.voxels - 5);
  EXPECT_LT(wallError(scan).first, 0.02);
}

TEST(CloudToScan, NanPointsAreDroppedAndCounted)
{
  TimedCloud cloud = roomCloud();
  const float nan = std::numeric_limits<float>::quiet_NaN();
  for (std::size_t i = 0; i < cloud.size(); i += 3)
    cloud[i].x = nan;
  CloudToScanCounts counts;
  const Scan scan = cloudToScan(cloud, true, CloudToScanOptions(), &counts);
  EXPECT_EQ(counts.finite, counts.input - (counts.input + 2) / 3);
  EXPECT_GT(wallError(scan).second, 500u);
}

/// The message of what cloudToScan throws ("" if it does not).
std::string rejection(const TimedCloud& cloud, const CloudToScanOptions& options = {})
{
  try {
    cloudToScan(cloud, true, options);
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

TEST(CloudToScan, CloudsThatGiveNoScanAreRejectedSayingWhy)
{
  EXPECT_EQ(rejection(TimedCloud()), "the cloud is empty");

  TimedCloud all_nan = roomCloud();
  for (auto& point : all_nan.points)
    point.z = std::numeric_limits<float>::quiet_NaN();
  const std::string nan_message = rejection(all_nan);
  EXPECT_NE(nan_message.find("0 finite"), std::string::npos) << nan_message;

  // A band near the top ring's highest returns (+15 deg reaches 1.7 m 6.35 m out, where only
  // the room's corners, 6.4 m away, lie): a few bearings remain.
  CloudToScanOptions high;
  high.band_min_m = 1.7;
  high.band_max_m = 1.8;
  const std::string sparse = rejection(roomCloud(), high);
  EXPECT_NE(sparse.find("[1.7, 1.8] m about the sensor's plane"), std::string::npos) << sparse;
  EXPECT_NE(sparse.find("bearings left (20 needed)"), std::string::npos) << sparse;
  EXPECT_NE(sparse.find("in the band"), std::string::npos) << sparse;
  EXPECT_EQ(sparse.find(": 0 bearings"), std::string::npos) << sparse;
}

TEST(CloudToScan, ScanFromPointsKeepsEveryVoxelAtItsOwnBearing)
{
  CloudToScanOptions options;  // 5 cm voxels
  options.scan_from = ScanFrom::kPoints;
  CloudToScanCounts counts;
  const Scan scan = cloudToScan(roomCloud(), true, options, &counts);
  // The band projected before the voxel grid: the rings seeing a wall share its voxels, so
  // the walls' 36 m make about 36 / 0.05 = 720 voxels (a 3D grid would keep each ring's).
  EXPECT_GT(counts.voxels, 650u);
  EXPECT_LT(counts.voxels, 800u);
  // Every voxel in range becomes a ray: the room's walls are all within 6.4 m.
  ASSERT_EQ(scan.ranges_m.size(), counts.voxels);
  EXPECT_EQ(counts.rays, counts.voxels);
  ASSERT_EQ(scan.ray_angles_rad.size(), scan.ranges_m.size());
  ASSERT_EQ(scan.ray_times_s.size(), scan.ranges_m.size());
  EXPECT_TRUE(std::is_sorted(scan.ray_angles_rad.begin(), scan.ray_angles_rad.end()));
  EXPECT_NO_THROW(validate(scan));
  // Each ray is its voxel's centroid, on the wall at its own bearing (no half-bin error).
  double worst = 0.0;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    worst = std::max(worst, std::abs(scan.ranges_m[i] - wallDistance(scan.ray_angles_rad[i])));
    // Column k (bearing -pi + 2 pi (k + 0.5) / 900) was taken at 0.1 ms k; a voxel's time is
    // the mean of its points', within the 5 cm (at most 0.6 deg, 1.5 columns) it spans.
    const double column = (scan.ray_angles_rad[i] + M_PI) / (2.0 * M_PI) * 900.0 - 0.5;
    EXPECT_NEAR(scan.ray_times_s[i], 1e-4 * column, 2e-4) << i;
  }
  // A centroid of points on a straight wall lies on it: only corners and float rounding.
  EXPECT_LT(worst, 0.01);
  // The bins of the same cloud lose half a bin at the corners: more error.
  options.scan_from = ScanFrom::kBins;
  options.angular_resolution_rad = 2.0 * M_PI / 900.0;
  EXPECT_GT(wallError(cloudToScan(roomCloud(), true, options)).first, worst);
}

TEST(CloudToScan, ScanFromPointsLevelsATiltedSensorAndDropsTheFloor)
{
  const double pitch = 2.0 * M_PI / 180.0;
  const Eigen::Matrix3d R_level_sensor =
      Eigen::AngleAxisd(pitch, Eigen::Vector3d::UnitY()).toRotationMatrix();
  CloudToScanOptions options;
  options.scan_from = ScanFrom::kPoints;
  options.voxel_size_m = 0.0;
  options.pitch_rad = pitch;
  const Scan scan = cloudToScan(roomCloud(R_level_sensor.transpose(), 15.0, 15.0), false, options);
  EXPECT_TRUE(scan.ray_times_s.empty());
  EXPECT_GT(scan.ranges_m.size(), 900u);
  double worst = 0.0;
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i) {
    worst = std::max(worst,
                     std::abs(scan.ranges_m[i] - wallDistance(scan.ray_angles_rad[i], 15.0, 15.0)));
  }
  EXPECT_LT(worst, 0.01);  // float rounding at 21 m; the floor would be metres off
}

TEST(CloudToScanOptions, ScanFromNames)
{
  EXPECT_EQ(scanFromName("bins"), ScanFrom::kBins);
  EXPECT_EQ(scanFromName("points"), ScanFrom::kPoints);
  EXPECT_STREQ(toString(ScanFrom::kPoints), "points");
  EXPECT_THROW(scanFromName("rays"), std::invalid_argument);
}

TEST(CloudToScanOptions, BadOptionsAreNamed)
{
  CloudToScanOptions options;
  options.band_min_m = 0.5;
  options.band_max_m = 0.1;
  EXPECT_THROW(validate(options), std::invalid_argument);
  options = CloudToScanOptions();
  options.voxel_size_m = -1.0;
  EXPECT_THROW(validate(options), std::invalid_argument);
  options = CloudToScanOptions();
  options.angular_resolution_rad = 0.0;
  EXPECT_THROW(validate(options), std::invalid_argument);
  options = CloudToScanOptions();
  options.pitch_rad = 2.0;
  EXPECT_THROW(validate(options), std::invalid_argument);
  options = CloudToScanOptions();
  options.point_times.limit_s = -1.0;
  EXPECT_THROW(validate(options), std::invalid_argument);
  EXPECT_NO_THROW(validate(CloudToScanOptions()));
}

}  // namespace
}  // namespace odometry_calibration
