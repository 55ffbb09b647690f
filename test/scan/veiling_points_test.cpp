#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/veiling_points.h"

namespace odometry_calibration {
namespace {

constexpr double kIncrement = 0.00613;  // rad, a URG's 0.35 degrees

/// 41 rays over a face-on wall at x = 5 m, with rays 15-24 hitting a box face at x = 2 m, and
/// ray 25 a mixed pixel halfway between the two surfaces (3.5 m along its ray).
Scan stepScan()
{
  Scan scan;
  scan.angle_min_rad = -20 * kIncrement;
  scan.angle_increment_rad = kIncrement;
  scan.range_min_m = 0.05;
  scan.range_max_m = 10.0;
  for (int i = 0; i < 41; ++i) {
    const double angle = scan.angle_min_rad + i * kIncrement;
    const double x = i >= 15 && i <= 24 ? 2.0 : (i == 25 ? 3.5 : 5.0);
    scan.ranges_m.push_back(x / std::cos(angle));
  }
  return scan;
}

TEST(VeilingPoints, TheMixedPixelAndTheFarEdgesOfTheStepAreMarkedAndNothingElse)
{
  const ScanPoints points = scanToPoints(stepScan());
  const std::vector<std::uint8_t> veiling = findVeilingPoints(points, 10.0 * M_PI / 180.0, 2);
  ASSERT_EQ(veiling.size(), 41u);
  for (int i = 0; i < 41; ++i) {
    // The mixed pixel (25), the far wall's first points beyond the box (14 and 26).
    const bool expected = i == 14 || i == 25 || i == 26;
    EXPECT_EQ(veiling[i] != 0, expected) << "ray " << i;
  }
  EXPECT_EQ(findVeilingPoints(points, 0.0, 2), std::vector<std::uint8_t>(41, 0));
}

TEST(VeilingPoints, RaysMoreThanTheGapApartAreNotNeighbours)
{
  Scan scan = stepScan();
  scan.ranges_m[14] = scan.ranges_m[13] = std::nan("");  // drop the two rays before the box
  const ScanPoints points = scanToPoints(scan);
  // Ray 12 (far wall) is 3 rays from ray 15 (box): not neighbours with a gap of 2.
  const std::vector<std::uint8_t> veiling = findVeilingPoints(points, 10.0 * M_PI / 180.0, 2);
  EXPECT_EQ(veiling[12], 0);
  EXPECT_EQ(findVeilingPoints(points, 10.0 * M_PI / 180.0, 3)[12], 1);
}

TEST(VeilingPoints, RemovePointsKeepsTheOthersInOrder)
{
  const ScanPoints points = scanToPoints(stepScan());
  std::vector<std::uint8_t> remove(points.size(), 0);
  remove[3] = remove[25] = 1;
  const ScanPoints kept = removePoints(points, remove);
  ASSERT_EQ(kept.size(), 39u);
  EXPECT_EQ(kept.directions.size(), 39u);
  EXPECT_EQ(kept.angles_rad.size(), 39u);
  EXPECT_EQ(kept.ranges_m.size(), 39u);
  EXPECT_EQ(kept.ray_indices[3], 4);
  EXPECT_EQ(kept.ray_indices[24], 26);
  EXPECT_DOUBLE_EQ(kept.ranges_m[24], points.ranges_m[26]);
  EXPECT_THROW(removePoints(points, std::vector<std::uint8_t>(3, 0)), std::invalid_argument);
}

TEST(VeilingPoints, PrepareScanDropsThemWhenAskedAndRejectsBadOptions)
{
  LineFitOptions options;
  EXPECT_EQ(prepareScan(stepScan(), options).points.size(), 41u);  // off by default
  options.veiling_min_angle_rad = 10.0 * M_PI / 180.0;
  EXPECT_EQ(prepareScan(stepScan(), options).points.size(), 38u);
  EXPECT_THROW(findVeilingPoints(scanToPoints(stepScan()), -0.1, 2), std::invalid_argument);
  EXPECT_THROW(findVeilingPoints(scanToPoints(stepScan()), 0.1, 0), std::invalid_argument);
  options.veiling_min_angle_rad = 2.0;
  EXPECT_THROW(prepareScan(stepScan(), options), std::invalid_argument);
  options.veiling_min_angle_rad = 0.0;
  options.veiling_max_ray_gap = 0;
  EXPECT_THROW(prepareScan(stepScan(), options), std::invalid_argument);
}

TEST(SegmentFallback, LongSparseSurfacesGetNoSegmentWhenLimitedSmallOnesKeepTheirs)
{
  // A wall at 20 m, rays 12 cm apart (sparser than the 0.12 m radius allows a fit), and a
  // three-ray post at 2 m in front of it.
  Scan scan;
  scan.angle_min_rad = -20 * kIncrement;
  scan.angle_increment_rad = kIncrement;
  scan.range_min_m = 0.05;
  scan.range_max_m = 30.0;
  for (int i = 0; i < 41; ++i) {
    const double x = i >= 19 && i <= 21 ? 2.0 : 20.0;
    scan.ranges_m.push_back(x / std::cos(scan.angle_min_rad + i * kIncrement));
  }
  LineFitOptions options;
  const PreparedScan any = prepareScan(scan, options);
  options.segment_fallback_max_surface_points = 4;
  const PreparedScan limited = prepareScan(scan, options);
  for (int i = 0; i < 41; ++i) {
    const bool post = i >= 19 && i <= 21;
    EXPECT_EQ(any.lines.valid[i], 1) << "ray " << i;
    EXPECT_EQ(limited.lines.valid[i], post ? 1 : 0) << "ray " << i;
  }
  options.segment_fallback_max_surface_points = -1;
  EXPECT_THROW(prepareScan(scan, options), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
