// Scan -> points (invalid readings), local line fits, and the two nearest-point searches.
#include <array>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/nearest_point_search.h"
#include "odometry_calibration/scan/scan.h"
#include "odometry_calibration/scan/scan_lines.h"
#include "support/synthetic_scans.h"

namespace odometry_calibration {
namespace {

constexpr double kInf = std::numeric_limits<double>::infinity();

Scan fourRayScan(std::vector<double> ranges_m)
{
  Scan scan;
  scan.angle_min_rad = -M_PI / 4;
  scan.angle_increment_rad = M_PI / 6;
  scan.range_min_m = 0.1;
  scan.range_max_m = 10.0;
  scan.ranges_m = std::move(ranges_m);
  return scan;
}

TEST(ScanToPoints, KeepsValidReadingsWithTheirRayGeometry)
{
  const ScanPoints points = scanToPoints(fourRayScan({1.0, 2.0, 3.0, 4.0}));
  ASSERT_EQ(points.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    const double angle = -M_PI / 4 + i * M_PI / 6;
    EXPECT_NEAR(points.angles_rad[i], angle, 1e-15);
    EXPECT_NEAR(points.points_m[i].x(), (i + 1.0) * std::cos(angle), 1e-15);
    EXPECT_NEAR(points.points_m[i].y(), (i + 1.0) * std::sin(angle), 1e-15);
    EXPECT_NEAR(points.directions[i].norm(), 1.0, 1e-15);
    EXPECT_EQ(points.ray_indices[i], i);
  }
}

TEST(ScanToPoints, DropsNanInfZeroOutOfRangeAndMaskedReadings)
{
  Scan scan = fourRayScan({std::nan(""), kInf, 0.0, 0.05});
  scan.ranges_m.insert(scan.ranges_m.end(), {10.5, -kInf, 2.5, 3.5});
  scan.valid = {1, 1, 1, 1, 1, 1, 1, 0};
  const ScanPoints points = scanToPoints(scan);
  ASSERT_EQ(points.size(), 1u);  // only 2.5 m on ray 6 survives
  EXPECT_EQ(points.ray_indices[0], 6);
  EXPECT_DOUBLE_EQ(points.ranges_m[0], 2.5);
  // The count without conversion agrees, ray by ray.
  EXPECT_EQ(countUsableReadings(scan), 1u);
  for (std::size_t i = 0; i < scan.ranges_m.size(); ++i)
    EXPECT_EQ(isUsableReading(scan, i), i == 6) << i;
  scan.valid.clear();
  EXPECT_EQ(countUsableReadings(scan), scanToPoints(scan).size());
  EXPECT_EQ(countUsableReadings(scan), 2u);  // 2.5 m and 3.5 m
}

TEST(ScanToPoints, AllInvalidGivesNoPointsAndNoException)
{
  EXPECT_TRUE(scanToPoints(fourRayScan({0.0, kInf, std::nan(""), 0.0})).empty());
  EXPECT_TRUE(scanToPoints(fourRayScan({})).empty());
}

TEST(ScanToPoints, CompensatesTheMotionDuringTheSweep)
{
  // Ray 3 is measured 3 ms after the stamp; meanwhile the sensor turned by omega * 3 ms and
  // moved along the arc exp(tau xi). The point must come out where the sensor at the stamp sees
  // it: turned, then shifted by the chord of the arc.
  Scan scan = fourRayScan({1.0, 2.0, 3.0, 4.0});
  scan.time_increment_s = 0.001;
  SensorVelocity velocity;
  velocity.vx_mps = 2.0;
  velocity.vy_mps = -0.5;
  velocity.omega_radps = 4.0;
  const ScanPoints points = scanToPoints(scan, velocity);
  ASSERT_EQ(points.size(), 4u);
  const double tau_s = 0.003;
  const double theta = velocity.omega_radps * tau_s;
  const double a = std::sin(theta) / theta;
  const double b = (1.0 - std::cos(theta)) / theta;
  const Eigen::Vector2d t(a * velocity.vx_mps * tau_s - b * velocity.vy_mps * tau_s,
                          b * velocity.vx_mps * tau_s + a * velocity.vy_mps * tau_s);
  const double angle = -M_PI / 4 + 3 * M_PI / 6;
  const Eigen::Vector2d expected =
      4.0 * Eigen::Vector2d(std::cos(angle + theta), std::sin(angle + theta)) + t;
  EXPECT_NEAR((points.points_m[3] - expected).norm(), 0.0, 1e-12);
  EXPECT_NEAR(points.ranges_m[3], expected.norm(), 1e-12);
  EXPECT_NEAR(points.angles_rad[3], std::atan2(expected.y(), expected.x()), 1e-12);
  EXPECT_NEAR((points.directions[3] - expected.normalized()).norm(), 0.0, 1e-12);
  // Ray 0 is at the stamp: unchanged. Without a time increment nothing moves.
  EXPECT_NEAR(
      (points.points_m[0] - Eigen::Vector2d(std::cos(M_PI / 4), -std::sin(M_PI / 4))).norm(), 0.0,
      1e-15);
  scan.time_increment_s = 0.0;
  EXPECT_NEAR(scanToPoints(scan, velocity).points_m[3].y(), 4.0 * std::sin(angle), 1e-15);
  scan.time_increment_s = std::nan("");
  EXPECT_THROW(scanToPoints(scan), std::invalid_argument);
}

TEST(ScanToPoints, CompensatesATurnThatSpeedsUpDuringTheSweep)
{
  // Turning from 1 rad/s at the stamp at 30 rad/s^2 and driving at 2 m/s gaining 4 m/s^2: ray 3,
  // 3 ms after the stamp, is seen from the pose exp(tau v + tau^2 / 2 a). The same scan
  // compensated with the velocity at the stamp alone misplaces it by the turn's growth.
  Scan scan = fourRayScan({1.0, 2.0, 3.0, 4.0});
  scan.time_increment_s = 0.001;
  SensorVelocity velocity;
  velocity.vx_mps = 2.0;
  velocity.omega_radps = 1.0;
  velocity.ax_mps2 = 4.0;
  velocity.alpha_radps2 = 30.0;
  const ScanPoints points = scanToPoints(scan, velocity);
  ASSERT_EQ(points.size(), 4u);
  const double tau_s = 0.003;
  const double x = 2.0 * tau_s + 0.5 * 4.0 * tau_s * tau_s;
  const double theta = 1.0 * tau_s + 0.5 * 30.0 * tau_s * tau_s;
  const Eigen::Vector2d t(std::sin(theta) / theta * x, (1.0 - std::cos(theta)) / theta * x);
  const double angle = -M_PI / 4 + 3 * M_PI / 6;
  const Eigen::Vector2d expected =
      4.0 * Eigen::Vector2d(std::cos(angle + theta), std::sin(angle + theta)) + t;
  EXPECT_NEAR((points.points_m[3] - expected).norm(), 0.0, 1e-12);
  EXPECT_NEAR(points.angles_rad[3], std::atan2(expected.y(), expected.x()), 1e-12);
  // Without the rates of change: 0.135 mrad less turn, 0.54 mm off at 4 m.
  SensorVelocity constant = velocity;
  constant.ax_mps2 = 0.0;
  constant.alpha_radps2 = 0.0;
  EXPECT_GT((scanToPoints(scan, constant).points_m[3] - expected).norm(), 5e-4);
  // A sensor standing still but for its acceleration is not at rest.
  SensorVelocity accelerating;
  accelerating.alpha_radps2 = 30.0;
  EXPECT_FALSE(accelerating.isZero());
  EXPECT_NEAR(scanToPoints(scan, accelerating).angles_rad[3], angle + 0.5 * 30.0 * tau_s * tau_s,
              1e-12);
}

TEST(ScanToPoints, CompensatedPointsStayOrderedByBearing)
{
  // Turning clockwise faster than the rays advance reverses their bearings: the points must
  // come out sorted by bearing again, each with its own ray index and geometry.
  Scan scan = fourRayScan({1.0, 2.0, 3.0, 4.0});
  scan.time_increment_s = 1.0;
  SensorVelocity velocity;
  velocity.omega_radps = -1.0;  // -1 rad per ray against +pi/6 between rays
  const ScanPoints points = scanToPoints(scan, velocity);
  ASSERT_EQ(points.size(), 4u);
  for (int k = 0; k < 4; ++k) {
    const int ray = 3 - k;
    EXPECT_EQ(points.ray_indices[k], ray);
    EXPECT_NEAR(points.ranges_m[k], ray + 1.0, 1e-12);
    const double bearing = -M_PI / 4 + ray * (M_PI / 6 - 1.0);
    EXPECT_NEAR(points.angles_rad[k], bearing, 1e-12);
    EXPECT_NEAR(points.points_m[k].x(), (ray + 1.0) * std::cos(bearing), 1e-12);
    if (k > 0) {
      EXPECT_LT(points.angles_rad[k - 1], points.angles_rad[k]);
    }
  }
}

TEST(ScanToPoints, NegativeIncrementStillGivesIncreasingAngles)
{
  Scan scan = fourRayScan({1.0, 2.0, 3.0, 4.0});
  scan.angle_min_rad = M_PI / 4;
  scan.angle_increment_rad = -M_PI / 6;
  const ScanPoints points = scanToPoints(scan);
  ASSERT_EQ(points.size(), 4u);
  EXPECT_EQ(points.ray_indices.front(), 3);
  for (std::size_t i = 1; i < points.size(); ++i) {
    EXPECT_GT(points.angles_rad[i], points.angles_rad[i - 1]);
  }
}

TEST(ScanToPoints, RejectsUnusableGeometryNamingTheField)
{
  Scan scan = fourRayScan({1.0});
  scan.angle_increment_rad = 0.0;
  EXPECT_THROW(
      {
        try {
          scanToPoints(scan);
        } catch (const std::invalid_argument& error) {
          EXPECT_NE(std::string(error.what()).find("angle_increment_rad"), std::string::npos);
          throw;
        }
      },
      std::invalid_argument);
  scan = fourRayScan({1.0});
  scan.range_max_m = 0.05;
  EXPECT_THROW(scanToPoints(scan), std::invalid_argument);
  scan = fourRayScan({1.0, 2.0});
  scan.valid = {1};
  EXPECT_THROW(scanToPoints(scan), std::invalid_argument);
  // Found by fuzz_messages: a LaserScan with angle_min 1e30 made the matcher's bearing search
  // wrap the angle 2 pi at a time, forever. Rays beyond two turns are refused.
  scan = fourRayScan({1.0, 2.0});
  scan.angle_min_rad = 1e30;
  EXPECT_THROW(scanToPoints(scan), std::invalid_argument);
  scan = fourRayScan({1.0, 2.0});
  scan.angle_increment_rad = 1e10;
  EXPECT_THROW(scanToPoints(scan), std::invalid_argument);
  scan = fourRayScan({1.0, 2.0});
  scan.angle_min_rad = -2.0 * M_PI;  // a full turn from -2 pi is fine
  EXPECT_NO_THROW(scanToPoints(scan));
}

TEST(ScanToPoints, PerRayAnglesReplaceTheEqualSpacing)
{
  // Unequally spaced rays (a 3D lidar's points ordered by bearing), two at the same bearing.
  Scan scan = fourRayScan({1.0, 2.0, 3.0, 4.0});
  scan.ray_angles_rad = {-1.0, 0.3, 0.3, 2.5};
  scan.ray_times_s = {0.0, 0.01, 0.02, 0.03};
  const ScanPoints points = scanToPoints(scan);
  ASSERT_EQ(points.size(), 4u);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(points.angles_rad[i], scan.ray_angles_rad[i]);
    EXPECT_NEAR(points.points_m[i].x(), (i + 1.0) * std::cos(scan.ray_angles_rad[i]), 1e-15);
    EXPECT_NEAR(points.points_m[i].y(), (i + 1.0) * std::sin(scan.ray_angles_rad[i]), 1e-15);
  }
  // Compensated with a turn: each point turned by omega * its own ray time.
  const ScanPoints turned = scanToPoints(scan, SensorVelocity{0.0, 0.0, 1.0});
  EXPECT_NEAR(turned.angles_rad[3], 2.5 + 0.03, 1e-12);
  EXPECT_NEAR(turned.angles_rad[0], -1.0, 1e-12);

  auto refused = [&](std::vector<double> angles, double increment = M_PI / 6) {
    Scan bad = fourRayScan({1.0, 2.0, 3.0, 4.0});
    bad.ray_angles_rad = std::move(angles);
    bad.angle_increment_rad = increment;
    try {
      scanToPoints(bad);
    } catch (const std::invalid_argument& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(refused({0.0, 1.0, 2.0}).find("ray_angles_rad has 3 entries for 4 rays"),
            std::string::npos);
  EXPECT_NE(refused({0.0, 1.0, 0.5, 2.0}).find("non-decreasing (ray 2"), std::string::npos);
  EXPECT_NE(refused({0.0, std::nan(""), 1.0, 2.0}).find("ray_angles_rad must be finite"),
            std::string::npos);
  EXPECT_NE(refused({0.0, 1.0, 2.0, 20.0}).find("[-4 pi, 4 pi]"), std::string::npos);
  EXPECT_NE(refused({0.0, 1.0, 2.0, 3.0}, -0.1).find("positive"), std::string::npos);
}

/// Noise-free scan of a world from the origin.
ScanPoints cleanScan(const synthetic::World& world, const Pose2& pose = Pose2(),
                     int ray_count = 682)
{
  synthetic::LidarModel lidar;
  lidar.range_sigma_m = 0.0;
  lidar.ray_count = ray_count;
  std::mt19937 rng(1);
  return scanToPoints(synthetic::simulateScan(world, pose, lidar, rng));
}

TEST(ScanLines, StraightWallGivesExactNormalsTowardsTheSensor)
{
  synthetic::World world;
  world.addSegment(2.0, -5.0, 2.0, 5.0);  // wall x = 2 in front of the sensor
  const ScanPoints points = cleanScan(world);
  const ScanLines lines = fitScanLines(points, LineFitOptions());
  ASSERT_GT(lines.valid_count, 100u);
  for (std::size_t i = 0; i < points.size(); ++i) {
    if (lines.valid[i] == 0) {
      continue;
    }
    EXPECT_NEAR(lines.normals[i].x(), -1.0, 1e-9);
    EXPECT_NEAR(lines.normals[i].y(), 0.0, 1e-6);
    EXPECT_NEAR(lines.centroids_m[i].x(), 2.0, 1e-9);
    EXPECT_LE(lines.along_min_m[i], 0.0);
    EXPECT_GE(lines.along_max_m[i], 0.0);
  }
}

TEST(ScanLines, PointsNearACornerTakeTheSideOfTheirOwnWall)
{
  synthetic::World world;  // corner at (2, 1): walls x = 2 (below) and y = 1 (left)
  world.addSegment(2.0, -5.0, 2.0, 1.0);
  world.addSegment(2.0, 1.0, -5.0, 1.0);
  const ScanPoints points = cleanScan(world);
  const ScanLines lines = fitScanLines(points, LineFitOptions());
  int checked = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const Eigen::Vector2d& p = points.points_m[i];
    const double from_corner_m = (p - Eigen::Vector2d(2.0, 1.0)).norm();
    if (lines.valid[i] == 0 || from_corner_m > 0.3 || from_corner_m < 0.01) {
      continue;
    }
    // On the wall x = 2 the normal is -x, on the wall y = 1 it is -y: never in between.
    const bool on_x_wall = std::abs(p.x() - 2.0) < 1e-9;
    const Eigen::Vector2d expected = on_x_wall ? Eigen::Vector2d(-1, 0) : Eigen::Vector2d(0, -1);
    EXPECT_NEAR((lines.normals[i] - expected).norm(), 0.0, 1e-6) << "point " << p.transpose();
    ++checked;
  }
  EXPECT_GT(checked, 20);
}

TEST(ScanLines, SmallObjectsFallBackToTwoPointSegments)
{
  synthetic::World world;
  world.addCircle(1.5, 0.0, 0.012);  // a thin table leg: two or three points
  const ScanPoints points = cleanScan(world);
  ASSERT_GE(points.size(), 2u);
  const ScanLines lines = fitScanLines(points, LineFitOptions());
  EXPECT_EQ(lines.valid_count, points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_EQ(lines.fitted[i], 0);
  }
  LineFitOptions no_fallback;
  no_fallback.segment_fallback = false;
  EXPECT_EQ(fitScanLines(points, no_fallback).valid_count, 0u);
}

/// A noise-free scan with `ray_count` rays over 180 deg (ray_count 181: 1 deg rays) from
/// `pose`.
ScanPoints cleanScan180(const synthetic::World& world, int ray_count, const Pose2& pose = Pose2())
{
  synthetic::LidarModel lidar;
  lidar.range_sigma_m = 0.0;
  lidar.ray_count = ray_count;
  lidar.field_of_view_rad = 180.0 * synthetic::kDegToRad;
  lidar.range_max_m = 40.0;
  std::mt19937 rng(1);
  return scanToPoints(synthetic::simulateScan(world, pose, lidar, rng));
}

/// A noise-free scan (`rays` over 180 deg) of two walls facing the sensor, x = near_x_m for
/// y in [-half_width_m, 0] and x = far_x_m for y in [0, half_width_m]. Expects no point to get
/// a line with `breaking` (every gap a surface break) and, with the defaults, every point the
/// line of its own wall (the step between the walls still a break).
ScanPoints expectFarWallLines(double near_x_m, double far_x_m, double half_width_m, int rays,
                              const LineFitOptions& breaking)
{
  synthetic::World world;
  world.addSegment(near_x_m, -half_width_m, near_x_m, 0.0);
  world.addSegment(far_x_m, 0.0, far_x_m, half_width_m);
  const ScanPoints points = cleanScan180(world, rays);
  EXPECT_GT(points.size(), 30u);
  EXPECT_EQ(fitScanLines(points, breaking).valid_count, 0u);  // every point its own surface
  const ScanLines lines = fitScanLines(points, LineFitOptions());
  EXPECT_EQ(lines.valid_count, points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    const double wall_x_m = points.points_m[i].y() > 0.0 ? far_x_m : near_x_m;
    EXPECT_NEAR(lines.normals[i].x(), -1.0, 1e-9) << "point " << i;
    EXPECT_NEAR(lines.centroids_m[i].x(), wall_x_m, 1e-9) << "point " << i;
  }
  return points;
}

TEST(ScanLines, FarWallsOfSparseScannersKeepTheirLinesButDepthStepsStillBreak)
{
  // 1 deg rays: on the wall x = 15 neighbouring points lie 0.26-0.37 m apart, beyond max_gap_m
  // (0.2 m) but within the arc of one ray at max_gap_range_m (28 m: 0.49 m). Behind it (y > 0)
  // the wall steps back to x = 16: a 1 m step, a new surface.
  LineFitOptions before;
  before.max_gap_range_m = 0.0;
  const ScanPoints points = expectFarWallLines(15.0, 16.0, 6.0, 181, before);
  // Twice the ray spacing: the gaps exceed the threshold again.
  LineFitOptions shorter;
  shorter.max_gap_range_m = 10.0;
  shorter.max_gap_incidence_rad = 0.0;
  EXPECT_EQ(fitScanLines(points, shorter).valid_count, 0u);
}

TEST(ScanLines, FarSurfacesKeepTheirLinesWithinTheIncidenceGap)
{
  // 0.5 deg rays, a wall at x = 30 m: neighbouring points 0.26-0.29 m apart, beyond the fixed
  // arc at max_gap_range_m (28 m: 0.24 m) but within r * spacing / cos(70 deg) (0.77 m at 30 m).
  // A step back to x = 32 m (2 m) still breaks.
  LineFitOptions fixed_arc;
  fixed_arc.max_gap_incidence_rad = 0.0;
  expectFarWallLines(30.0, 32.0, 8.0, 361, fixed_arc);
  LineFitOptions invalid;
  invalid.max_gap_incidence_rad = 0.5 * M_PI;
  EXPECT_THROW(validate(invalid), std::invalid_argument);
}

TEST(ScanLines, DenseScansBreakSurfacesAtMaxGapAlone)
{
  // 0.25 and 0.375 deg rays: max_gap_range_m (28 m) gives 0.12 and 0.18 m, below max_gap_m: the
  // lines are those of max_gap_m alone (the office room: depth steps of every size).
  for (const int rays : {721, 481}) {
    const ScanPoints points = cleanScan180(synthetic::officeRoom(), rays, Pose2(3.0, 3.0, 0.4));
    ASSERT_GT(points.size(), static_cast<std::size_t>(rays) * 9 / 10);
    LineFitOptions alone;
    alone.max_gap_range_m = 0.0;
    const ScanLines expected = fitScanLines(points, alone);
    const ScanLines lines = fitScanLines(points, LineFitOptions());
    ASSERT_GT(expected.valid_count, points.size() / 2);
    EXPECT_EQ(lines.valid_count, expected.valid_count) << rays << " rays";
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_EQ(lines.valid[i], expected.valid[i]) << rays << " rays, point " << i;
      EXPECT_EQ(lines.normals[i], expected.normals[i]) << rays << " rays, point " << i;
      EXPECT_EQ(lines.first[i], expected.first[i]) << rays << " rays, point " << i;
    }
  }
}

TEST(ScanLines, OptionsAreValidated)
{
  LineFitOptions options;
  options.min_points = 2;
  EXPECT_THROW(validate(options), std::invalid_argument);
  options = LineFitOptions();
  options.radius_m = -1.0;
  try {
    validate(options);
    FAIL() << "negative radius accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("line_fit.radius_m"), std::string::npos);
  }
}

/// The office room seen from (3, 3, 0.4) with the parameter's field of view (240 deg, 270 deg,
/// or more: the walks wrap around), its lines and both searches over it.
class NearestPointSearchFieldOfView : public ::testing::TestWithParam<double>
{
protected:
  /// Scans with noise from `seed`; the tests draw their queries from the same generator.
  void scan(unsigned seed)
  {
    synthetic::LidarModel lidar;
    lidar.field_of_view_rad = GetParam();
    rng_.seed(seed);
    points_ = scanToPoints(
        synthetic::simulateScan(synthetic::officeRoom(), Pose2(3, 3, 0.4), lidar, rng_));
    lines_ = fitScanLines(points_, LineFitOptions());
    angular_ = makeAngularSearch(points_, lines_);
    kdtree_ = makeKdTreeSearch(points_, lines_);
  }

  std::mt19937 rng_;
  ScanPoints points_;
  ScanLines lines_;
  std::unique_ptr<NearestPointSearch> angular_, kdtree_;
  const double min_cosine_ = std::cos(0.6);
};

TEST_P(NearestPointSearchFieldOfView, AngularAndKdTreeAgreeWithBruteForce)
{
  scan(3);
  std::uniform_real_distribution<double> coordinate(-6.0, 6.0);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::uniform_int_distribution<std::size_t> hint_index(0, points_.size() - 1);
  for (int query = 0; query < 2000; ++query) {
    const Eigen::Vector2d q(coordinate(rng_), coordinate(rng_));
    const double a = angle(rng_);
    const Eigen::Vector2d normal =
        query % 2 == 0 ? Eigen::Vector2d(std::cos(a), std::sin(a)) : Eigen::Vector2d::Zero();
    const double max_distance_m = query % 3 == 0 ? 0.3 : 2.0;
    int expected = -1;
    double best = max_distance_m;
    for (std::size_t i = 0; i < points_.size(); ++i) {
      const bool compatible =
          lines_.fitted[i] == 0 || normal.isZero() || lines_.normals[i].dot(normal) >= min_cosine_;
      const double distance = (points_.points_m[i] - q).norm();
      if (lines_.valid[i] != 0 && compatible && distance <= best) {
        best = distance;
        expected = static_cast<int>(i);
      }
    }
    EXPECT_EQ(angular_->nearest(q, normal, min_cosine_, max_distance_m, nullptr), expected)
        << "query " << q.transpose();
    EXPECT_EQ(kdtree_->nearest(q, normal, min_cosine_, max_distance_m, nullptr), expected)
        << "query " << q.transpose();
    // A hint (any reference point: near, far, unusable or out of range) never changes the
    // answer.
    for (const int hint : {expected, static_cast<int>(hint_index(rng_)), -1, 100000}) {
      EXPECT_EQ(angular_->nearest(q, normal, min_cosine_, max_distance_m, nullptr, hint), expected)
          << "query " << q.transpose() << ", hint " << hint;
    }
  }
}

/// The usable reference point nearest to q within max_distance_m with a compatible normal (the
/// rule of NearestPointSearch::find), by brute force; -1 when none.
int bruteForceNearest(const ScanPoints& points, const ScanLines& lines, const Eigen::Vector2d& q,
                      const Eigen::Vector2d& normal, double min_cosine, double max_distance_m)
{
  int expected = -1;
  double best = max_distance_m;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool compatible =
        lines.fitted[i] == 0 || lines.normals[i].dot(normal) >= min_cosine * normal.norm();
    const double distance = (points.points_m[i] - q).norm();
    if (lines.valid[i] != 0 && compatible && distance < best) {
      best = distance;
      expected = static_cast<int>(i);
    }
  }
  return expected;
}

TEST_P(NearestPointSearchFieldOfView, IsolationBoundsEveryOtherPoint)
{
  scan(5);
  std::uniform_int_distribution<std::size_t> point_index(0, points_.size() - 1);
  std::normal_distribution<double> offset(0.0, 0.05);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  int isolated_beyond_answer = 0;
  for (int query = 0; query < 1500; ++query) {
    // Near the surfaces, where ICP asks.
    const Eigen::Vector2d q =
        points_.points_m[point_index(rng_)] + Eigen::Vector2d(offset(rng_), offset(rng_));
    const double a = angle(rng_);
    const Eigen::Vector2d normal =
        query % 2 == 0 ? Eigen::Vector2d(std::cos(a), std::sin(a)) : Eigen::Vector2d::Zero();
    const double max_distance_m = query % 3 == 0 ? 0.03 : 0.5;
    const double margin_m = std::array<double, 3>{0.0, 0.01, 0.05}[query % 3];
    const int expected = bruteForceNearest(points_, lines_, q, normal, min_cosine_, max_distance_m);
    const double reach_m =
        (expected >= 0 ? (points_.points_m[expected] - q).norm() : max_distance_m) + margin_m;
    double others_m = std::numeric_limits<double>::infinity();  // nearest point but the answer
    for (std::size_t i = 0; i < points_.size(); ++i) {
      if (lines_.valid[i] != 0 && static_cast<int>(i) != expected)
        others_m = std::min(others_m, (points_.points_m[i] - q).norm());
    }
    for (const auto* search : {angular_.get(), kdtree_.get()}) {
      const NearestPoint answer =
          search->find(q, normal, min_cosine_, max_distance_m, -1, margin_m);
      ASSERT_EQ(answer.index, expected) << "query " << q.transpose() << ", margin " << margin_m;
      if (expected >= 0) {
        EXPECT_NEAR(answer.distance_m, (points_.points_m[expected] - q).norm(), 1e-12);
      }
      // A bound: no other point nearer than the isolation ...
      EXPECT_LE(answer.isolation_m, others_m + 1e-12) << "query " << q.transpose();
      // ... and as large as the margin makes it: up to the reach, unless another point is nearer.
      EXPECT_GE(answer.isolation_m, std::min(others_m, reach_m) - 1e-12)
          << "query " << q.transpose() << ", margin " << margin_m;
    }
    isolated_beyond_answer +=
        expected >= 0 &&
        angular_->find(q, normal, min_cosine_, max_distance_m, expected, margin_m).isolation_m >
            reach_m - margin_m + 1e-3;
  }
  // The margin buys certificates: most answers are isolated by more than a millimetre.
  EXPECT_GT(isolated_beyond_answer, 500);
}

TEST_P(NearestPointSearchFieldOfView, TrackedQueriesAnswerAsSearchesDoWithFewerSearches)
{
  scan(7);
  std::uniform_int_distribution<std::size_t> point_index(0, points_.size() - 1);
  std::normal_distribution<double> unit(0.0, 1.0);
  for (const auto* search : {angular_.get(), kdtree_.get()}) {
    int calls = 0;
    int searches = 0;
    for (int track_number = 0; track_number < 300; ++track_number) {
      // A new point over ICP iterations: steps shrinking from 5 cm to nothing, its normal
      // turning with the pose (sometimes across the compatibility limit of 0.6 rad).
      Eigen::Vector2d q =
          points_.points_m[point_index(rng_)] + 0.05 * Eigen::Vector2d(unit(rng_), unit(rng_));
      double normal_angle = std::atan2(q.y(), q.x()) + M_PI + 0.6 * unit(rng_);
      const double max_distance_m = track_number % 4 == 0 ? 0.02 : 0.5;
      NearestTrack track;
      for (const double step_m : {0.05, 0.02, 0.005, 0.001, 2e-4, 3e-5, 0.0, 0.0}) {
        q += step_m * Eigen::Vector2d(unit(rng_), unit(rng_));
        normal_angle += 5.0 * step_m * unit(rng_);
        const Eigen::Vector2d normal(std::cos(normal_angle), std::sin(normal_angle));
        const Eigen::Vector2d searched_at = track.query_m;
        const int answer =
            search->nearestTracked(q, normal, min_cosine_, max_distance_m, 4.0 * step_m, track);
        ++calls;
        searches += track.query_m != searched_at || calls == 1 ? 1 : 0;
        ASSERT_EQ(answer,
                  bruteForceNearest(points_, lines_, q, normal, min_cosine_, max_distance_m))
            << "track " << track_number << ", step " << step_m << " m";
      }
    }
    // The margins make most of the later, smaller steps free.
    EXPECT_LT(searches, 0.5 * calls);
    EXPECT_GT(searches, 300);  // every track's first call searches
  }
}

// 270 degrees and a hair (5e-6 rad, as a float32 angle increment puts it): searched without
// wrap-around; 1e-4 rad beyond 270 degrees: with it.
INSTANTIATE_TEST_SUITE_P(FieldsOfView, NearestPointSearchFieldOfView,
                         ::testing::Values(240.0 * synthetic::kDegToRad, 1.5 * M_PI - 1e-3,
                                           1.5 * M_PI - 0.2, 1.5 * M_PI + 5e-6, 1.5 * M_PI + 1e-4,
                                           2.0 * M_PI));

}  // namespace
}  // namespace odometry_calibration
