// Issue 16, "honest in weak scenes": a match reported valid must be right within its own
// covariance, along its least certain direction and in heading. Simulated pairs in scenes a
// short-range lidar (5.6 m, as a Hokuyo URG) sees little of: the simulator's hall of pillars,
// a smooth corridor, a corridor with door recesses.
#include <cmath>
#include <iostream>
#include <map>
#include <random>
#include <string>

#include <gtest/gtest.h>
#include <Eigen/Eigenvalues>

#include "odometry_calibration/scan/plicp.h"
#include "support/synthetic_scans.h"

namespace odometry_calibration {
namespace {

constexpr int kTrialsPerWorld = 500;  // per world and seed

/// The simulator's hall (config/sim/worlds/hall.yaml): 30 m x 20 m, pillars 4-8 m apart; with a
/// 5.6 m range, most poses see one to three pillars and little or no wall.
synthetic::World sparseHall()
{
  synthetic::World world;
  world.name = "sparse hall";
  world.addSegment(-15, -10, 15, -10);
  world.addSegment(15, -10, 15, 10);
  world.addSegment(15, 10, -15, 10);
  world.addSegment(-15, 10, -15, -10);
  world.addBox(-8.0, -5.0, 0.6, 0.6);
  world.addBox(0.0, -5.0, 0.6, 0.6, 0.4);
  world.addBox(8.0, -5.0, 0.6, 0.6);
  world.addBox(-8.0, 5.0, 0.6, 0.6, 0.2);
  world.addBox(8.0, 5.0, 0.6, 0.6);
  world.addBox(12.5, 0.0, 2.0, 1.0);
  world.addCircle(0.0, 5.0, 0.4);
  world.addCircle(-4.0, 0.0, 0.3);
  world.addCircle(4.0, 0.0, 0.3);
  world.addCircle(-12.0, 0.0, 0.5);
  world.free_box = Eigen::Vector4d(-13.0, -8.0, 13.0, 8.0);
  world.clearance_m = 0.6;
  return world;
}

/// A corridor 2 m wide with door recesses every 6 m on one side (10 cm deep, 1 m wide).
synthetic::World corridorWithDoors()
{
  synthetic::World world;
  world.name = "corridor with doors";
  world.addSegment(-100, 0, 100, 0);
  double x = -100.0;
  for (double door = -99.0; door < 100.0; door += 6.0) {
    world.addSegment(x, 2, door, 2);
    world.addSegment(door, 2, door, 2.1);
    world.addSegment(door, 2.1, door + 1.0, 2.1);
    world.addSegment(door + 1.0, 2.1, door + 1.0, 2);
    x = door + 1.0;
  }
  world.addSegment(x, 2, 100, 2);
  world.free_box = Eigen::Vector4d(-5.0, 0.6, 5.0, 1.4);
  world.clearance_m = 0.3;
  return world;
}

struct Honesty
{
  int trials = 0;
  int valid = 0;
  int beyond_5_sigma = 0;
  double worst_sigma = 0.0;
  std::map<std::string, int> statuses;
};

Honesty runWorld(const synthetic::World& world, unsigned seed, bool check_ambiguity = true)
{
  synthetic::LidarModel lidar;  // 682 rays over 240 deg, 1 cm noise
  lidar.range_max_m = 5.6;
  std::mt19937 rng(seed);
  Honesty honesty;
  for (int k = 0; k < kTrialsPerWorld; ++k) {
    const synthetic::Trial trial =
        synthetic::makeTrial(world, lidar, synthetic::TrialOptions(), rng);
    PlicpOptions options;
    options.check_ambiguity = check_ambiguity;
    const PlicpResult result =
        matchScans(trial.reference, trial.current, trial.guess_ref_new, options);
    ++honesty.trials;
    ++honesty.statuses[toString(result.status)];
    if (!result.valid())
      continue;
    ++honesty.valid;
    Eigen::Vector3d error = result.T_ref_new.vector() - trial.T_ref_new.vector();
    error(2) = normalizeAngle(error(2));
    // The least certain translation direction: the eigenvector of the largest eigenvalue.
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> eigen(
        result.covariance.topLeftCorner<2, 2>());
    const Eigen::Vector2d weakest = eigen.eigenvectors().col(1);
    const double along_sigma =
        std::abs(weakest.dot(error.head<2>())) / std::sqrt(eigen.eigenvalues()(1));
    const double heading_sigma = std::abs(error(2)) / std::sqrt(result.covariance(2, 2));
    const double worst = std::max(along_sigma, heading_sigma);
    honesty.worst_sigma = std::max(honesty.worst_sigma, worst);
    if (worst > 5.0) {
      ++honesty.beyond_5_sigma;
      if (check_ambiguity)
        std::cout << "  beyond 5 sigma: error " << error.transpose() << ", sigma along/heading "
                  << along_sigma << " / " << heading_sigma << ", sigmas "
                  << std::sqrt(eigen.eigenvalues()(1)) << " m, "
                  << std::sqrt(eigen.eigenvalues()(0)) << " m, "
                  << std::sqrt(result.covariance(2, 2)) << " rad; correspondences "
                  << result.correspondence_count << ", inliers " << result.inlier_fraction
                  << ", residual " << result.mean_residual_m << ", iterations " << result.iterations
                  << ", true motion " << trial.T_ref_new.vector().transpose() << "\n";
    }
  }
  return honesty;
}

void print(const std::string& name, const Honesty& h)
{
  std::cout << name << ": " << h.valid << " of " << h.trials << " valid, " << h.beyond_5_sigma
            << " beyond 5 sigma (worst " << h.worst_sigma << " sigma); statuses:";
  for (const auto& [status, count] : h.statuses)
    std::cout << " " << status << " " << count;
  std::cout << "\n";
}

TEST(PlicpHonesty, ValidMatchesInWeakScenesAreRightWithinTheirCovariance)
{
  // The corridors: every match degenerate along the axis, none valid and wrong.
  for (const synthetic::World& world : {synthetic::corridor(), corridorWithDoors()}) {
    const Honesty honesty = runWorld(world, 16);
    print(world.name, honesty);
    EXPECT_EQ(honesty.beyond_5_sigma, 0) << world.name;
  }
  // The sparse hall, 1500 pairs: issue 16 asks for none beyond 5 sigma; measured none of 1156
  // valid with the ambiguity check (3 without, wrong minima only the check finds).
  int valid = 0, beyond = 0, beyond_unchecked = 0;
  for (const unsigned seed : {1u, 2u, 16u}) {
    const Honesty honesty = runWorld(sparseHall(), seed);
    print("sparse hall, seed " + std::to_string(seed), honesty);
    valid += honesty.valid;
    beyond += honesty.beyond_5_sigma;
    beyond_unchecked += runWorld(sparseHall(), seed, false).beyond_5_sigma;
  }
  std::cout << "sparse hall: " << beyond << " of " << valid
            << " valid matches beyond 5 sigma with the ambiguity check, " << beyond_unchecked
            << " without\n";
  EXPECT_GT(valid, 1000);
  EXPECT_EQ(beyond, 0);
  EXPECT_GT(beyond_unchecked, 0);  // the scene still holds the wrong minima the check must find
}

}  // namespace
}  // namespace odometry_calibration
