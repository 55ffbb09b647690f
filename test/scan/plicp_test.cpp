// matchScans(): options, failure statuses, exact recovery, the degenerate corridor, covariance.
#include <cmath>
#include <cstdio>
#include <functional>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "odometry_calibration/scan/pcl_support.h"
#include "odometry_calibration/scan/plicp.h"
#include "support/synthetic_scans.h"

namespace odometry_calibration {
namespace {

using synthetic::kDegToRad;

/// Expects validate() to throw an invalid_argument whose message names `name`.
void expectRejected(const PlicpOptions& options, const std::string& name)
{
  try {
    validate(options);
    FAIL() << name << ": invalid value accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find(name), std::string::npos) << error.what();
  }
}

TEST(PlicpOptions, DefaultsAreValidAndBadValuesAreNamed)
{
  EXPECT_NO_THROW(validate(PlicpOptions()));
  const std::vector<std::pair<std::string, std::function<void(PlicpOptions&)>>> cases = {
      {"max_correspondence_distance_m",
       [](PlicpOptions& o) { o.max_correspondence_distance_m = 0; }},
      {"max_correspondence_distance_doublings",
       [](PlicpOptions& o) { o.max_correspondence_distance_doublings = -1; }},
      {"max_normal_angle_rad", [](PlicpOptions& o) { o.max_normal_angle_rad = 4.0; }},
      {"surface_extent_margin_m", [](PlicpOptions& o) { o.surface_extent_margin_m = -0.1; }},
      {"trim_keep_fraction", [](PlicpOptions& o) { o.trim_keep_fraction = 1.5; }},
      {"adaptive_trim_quantile", [](PlicpOptions& o) { o.adaptive_trim_quantile = 0.0; }},
      {"adaptive_trim_multiplier", [](PlicpOptions& o) { o.adaptive_trim_multiplier = -1; }},
      {"adaptive_trim_floor_m", [](PlicpOptions& o) { o.adaptive_trim_floor_m = std::nan(""); }},
      {"translation_tolerance_m", [](PlicpOptions& o) { o.translation_tolerance_m = 0; }},
      {"rotation_tolerance_rad", [](PlicpOptions& o) { o.rotation_tolerance_rad = -1; }},
      {"max_iterations", [](PlicpOptions& o) { o.max_iterations = 0; }},
      {"max_correction_translation_m", [](PlicpOptions& o) { o.max_correction_translation_m = 0; }},
      {"max_correction_rotation_rad", [](PlicpOptions& o) { o.max_correction_rotation_rad = 0; }},
      {"min_points", [](PlicpOptions& o) { o.min_points = 2; }},
      {"min_correspondences", [](PlicpOptions& o) { o.min_correspondences = 1; }},
      {"min_inlier_fraction", [](PlicpOptions& o) { o.min_inlier_fraction = 2.0; }},
      {"inlier_distance_m", [](PlicpOptions& o) { o.inlier_distance_m = 0.0; }},
      {"range_sigma_m", [](PlicpOptions& o) { o.range_sigma_m = 0.0; }},
      {"min_information_ratio", [](PlicpOptions& o) { o.min_information_ratio = 1.0; }},
      {"ambiguity_return_sigma", [](PlicpOptions& o) { o.ambiguity_return_sigma = 3.0; }},
      {"ambiguity_return_sigma", [](PlicpOptions& o) { o.ambiguity_return_sigma = -0.1; }},
      {"line_fit.max_gap_m", [](PlicpOptions& o) { o.line_fit.max_gap_m = 0.0; }},
      {"line_fit.max_gap_range_m", [](PlicpOptions& o) { o.line_fit.max_gap_range_m = -1.0; }},
  };
  for (const auto& [name, breakIt] : cases) {
    PlicpOptions options;
    breakIt(options);
    expectRejected(options, name);
  }
  Scan scan;
  scan.angle_increment_rad = 0.01;
  scan.range_max_m = 10.0;
  PlicpOptions options;
  options.max_iterations = 0;
  EXPECT_THROW(matchScans(scan, scan, Pose2(), options), std::invalid_argument);
}

/// A noise-free or noisy scan pair of the office room.
synthetic::Trial officeTrial(double sigma_m, unsigned seed)
{
  synthetic::LidarModel lidar;
  lidar.range_sigma_m = sigma_m;
  std::mt19937 rng(seed);
  return synthetic::makeTrial(synthetic::officeRoom(), lidar, synthetic::TrialOptions(), rng);
}

TEST(Plicp, TooFewPointsIsAFailureResultNotACrash)
{
  const synthetic::Trial trial = officeTrial(0.01, 1);
  Scan empty = trial.current;
  std::fill(empty.ranges_m.begin(), empty.ranges_m.end(), std::nan(""));
  Scan sparse = trial.current;
  for (std::size_t i = 0; i < sparse.ranges_m.size(); ++i) {
    if (i % 60 != 0) {
      sparse.ranges_m[i] = 0.0;  // "no return"
    }
  }
  for (const Scan* current : {&empty, &sparse}) {
    const PlicpResult result = matchScans(trial.reference, *current, trial.guess_ref_new, {});
    EXPECT_EQ(result.status, PlicpStatus::kTooFewPoints);
    EXPECT_FALSE(result.converged());
    EXPECT_NE(result.message.find("min_points"), std::string::npos) << result.message;
    EXPECT_TRUE(result.covariance.isZero());
  }
  const PlicpResult reversed = matchScans(empty, trial.current, Pose2(), {});
  EXPECT_EQ(reversed.status, PlicpStatus::kTooFewPoints);
}

TEST(Plicp, RecoversTheMotionExactlyFromNoiseFreeScans)
{
  for (unsigned seed = 0; seed < 10; ++seed) {
    const synthetic::Trial trial = officeTrial(0.0, seed);
    const PlicpResult result = matchScans(trial.reference, trial.current, trial.guess_ref_new, {});
    ASSERT_EQ(result.status, PlicpStatus::kValid) << result.message;
    EXPECT_NEAR(result.T_ref_new.x(), trial.T_ref_new.x(), 5e-4);
    EXPECT_NEAR(result.T_ref_new.y(), trial.T_ref_new.y(), 5e-4);
    EXPECT_NEAR(result.T_ref_new.theta(), trial.T_ref_new.theta(), 1e-4);
    EXPECT_LT(result.mean_residual_m, 1e-3);
    EXPECT_GT(result.correspondence_count, 400);
    EXPECT_GT(result.inlier_fraction, 0.5);
    EXPECT_FALSE(result.degeneracy.degenerate());
  }
}

/// The sensor's pose tau_s after a pose, moving at constant `velocity` (SE(2) exponential).
Pose2 poseAfter(const Pose2& start, const SensorVelocity& velocity, double tau_s)
{
  const double theta = velocity.omega_radps * tau_s;
  const double a = std::abs(theta) > 1e-12 ? std::sin(theta) / theta : 1.0;
  const double b = std::abs(theta) > 1e-12 ? (1.0 - std::cos(theta)) / theta : 0.0;
  const double vx = velocity.vx_mps * tau_s;
  const double vy = velocity.vy_mps * tau_s;
  return start * Pose2(a * vx - b * vy, b * vx + a * vy, theta);
}

/// A noise-free scan whose ray i is measured from the pose reached i * time_increment_s after
/// `stamp_pose`.
Scan sweptScan(const synthetic::World& world, const Pose2& stamp_pose,
               const SensorVelocity& velocity, double time_increment_s)
{
  const synthetic::LidarModel lidar;
  Scan scan;
  scan.angle_min_rad = -0.5 * lidar.field_of_view_rad;
  scan.angle_increment_rad = lidar.field_of_view_rad / (lidar.ray_count - 1);
  scan.range_min_m = lidar.range_min_m;
  scan.range_max_m = lidar.range_max_m;
  scan.time_increment_s = time_increment_s;
  for (int i = 0; i < lidar.ray_count; ++i) {
    const Pose2 pose = poseAfter(stamp_pose, velocity, i * time_increment_s);
    const double angle = pose.theta() + scan.angle_min_rad + i * scan.angle_increment_rad;
    scan.ranges_m.push_back(synthetic::castRay(world, Eigen::Vector2d(pose.x(), pose.y()),
                                               Eigen::Vector2d(std::cos(angle), std::sin(angle))));
  }
  return scan;
}

TEST(Plicp, MotionDuringTheSweepIsCompensated)
{
  // 1.2 m/s and 1.5 rad/s while a 10 Hz lidar sweeps 682 rays in 67 ms: without compensation
  // the scans are bent and the match is millimetres off (3 % of the motion); with it, exact.
  const synthetic::World world = synthetic::officeRoom();
  SensorVelocity velocity;
  velocity.vx_mps = 1.2;
  velocity.vy_mps = 0.1;
  velocity.omega_radps = 1.5;
  const double time_increment_s = 0.1 / 1024;
  const Pose2 reference_pose(3.0, 2.5, 0.3);
  const Pose2 current_pose = poseAfter(reference_pose, velocity, 0.1);
  const Pose2 truth = reference_pose.inverse() * current_pose;
  const Scan reference = sweptScan(world, reference_pose, velocity, time_increment_s);
  const Scan current = sweptScan(world, current_pose, velocity, time_increment_s);
  const PlicpOptions options;
  auto error = [&](const PlicpResult& result) {
    EXPECT_TRUE(result.valid()) << result.message;
    return Eigen::Vector2d(result.T_ref_new.x() - truth.x(), result.T_ref_new.y() - truth.y())
        .norm();
  };
  const double raw_m = error(matchScans(reference, current, truth, options));
  const PlicpResult compensated =
      matchScans(prepareScan(reference, options.line_fit, velocity),
                 prepareScan(current, options.line_fit, velocity), truth, options);
  std::printf("[ plicp    ] swept scans: error %.3f mm raw, %.4f mm compensated\n", 1e3 * raw_m,
              1e3 * error(compensated));
  EXPECT_LT(error(compensated), 1e-4);
  EXPECT_NEAR(compensated.T_ref_new.theta(), truth.theta(), 1e-4);
  EXPECT_GT(raw_m, 2e-3);
}

TEST(Plicp, AngularAndKdTreeSearchGiveTheSameMatch)
{
  const synthetic::Trial trial = officeTrial(0.01, 3);
  PlicpOptions kdtree;
  kdtree.correspondence_search = CorrespondenceSearch::kKdTree;
  if (!kHavePcl) {  // a build without PCL has no kd-tree: refused, saying how to get it
    try {
      matchScans(trial.reference, trial.current, trial.guess_ref_new, kdtree);
      FAIL() << "the kd-tree search was accepted without PCL";
    } catch (const std::invalid_argument& error) {
      EXPECT_NE(std::string(error.what()).find("kKdTree (the kd-tree search) needs PCL"),
                std::string::npos)
          << error.what();
    }
    return;
  }
  const PlicpResult a = matchScans(trial.reference, trial.current, trial.guess_ref_new, {});
  const PlicpResult b = matchScans(trial.reference, trial.current, trial.guess_ref_new, kdtree);
  ASSERT_TRUE(a.valid());
  ASSERT_TRUE(b.valid());
  EXPECT_NEAR((a.T_ref_new.vector() - b.T_ref_new.vector()).norm(), 0.0, 1e-9);
  EXPECT_EQ(a.correspondence_count, b.correspondence_count);
}

TEST(Plicp, CovarianceIsSymmetricPositiveDefiniteAndScalesWithTheNoise)
{
  const synthetic::Trial trial = officeTrial(0.01, 4);
  PlicpOptions options;
  const PlicpResult result =
      matchScans(trial.reference, trial.current, trial.guess_ref_new, options);
  ASSERT_TRUE(result.valid());
  EXPECT_NEAR((result.covariance - result.covariance.transpose()).norm(), 0.0, 1e-18);
  EXPECT_GT(
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(result.covariance).eigenvalues().minCoeff(),
      0.0);
  // 682 rays, 1 cm noise: sub-millimetre, hundredths of a degree.
  EXPECT_LT(std::sqrt(result.covariance(0, 0)), 2e-3);
  EXPECT_LT(std::sqrt(result.covariance(2, 2)), 0.05 * kDegToRad);
  options.range_sigma_m = 0.02;
  const PlicpResult doubled =
      matchScans(trial.reference, trial.current, trial.guess_ref_new, options);
  EXPECT_NEAR(doubled.covariance(0, 0) / result.covariance(0, 0), 4.0, 1e-6);
  options.compute_covariance = false;
  EXPECT_TRUE(
      matchScans(trial.reference, trial.current, trial.guess_ref_new, options).covariance.isZero());
}

TEST(Plicp, CorrectionBeyondTheLimitFails)
{
  const synthetic::Trial trial = officeTrial(0.01, 5);
  PlicpOptions options;
  options.max_correction_translation_m = 0.005;  // the guess is 2-5 cm off
  const PlicpResult result =
      matchScans(trial.reference, trial.current, trial.guess_ref_new, options);
  EXPECT_EQ(result.status, PlicpStatus::kCorrectionTooLarge);
  EXPECT_NE(result.message.find("initial guess"), std::string::npos);
  options = PlicpOptions();
  options.max_iterations = 1;
  EXPECT_EQ(matchScans(trial.reference, trial.current, trial.guess_ref_new, options).status,
            PlicpStatus::kNoConvergence);
}

TEST(Plicp, CorridorIsReportedDegenerateAlongItsAxis)
{
  const synthetic::World corridor = synthetic::corridor();
  synthetic::LidarModel lidar;
  std::mt19937 rng(8);
  for (int trial_index = 0; trial_index < 20; ++trial_index) {
    const synthetic::Trial trial =
        synthetic::makeTrial(corridor, lidar, synthetic::TrialOptions(), rng);
    const PlicpResult result = matchScans(trial.reference, trial.current, trial.guess_ref_new, {});
    ASSERT_EQ(result.status, PlicpStatus::kDegenerate) << result.message;
    EXPECT_TRUE(result.converged());
    EXPECT_FALSE(result.valid());
    ASSERT_EQ(result.degeneracy.direction, DegenerateDirection::kTranslation);
    EXPECT_NE(result.message.find("not constrained"), std::string::npos);
    // The corridor's axis (world x) seen from the reference pose.
    const Eigen::Vector2d axis =
        Eigen::Rotation2Dd(-trial.T_world_ref.theta()) * Eigen::Vector2d::UnitX();
    EXPECT_GT(std::abs(result.degeneracy.axis_ref.dot(axis)), 0.999);
    // Along the axis: the guess, not a measurement. Across it and in heading: measured.
    const Eigen::Vector2d estimate(result.T_ref_new.x(), result.T_ref_new.y());
    const Eigen::Vector2d guess(trial.guess_ref_new.x(), trial.guess_ref_new.y());
    const Eigen::Vector2d truth(trial.T_ref_new.x(), trial.T_ref_new.y());
    EXPECT_NEAR(result.degeneracy.axis_ref.dot(estimate - guess), 0.0, 1e-9);
    const Eigen::Vector2d across(-axis.y(), axis.x());
    EXPECT_LT(std::abs(across.dot(estimate - truth)), 5e-3);
    EXPECT_LT(std::abs(normalizeAngle(result.T_ref_new.theta() - trial.T_ref_new.theta())),
              0.1 * kDegToRad);
    const Eigen::Matrix2d translation_covariance = result.covariance.topLeftCorner<2, 2>();
    EXPECT_GT(axis.dot(translation_covariance * axis),
              10.0 * across.dot(translation_covariance * across));
  }
}

TEST(Plicp, StatusNamesAreReadable)
{
  EXPECT_STREQ(toString(PlicpStatus::kValid), "valid");
  EXPECT_STREQ(toString(PlicpStatus::kDegenerate), "degenerate");
  EXPECT_STREQ(toString(PlicpStatus::kTooFewPoints), "too few points");
  EXPECT_STREQ(toString(PlicpStatus::kNoConvergence), "no convergence");
  EXPECT_STREQ(toString(PlicpStatus::kCorrectionTooLarge), "correction too large");
}

}  // namespace
}  // namespace odometry_calibration
