// The simulated laser's sensor effects (sim/laser_model.h): each one is tested for what it must
// do to the readings, so that a model that ignored its option fails.
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/sim/laser_model.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace sim {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// A laser with one ray per degree over `fov_deg`, noise-free unless a test adds some.
LaserOptions degreeLaser(int fov_deg)
{
  LaserOptions laser;
  laser.rays = fov_deg + 1;
  laser.fov_rad = fov_deg * M_PI / 180.0;
  laser.range_noise_m = 0.0;
  laser.max_range_m = 20.0;
  return laser;
}

/// A standing laser at `pose`.
std::function<Pose2(double)> standing(const Pose2& pose)
{
  return [pose](double) { return pose; };
}

World wallAtX(double x)
{
  World world;
  world.addSegment({{x, -100.0}, {x, 100.0}});
  return world;
}

TEST(LaserModel, WithoutSweepAllRaysAreTakenAtTheStamp)
{
  LaserModel model(degreeLaser(240), 1);
  EXPECT_EQ(model.timeIncrement(), 0.0);
  int asked = 0;
  const ScanSample scan = model.measure(wallAtX(5.0), 2.0, [&](double tau) {
    EXPECT_EQ(tau, 0.0);
    ++asked;
    return Pose2();
  });
  EXPECT_EQ(asked, 1);
  EXPECT_EQ(scan.time_increment_s, 0.0);
  EXPECT_NEAR(scan.scan_time_s, 0.1, 1e-12);
  EXPECT_NEAR(scan.ranges[120], 5.0, 1e-6);
}

TEST(LaserModel, SweepTakesEachRayFromThePoseAtItsTime)
{
  // Driving at 1 m/s towards a wall 5 m ahead: ray i is taken i / 3600 s after the stamp (1 deg
  // of a turn per scan period of 0.1 s), so the ray at +60 deg, taken 1/30 s after the one at
  // -60 deg, is shorter by (1/30 m) / cos(60 deg).
  LaserOptions laser = degreeLaser(240);
  laser.sweep = true;
  LaserModel model(laser, 1);
  EXPECT_NEAR(model.timeIncrement(), 1.0 / 3600.0, 1e-12);
  EXPECT_NEAR(model.sweepDuration(), 240.0 / 3600.0, 1e-12);
  const ScanSample scan =
      model.measure(wallAtX(5.0), 0.0, [](double tau) { return Pose2(tau, 0.0, 0.0); });
  EXPECT_NEAR(scan.time_increment_s, 1.0 / 3600.0, 1e-12);
  for (const int i : {60, 120, 180}) {
    const double tau = i / 3600.0;
    const double angle = (i - 120) * M_PI / 180.0;
    EXPECT_NEAR(scan.ranges[static_cast<std::size_t>(i)], (5.0 - tau) / std::cos(angle), 1e-5)
        << "ray " << i;
  }
  EXPECT_NEAR(scan.ranges[60] - scan.ranges[180], (120.0 / 3600.0) / 0.5, 1e-5);
}

TEST(LaserModel, SimulatedSweepStampsTheFirstRayAndFollowsTheTruth)
{
  // Through the simulator: a scan ends at its scheduled instant, so its stamp is one sweep
  // (180 deg at one turn per 0.1 s: 0.05 s) earlier; the truth (at the encoder instants, every
  // 1 ms here) places ray 0, the middle ray and the last ray.
  Scenario s;
  s.duration_s = 3.0;
  s.robot.type = "diff_drive";
  s.laser = degreeLaser(180);
  s.laser.sweep = true;
  s.laser.rate_hz = 10.0;
  s.encoders.rate_hz = 1000.0;
  s.motion.type = "scripted";
  ScriptedMotion drive;
  drive.duration_s = 3.0;
  drive.twist.vx_mps = 0.5;
  drive.twist.omega_radps = 0.8;
  s.motion.script = {drive};
  struct Recorder : SimulationSink
  {
    std::vector<ScanSample> scans;
    std::vector<TruthSample> truth;
    void onJointState(const JointStateSample&) override {}
    void onScan(const ScanSample& scan) override { scans.push_back(scan); }
    void onTruth(const TruthSample& truth_sample) override { truth.push_back(truth_sample); }
  } recorder;
  const World world =
      parseWorldYaml("polygons:\n  - [[-6, -5], [7, -5], [7, 5], [-6, 5]]\n", "room");
  const auto robot = makeRobot(s.robot);
  simulate(s, world, *robot, recorder);
  ASSERT_EQ(recorder.scans.size(), 30u);  // the one at t = 0 would start before the run
  const ScanSample& scan = recorder.scans[20];
  EXPECT_NEAR(scan.stamp_s, 2.05, 1e-9);
  EXPECT_NEAR(scan.time_increment_s, 1.0 / 3600.0, 1e-12);
  std::vector<double> unswept;
  for (const int i : {0, 90, 180}) {
    const double t = 2.05 + i / 3600.0;
    const std::size_t k = static_cast<std::size_t>(std::llround(t * 1000.0));
    ASSERT_NEAR(recorder.truth[k].stamp_s, t, 1e-9);
    const Pose2 at_ray = recorder.truth[k].T_world_base * s.laser.T_base_laser;
    const double angle = (i - 90) * M_PI / 180.0;
    EXPECT_NEAR(scan.ranges[static_cast<std::size_t>(i)],
                world.castRay({at_ray.x(), at_ray.y()}, at_ray.theta() + angle, 20.0), 2e-6)
        << "ray " << i;
    // Seen from the pose at the stamp instead, the later rays would read differently.
    const Pose2 at_stamp = recorder.truth[2050].T_world_base * s.laser.T_base_laser;
    unswept.push_back(world.castRay({at_stamp.x(), at_stamp.y()}, at_stamp.theta() + angle, 20.0));
  }
  EXPECT_GT(std::abs(unswept[2] - scan.ranges[180]), 0.01);
}

TEST(LaserModel, ReturnsAreQuantisedToTheResolution)
{
  LaserOptions laser = degreeLaser(240);
  laser.range_noise_m = 0.01;
  laser.range_resolution_m = 0.001;
  LaserModel model(laser, 3);
  const ScanSample scan = model.measure(wallAtX(4.0), 0.0, standing(Pose2(0.0, 0.3, 0.1)));
  int finite = 0;
  for (const float range : scan.ranges) {
    if (!std::isfinite(range))
      continue;
    ++finite;
    const double millimetres = 1000.0 * static_cast<double>(range);
    // A float near 20 m holds millimetres to within 1e-3 mm; unquantised ranges almost never do.
    EXPECT_NEAR(millimetres, std::round(millimetres), 1e-3) << range;
  }
  EXPECT_GT(finite, 100);
}

TEST(LaserModel, ARangeRippleFixedToTheRays)
{
  LaserOptions laser = degreeLaser(240);
  laser.range_ripple_m = 0.006;
  laser.range_ripple_period_rays = 40.0;
  LaserModel rippled(laser, 3);
  laser.range_ripple_m = 0.0;
  LaserModel plain(laser, 3);
  // The same error on the same ray whatever the pose (it moves with the sensor).
  for (const Pose2& pose : {Pose2(0.0, 0.3, 0.1), Pose2(0.5, -0.2, -0.05)}) {
    const ScanSample with = rippled.measure(wallAtX(4.0), 0.0, standing(pose));
    const ScanSample without = plain.measure(wallAtX(4.0), 0.0, standing(pose));
    int finite = 0;
    for (std::size_t i = 0; i < with.ranges.size(); ++i) {
      if (!std::isfinite(without.ranges[i]))
        continue;
      ++finite;
      EXPECT_NEAR(with.ranges[i] - without.ranges[i], 0.006 * std::sin(2.0 * M_PI * i / 40.0), 1e-5)
          << "ray " << i;
    }
    EXPECT_GT(finite, 100);
  }
}

TEST(LaserModel, RangeNoiseCorrelatedBetweenNeighbouringRays)
{
  // A wall 3 m ahead, seen at 1 degree steps within +-30 degrees: the noise on each ray, over
  // 400 scans, has sigma 5 mm + 1 % of its range, and neighbouring rays correlate by
  // rho, rays two apart by rho^2. Without the option they do not correlate.
  for (const double rho : {0.0, 0.46}) {
    LaserOptions laser = degreeLaser(60);
    laser.range_noise_m = 0.005;
    laser.range_noise_per_m = 0.01;
    laser.range_noise_correlation = rho;
    LaserModel model(laser, 11);
    const World wall = wallAtX(3.0);
    double sum_sq = 0.0, sum_sq_expected = 0.0, lag1 = 0.0, lag2 = 0.0;
    int count = 0, count1 = 0, count2 = 0;
    for (int k = 0; k < 400; ++k) {
      const ScanSample scan = model.measure(wall, 0.0, standing(Pose2()));
      std::vector<double> error(scan.ranges.size());
      for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
        const double angle = scan.angle_min_rad + i * scan.angle_increment_rad;
        const double truth = 3.0 / std::cos(angle);
        error[i] = scan.ranges[i] - truth;
        sum_sq += error[i] * error[i];
        sum_sq_expected += std::pow(0.005 + 0.01 * truth, 2);
        ++count;
        if (i >= 1) {
          lag1 += error[i] * error[i - 1] / ((0.005 + 0.01 * truth) * (0.005 + 0.01 * truth));
          ++count1;
        }
        if (i >= 2) {
          lag2 += error[i] * error[i - 2] / ((0.005 + 0.01 * truth) * (0.005 + 0.01 * truth));
          ++count2;
        }
      }
    }
    ASSERT_EQ(count, 400 * 61);
    EXPECT_NEAR(std::sqrt(sum_sq / sum_sq_expected), 1.0, 0.02) << "rho " << rho;
    EXPECT_NEAR(lag1 / count1, rho, 0.02) << "rho " << rho;
    EXPECT_NEAR(lag2 / count2, rho * rho, 0.02) << "rho " << rho;
  }
}

TEST(LaserModel, RangeNoiseSigmaGrowsWithTheRange)
{
  // sigma = 0.002 + 0.01 r: about 0.012 m near 1 m and 0.052 m near 5 m, measured over 300
  // scans of a room seen from an off-centre pose.
  LaserOptions laser = degreeLaser(360);
  laser.fov_rad = 2.0 * M_PI * 359.0 / 360.0;
  laser.rays = 360;
  laser.range_noise_m = 0.002;
  laser.range_noise_per_m = 0.01;
  LaserModel model(laser, 5);
  const World world =
      parseWorldYaml("polygons:\n  - [[-1, -1], [6, -1], [6, 6], [-1, 6]]\n", "room");
  const Pose2 pose(0.0, 0.0, 0.0);
  double near_sum = 0.0, near_expected = 0.0, far_sum = 0.0, far_expected = 0.0;
  int near_count = 0, far_count = 0;
  for (int k = 0; k < 300; ++k) {
    const ScanSample scan = model.measure(world, k * 0.1, standing(pose));
    for (int i = 0; i < laser.rays; ++i) {
      const double angle = scan.angle_min_rad + i * laser.fov_rad / (laser.rays - 1);
      const double truth = world.castRay({0.0, 0.0}, angle, laser.max_range_m);
      const double error = scan.ranges[static_cast<std::size_t>(i)] - truth;
      const double sigma = 0.002 + 0.01 * truth;
      if (truth < 1.5) {
        near_sum += error * error;
        near_expected += sigma * sigma;
        ++near_count;
      } else if (truth > 5.0) {
        far_sum += error * error;
        far_expected += sigma * sigma;
        ++far_count;
      }
    }
  }
  ASSERT_GT(near_count, 1000);
  ASSERT_GT(far_count, 1000);
  EXPECT_NEAR(near_sum / near_expected, 1.0, 0.1);
  EXPECT_NEAR(far_sum / far_expected, 1.0, 0.1);
  EXPECT_GT(std::sqrt(far_sum / far_count), 3.0 * std::sqrt(near_sum / near_count));
}

/// A 1 m panel 2 m ahead of a wall 5 m ahead: depth steps at +-atan(0.5 / 2) = +-14.04 deg.
World panelBeforeWall()
{
  World world = wallAtX(5.0);
  world.addSegment({{2.0, -0.5}, {2.0, 0.5}});
  return world;
}

/// Indices of the rays whose reading is neither surface (no noise: more than 1 mm off both).
std::vector<int> mixedRays(const ScanSample& scan, const World& world)
{
  std::vector<int> mixed;
  for (std::size_t i = 0; i < scan.ranges.size(); ++i) {
    const double angle = scan.angle_min_rad + static_cast<double>(i) * scan.angle_increment_rad;
    const double truth = world.castRay({0.0, 0.0}, angle, 20.0);
    if (std::abs(scan.ranges[i] - truth) > 1e-3)
      mixed.push_back(static_cast<int>(i));
  }
  return mixed;
}

TEST(LaserModel, MixedPixelsLieBetweenTheSurfacesAtDepthStepsOnly)
{
  LaserOptions laser = degreeLaser(120);
  const World world = panelBeforeWall();
  LaserModel off(laser, 7);
  EXPECT_TRUE(mixedRays(off.measure(world, 0.0, standing(Pose2())), world).empty());

  laser.mixed_pixel_probability = 1.0;
  LaserModel on(laser, 7);
  const ScanSample scan = on.measure(world, 0.0, standing(Pose2()));
  const std::vector<int> mixed = mixedRays(scan, world);
  ASSERT_FALSE(mixed.empty());
  bool left_edge = false, right_edge = false;
  for (const int i : mixed) {
    const double angle_deg = i - 60.0;
    // Within half a ray increment of an edge, and between the panel and the wall.
    EXPECT_LT(std::abs(std::abs(angle_deg) - 14.04), 0.5 + 1e-6) << "ray at " << angle_deg;
    const double range = scan.ranges[static_cast<std::size_t>(i)];
    EXPECT_GT(range, 2.0);
    EXPECT_LT(range, 5.0 / std::cos((std::abs(angle_deg) + 0.5) * M_PI / 180.0));
    left_edge = left_edge || angle_deg > 0.0;
    right_edge = right_edge || angle_deg < 0.0;
  }
  EXPECT_TRUE(left_edge);
  EXPECT_TRUE(right_edge);

  // A plain room has no depth step (its corners join their walls): no mixed pixel even with
  // probability 1.
  const World room = parseWorldYaml("polygons:\n  - [[-3, -3], [5, -3], [5, 4], [-3, 4]]\n", "r");
  EXPECT_TRUE(mixedRays(on.measure(room, 0.0, standing(Pose2())), room).empty());
}

TEST(LaserModel, ABroaderBeamMixesMoreRaysAroundAnEdge)
{
  LaserOptions laser = degreeLaser(120);
  laser.rays = 1201;  // 0.1 deg per ray
  laser.mixed_pixel_probability = 1.0;
  const World world = panelBeforeWall();
  LaserModel narrow(laser, 9);
  laser.beam_divergence_rad = 2.0 * M_PI / 180.0;  // +-1 deg: about 20 rays per edge
  LaserModel broad(laser, 9);
  const std::size_t narrow_count =
      mixedRays(narrow.measure(world, 0.0, standing(Pose2())), world).size();
  const std::size_t broad_count =
      mixedRays(broad.measure(world, 0.0, standing(Pose2())), world).size();
  EXPECT_LE(narrow_count, 4u);
  EXPECT_GE(broad_count, 30u);
}

TEST(LaserModel, DarkSurfaceDropoutsRiseWithRangeAndIncidence)
{
  // A wall 2 m ahead seen from 0 to 70 deg off its normal: the chance of a dropout is
  // 0.6 (r / 10)^2 / cos(incidence) = 0.024 / cos^3 (r = 2 / cos).
  LaserOptions laser = degreeLaser(140);
  laser.max_range_m = 10.0;
  laser.dark_dropout_probability = 0.6;
  LaserModel model(laser, 11);
  const World world = wallAtX(2.0);
  double expected_near = 0.0, expected_far = 0.0;
  int dropped_near = 0, dropped_far = 0;
  for (int k = 0; k < 400; ++k) {
    const ScanSample scan = model.measure(world, k * 0.1, standing(Pose2()));
    for (int i = 0; i <= 140; ++i) {
      const double incidence = std::abs(i - 70) * M_PI / 180.0;
      const double chance = std::min(1.0, 0.024 / std::pow(std::cos(incidence), 3));
      const bool dropped = std::isnan(scan.ranges[static_cast<std::size_t>(i)]);
      if (incidence < 20.0 * M_PI / 180.0) {
        expected_near += chance;
        dropped_near += dropped ? 1 : 0;
      } else if (incidence > 50.0 * M_PI / 180.0) {
        expected_far += chance;
        dropped_far += dropped ? 1 : 0;
      }
    }
  }
  // Binomial counts: within 4 standard deviations of their expectation.
  EXPECT_NEAR(dropped_near, expected_near, 4.0 * std::sqrt(expected_near));
  EXPECT_NEAR(dropped_far, expected_far, 4.0 * std::sqrt(expected_far));
  EXPECT_GT(dropped_far, 5 * dropped_near);
}

TEST(LaserModel, SameSeedSameScanAndEffectsOffKeepTheHistoricalStream)
{
  LaserOptions laser = degreeLaser(240);
  laser.range_noise_m = 0.01;
  laser.dropout_probability = 0.05;
  const World world = wallAtX(3.0);
  // Byte for byte (a dropout's NaN is not equal to itself).
  auto same = [](const std::vector<float>& x, const std::vector<float>& y) {
    return x.size() == y.size() && std::memcmp(x.data(), y.data(), x.size() * sizeof(float)) == 0;
  };
  LaserModel a(laser, 21), b(laser, 21), other_seed(laser, 22);
  const ScanSample first = a.measure(world, 0.0, standing(Pose2()));
  EXPECT_TRUE(same(first.ranges, b.measure(world, 0.0, standing(Pose2())).ranges));
  EXPECT_FALSE(same(first.ranges, other_seed.measure(world, 0.0, standing(Pose2())).ranges));
  // Switching on an effect that touches nothing here (mixed pixels: no depth step) leaves the
  // noise and dropouts as they were.
  laser.mixed_pixel_probability = 1.0;
  LaserModel c(laser, 21);
  EXPECT_TRUE(same(first.ranges, c.measure(world, 0.0, standing(Pose2())).ranges));
}

TEST(LaserModel, MinesLikeScenarioHasEveryEffectOnAndRuns)
{
  const Scenario s =
      loadScenarioYaml(kConfig + "/sim/scenarios/mines_like.yaml", kConfig + "/sim/worlds");
  EXPECT_TRUE(s.laser.sweep);
  EXPECT_EQ(s.laser.rays, 682);
  EXPECT_GT(s.laser.range_noise_per_m, 0.0);
  EXPECT_NEAR(s.laser.range_resolution_m, 0.001, 1e-12);
  EXPECT_GT(s.laser.mixed_pixel_probability, 0.0);
  EXPECT_GT(s.laser.dark_dropout_probability, 0.0);
  Scenario short_run = s;
  short_run.duration_s = 2.0;
  const World world = loadWorldYaml(s.world_path);
  const auto robot = makeRobot(short_run.robot);
  struct Counter : SimulationSink
  {
    std::size_t scans = 0;
    void onJointState(const JointStateSample&) override {}
    void onScan(const ScanSample& scan) override { scans += scan.time_increment_s > 0.0; }
    void onTruth(const TruthSample&) override {}
  } counter;
  simulate(short_run, world, *robot, counter);
  EXPECT_EQ(counter.scans, 20u);
}

}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
