// The ambiguity check of weak PLICP matches and the early stop of its rematches (issue 33): a
// rematch that is back at the solution stops, and the check's outcome (status, pose, widened
// covariance) is exactly what it is with every rematch run to convergence.
#include <iostream>
#include <memory>
#include <random>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/plicp_ambiguity.h"
#include "odometry_calibration/scan/plicp_match.h"
#include "support/synthetic_scans.h"

namespace odometry_calibration {
namespace {

/// A match as matchScans makes it, with what its ambiguity check did: whether it ran, the
/// rematches' iterations, how many rematches the early stop ended, and whether it widened the
/// covariance.
struct CheckedMatch
{
  PlicpResult result;
  bool checked = false;
  int rematches = 0;
  int rematch_iterations = 0;
  int rematches_stopped = 0;
  bool widened = false;
};

CheckedMatch matchCounted(const PreparedScan& reference, const PreparedScan& current,
                          const Pose2& guess, const PlicpOptions& options)
{
  std::unique_ptr<NearestPointSearch> search;
  CheckedMatch match;
  match.result = matchOnce(reference, current, guess, options, search);
  match.checked = needsAmbiguityCheck(match.result, options);
  if (!match.checked)
    return match;
  const Eigen::Matrix3d unchecked_covariance = match.result.covariance;
  match.result =
      checkAmbiguity(std::move(match.result), options,
                     [&](const Pose2& start, bool with_covariance, const IterationStop& stop) {
                       PlicpOptions rematch_options = options;
                       rematch_options.compute_covariance = with_covariance;
                       bool stopped = false;
                       IterationStop counted_stop;
                       if (stop) {
                         counted_stop = [&](const Pose2& T_ref_new, double pose_uncertainty_m) {
                           stopped = stop(T_ref_new, pose_uncertainty_m);
                           return stopped;
                         };
                       }
                       PlicpResult rematch = matchOnce(reference, current, start, rematch_options,
                                                       search, counted_stop);
                       ++match.rematches;
                       match.rematch_iterations += rematch.iterations;
                       match.rematches_stopped += stopped ? 1 : 0;
                       return rematch;
                     });
  match.widened = match.result.valid() && match.result.covariance != unchecked_covariance;
  return match;
}

/// A long wall with two pillars and a box a few metres from it: seen with 180 rays, the slide
/// along the wall is weakly held by a few points on the pillars (the check widens a third of
/// these matches).
synthetic::World wallAndPillars()
{
  synthetic::World world;
  world.name = "wall and pillars";
  world.addSegment(-30, 0, 30, 0);
  world.addCircle(-3.0, 3.0, 0.3);
  world.addCircle(4.0, 3.5, 0.2);
  world.addBox(0.0, 6.0, 0.6, 0.6, 0.3);
  world.free_box = Eigen::Vector4d(-2.0, 1.0, 2.0, 2.5);
  world.clearance_m = 0.5;
  return world;
}

/// A 180-ray lidar (1 cm noise) over `field_of_view_deg`, to `range_max_m`.
synthetic::LidarModel lidar180(double field_of_view_deg, double range_max_m)
{
  synthetic::LidarModel lidar;
  lidar.ray_count = 180;
  lidar.field_of_view_rad = field_of_view_deg * M_PI / 180.0;
  lidar.range_max_m = range_max_m;
  return lidar;
}

/// A random trial in `world`, both scans prepared with the default line fits, and its guess.
struct PreparedTrial
{
  PreparedScan reference;
  PreparedScan current;
  Pose2 guess;
};

PreparedTrial preparedTrial(const synthetic::World& world, const synthetic::LidarModel& lidar,
                            std::mt19937& rng)
{
  const synthetic::Trial trial = synthetic::makeTrial(world, lidar, synthetic::TrialOptions(), rng);
  const LineFitOptions line_fit;
  return {prepareScan(trial.reference, line_fit), prepareScan(trial.current, line_fit),
          trial.guess_ref_new};
}

/// Every trial matched with the early stop (defaults) and with every rematch run to
/// convergence (ambiguity_return_sigma 0).
struct Comparison
{
  int trials = 0;
  int checked = 0;
  int widened = 0;
  int widened_with_stops = 0;  // widened, though some of its rematches stopped early
  int differ = 0;              // status, pose or covariance not identical
  int stopped = 0;             // rematches the early stop ended (of 4 per checked match)
  int iterations_with_stop = 0;
  int iterations_to_convergence = 0;
  int unchanged_with_all_stopped = 0;  // checked, not widened, every rematch stopped
};

Comparison compare(const synthetic::World& world, const synthetic::LidarModel& lidar, unsigned seed,
                   int trials)
{
  std::mt19937 rng(seed);
  const PlicpOptions with_stop;
  PlicpOptions to_convergence;
  to_convergence.ambiguity_return_sigma = 0.0;
  Comparison comparison;
  for (int k = 0; k < trials; ++k) {
    const auto [reference, current, guess] = preparedTrial(world, lidar, rng);
    const CheckedMatch now = matchCounted(reference, current, guess, with_stop);
    const CheckedMatch before = matchCounted(reference, current, guess, to_convergence);
    // The helper makes the match as matchScans does.
    const PlicpResult public_result = matchScans(reference, current, guess, with_stop);
    EXPECT_EQ(public_result.covariance, now.result.covariance) << "trial " << k;
    EXPECT_EQ(public_result.T_ref_new.vector(), now.result.T_ref_new.vector()) << "trial " << k;
    ++comparison.trials;
    comparison.checked += now.checked ? 1 : 0;
    comparison.widened += now.widened ? 1 : 0;
    comparison.widened_with_stops += now.widened && now.rematches_stopped > 0 ? 1 : 0;
    const bool same = now.result.status == before.result.status &&
                      now.result.T_ref_new.vector() == before.result.T_ref_new.vector() &&
                      now.result.covariance == before.result.covariance;
    comparison.differ += same ? 0 : 1;
    EXPECT_TRUE(same) << "trial " << k << ": widened " << now.widened << " with the early stop, "
                      << before.widened << " without";
    comparison.stopped += now.rematches_stopped;
    comparison.iterations_with_stop += now.rematch_iterations;
    comparison.iterations_to_convergence += before.rematch_iterations;
    comparison.unchanged_with_all_stopped +=
        now.checked && !now.widened && now.rematches_stopped == now.rematches ? 1 : 0;
  }
  std::cout << world.name << ": " << comparison.checked << " of " << comparison.trials
            << " checked, " << comparison.widened << " widened (" << comparison.widened_with_stops
            << " of them with stopped rematches), " << comparison.differ
            << " differ from rematches to convergence; " << comparison.stopped
            << " rematches stopped early, rematch iterations " << comparison.iterations_with_stop
            << " against " << comparison.iterations_to_convergence << "\n";
  return comparison;
}

TEST(PlicpAmbiguity, EarlyStopKeepsEveryWidenedCovariance)
{
  // 360-degree 180-ray scans to 8 m by the wall and pillars: the check fires on every match and
  // widens about a third; the early stop must change none of them, and save iterations.
  const Comparison c = compare(wallAndPillars(), lidar180(360.0, 8.0), 2, 100);
  EXPECT_EQ(c.differ, 0);
  EXPECT_GE(c.checked, 90);
  EXPECT_GE(c.widened, 20);             // the scene does exercise the widening...
  EXPECT_GE(c.widened_with_stops, 10);  // ... also where some of the rematches stopped early
  EXPECT_GT(c.stopped, c.checked);      // more than one rematch per check stops early
  EXPECT_LT(c.iterations_with_stop, 0.9 * c.iterations_to_convergence);
}

TEST(PlicpAmbiguity, RematchesBackAtTheSolutionStopEarly)
{
  // The cluttered room with 180 rays over 180 degrees: the few checked matches are well
  // constrained; every rematch comes back to the solution and stops there, nothing is widened.
  const Comparison c = compare(synthetic::clutteredRoom(), lidar180(180.0, 20.0), 1, 100);
  EXPECT_EQ(c.differ, 0);
  EXPECT_GE(c.checked, 2);
  EXPECT_EQ(c.widened, 0);
  EXPECT_EQ(c.unchanged_with_all_stopped, c.checked);
  EXPECT_EQ(c.stopped, 4 * c.checked);
  EXPECT_LT(c.iterations_with_stop, 0.8 * c.iterations_to_convergence);
}

TEST(PlicpAmbiguity, WithoutTurnedStartsTheCheckRematchesTwiceAndWidensLess)
{
  // ambiguity_offset_rad 0: only the two starts shifted along the weakest direction. By the wall
  // and pillars (the slide along the wall is the ambiguity) they widen most of what the four
  // starts widen and nothing the four do not, with two rematches per checked match instead of
  // four (a third one only to return a clearly better fit); no status or pose changes.
  std::mt19937 rng(2);
  const synthetic::World world = wallAndPillars();
  const synthetic::LidarModel lidar = lidar180(360.0, 8.0);
  const PlicpOptions all_starts;
  PlicpOptions shifted_only;
  shifted_only.ambiguity_offset_rad = 0.0;
  int checked = 0, widened_all = 0, widened_shifted = 0, rematches = 0;
  for (int k = 0; k < 100; ++k) {
    const auto [reference, current, guess] = preparedTrial(world, lidar, rng);
    const CheckedMatch all = matchCounted(reference, current, guess, all_starts);
    const CheckedMatch shifted = matchCounted(reference, current, guess, shifted_only);
    EXPECT_EQ(all.result.status, shifted.result.status) << "trial " << k;
    EXPECT_EQ(all.result.T_ref_new.vector(), shifted.result.T_ref_new.vector()) << "trial " << k;
    EXPECT_FALSE(shifted.widened && !all.widened) << "trial " << k;
    checked += shifted.checked ? 1 : 0;
    widened_all += all.widened ? 1 : 0;
    widened_shifted += shifted.widened ? 1 : 0;
    rematches += shifted.rematches;
  }
  std::cout << "wall and pillars without turned starts: " << checked << " checked, " << rematches
            << " rematches, " << widened_shifted << " widened (" << widened_all
            << " with the turned starts)\n";
  EXPECT_GE(checked, 90);
  EXPECT_LE(rematches, 2 * checked + checked / 10);
  EXPECT_GE(widened_shifted, widened_all / 2);
  EXPECT_GE(widened_shifted, 10);
  PlicpOptions negative;
  negative.ambiguity_offset_rad = -0.1;
  EXPECT_THROW(validate(negative), std::invalid_argument);
  EXPECT_NO_THROW(validate(shifted_only));
}

TEST(PlicpAmbiguity, BackAtSolutionNeedsTheSolutionsTrimmingAndItsBasin)
{
  PlicpResult best;
  best.status = PlicpStatus::kValid;
  best.T_ref_new = Pose2(1.0, 2.0, 0.5);
  best.covariance = Eigen::Vector3d(1e-4, 4e-6, 1e-6).asDiagonal();  // sigma 1 cm, 2 mm, 1 mrad
  PlicpOptions options;  // ambiguity_return_sigma 0.5, adaptive_trim_floor_m 0.02
  const IterationStop stop = backAtSolution(best, options);
  ASSERT_TRUE(stop);
  EXPECT_TRUE(stop(Pose2(1.004, 2.0, 0.5), 0.001));                      // 0.4 sigma along x
  EXPECT_FALSE(stop(Pose2(1.0, 2.0012, 0.5), 0.001));                    // 0.6 sigma along y
  EXPECT_FALSE(stop(Pose2(1.0, 2.0, 0.5006), 0.001));                    // 0.6 sigma in heading
  EXPECT_TRUE(stop(Pose2(1.0, 2.0, 0.5 + 0.0004 - 2.0 * M_PI), 0.001));  // angles wrap
  // Back within the basin, but after a step so large that the next trimming keeps more.
  EXPECT_FALSE(stop(Pose2(1.004, 2.0, 0.5), 0.021));
  options.ambiguity_return_sigma = 0.0;  // every rematch runs to convergence
  EXPECT_FALSE(backAtSolution(best, options));
}

}  // namespace
}  // namespace odometry_calibration
