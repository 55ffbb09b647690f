// The matcher's failures on the real CARMEN logs (../shared/data/carmen, SLAM-corrected poses, see
// its README) may not grow silently: on the first 300 consecutive pairs of each log, from the
// corrected relative pose moved 5 cm in a random direction and turned 3 deg either way (the
// protocol of scripts/bench_plicp_vs_csm, seed 33), the silent gross failures (valid, > 10 cm or
// > 5 deg off the corrected pose) and the refusals (not valid) stay at or below the counts of the
// matcher as it is now. Counted against the corrected poses only (no reference matcher needed).
// And on the outdoor log, the matches refused for their gate's reach (starved of correspondences,
// run off the allowed correction, or converged with poor overlap) are matched again
// with a wider gate, changing no other match. Skips, saying so, without the logs.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/plicp.h"
#include "support/carmen_log.h"

namespace odometry_calibration {
namespace {

constexpr std::size_t kPairs = 300;

/// A log and the most gross failures and refusals of its first kPairs pairs allowed.
struct Limits
{
  const char* name;
  int max_gross;
  int max_refused;
};

struct Counts
{
  int pairs = 0;
  int gross = 0;
  int refused = 0;
};

/// The guess of the benchmark's protocol: the corrected relative pose moved 5 cm in a random
/// direction and turned 3 deg either way.
Pose2 perturbed(const Pose2& truth, std::mt19937& rng)
{
  std::uniform_real_distribution<double> direction(-M_PI, M_PI);
  std::bernoulli_distribution sign(0.5);
  const double bearing = direction(rng);
  const double turn_rad = (sign(rng) ? 3.0 : -3.0) * M_PI / 180.0;
  return Pose2(truth.x() + 0.05 * std::cos(bearing), truth.y() + 0.05 * std::sin(bearing),
               truth.theta() + turn_rad);
}

/// More than 10 cm or 5 deg off the corrected pose.
bool gross(const Pose2& truth, const PlicpResult& result)
{
  const Pose2 error = between(truth, result.T_ref_new);
  return std::hypot(error.x(), error.y()) > 0.10 || std::abs(error.theta()) > 5.0 * M_PI / 180.0;
}

/// Matches the first kPairs consecutive pairs of the log at `path` with the default options.
Counts countFailures(const std::string& path)
{
  const std::vector<carmen::Record> records = carmen::loadLog(path);
  const PlicpOptions options;
  std::mt19937 rng(33);
  Counts counts;
  for (std::size_t k = 0; k + 1 < records.size() && k < kPairs; ++k) {
    const Pose2 truth = between(records[k].T_map_robot, records[k + 1].T_map_robot);
    const PlicpResult result =
        matchScans(records[k].scan, records[k + 1].scan, perturbed(truth, rng), options);
    ++counts.pairs;
    if (!result.valid()) {
      ++counts.refused;
      continue;
    }
    counts.gross += gross(truth, result) ? 1 : 0;
  }
  return counts;
}

TEST(PlicpCarmen, GrossFailuresAndRefusalsDoNotGrow)
{
  const std::string folder = std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/carmen";
  if (!std::filesystem::is_directory(folder)) {
    GTEST_SKIP() << "no CARMEN logs at " << folder
                 << " (ODOMETRY_CALIBRATION_SHARED_DATA_DIR): nothing to guard";
  }
  // The counts of the matcher as it is now (a change that lowers them lowers these).
  const Limits logs[] = {
      {"aces", 5, 9},
      {"fhw", 16, 15},
      {"freiburg-079", 0, 0},
      {"freiburg-campus", 22, 28},
      {"infinite-corridor", 12, 10},
      {"intel", 0, 18},
      {"orebro", 4, 7},
      {"seattle", 0, 2},
  };
  int checked = 0;
  for (const Limits& log : logs) {
    const std::string path = carmen::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR, log.name);
    if (!std::filesystem::exists(path)) {
      std::printf("[ skipped  ] %s: no log at %s\n", log.name, path.c_str());
      continue;
    }
    const Counts counts = countFailures(path);
    std::printf(
        "[ carmen   ] %s: %d pairs, %d gross failures (at most %d), %d refused (at most %d)\n",
        log.name, counts.pairs, counts.gross, log.max_gross, counts.refused, log.max_refused);
    EXPECT_GT(counts.pairs, 100) << log.name << ": cannot read its FLASER pairs";
    EXPECT_LE(counts.gross, log.max_gross) << log.name << ": more silent gross failures";
    EXPECT_LE(counts.refused, log.max_refused) << log.name << ": more refusals";
    ++checked;
  }
  if (checked == 0)
    GTEST_SKIP() << "none of the CARMEN logs is in " << folder;
}

}  // namespace
}  // namespace odometry_calibration

namespace odometry_calibration {
namespace {

// Outdoors (the Freiburg campus log) most points are 15-25 m away, where the guess's 3 deg moves
// them about 1 m: at the guess few lie within max_correspondence_distance_m (0.5 m) of a reference
// surface, and the near ones alone may lead the match into a wrong minimum (refused with too few
// correspondences, too far from the guess or with poor overlap). Matching those again with the
// gate doubled leaves every other result as it is and turns many of them into matches near the
// corrected pose (the first 600 pairs, seed 33).
TEST(PlicpCarmen, MatchesRefusedForTheGatesReachAreMatchedAgainWithAWiderGate)
{
  const std::string path = carmen::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR, "freiburg-campus");
  if (!std::filesystem::exists(path)) {
    GTEST_SKIP() << "no log at " << path;
  }
  const std::vector<carmen::Record> records = carmen::loadLog(path);
  PlicpOptions single;
  single.max_correspondence_distance_doublings = 0;
  const PlicpOptions doubling;  // the default: up to twice
  std::mt19937 rng(33);
  int retried = 0, rescued = 0, rescued_gross = 0;
  for (std::size_t k = 0; k + 1 < records.size() && k < 2 * kPairs; ++k) {
    const Pose2 truth = between(records[k].T_map_robot, records[k + 1].T_map_robot);
    const Pose2 guess = perturbed(truth, rng);
    const PreparedScan reference = prepareScan(records[k].scan, doubling.line_fit);
    const PreparedScan current = prepareScan(records[k + 1].scan, doubling.line_fit);
    const PlicpResult before = matchScans(reference, current, guess, single);
    const PlicpResult after = matchScans(reference, current, guess, doubling);
    if (!refusedForReach(before)) {
      // Every other match is the same match.
      ASSERT_EQ(after.status, before.status) << "pair " << k;
      ASSERT_EQ(after.T_ref_new.vector(), before.T_ref_new.vector()) << "pair " << k;
      continue;
    }
    ++retried;
    if (after.valid()) {
      ++rescued;
      rescued_gross += gross(truth, after) ? 1 : 0;
    }
  }
  std::printf(
      "[ campus   ] %d matches refused for the gate's reach, %d valid with a wider gate, %d of "
      "those gross failures\n",
      retried, rescued, rescued_gross);
  // Measured: 81 refused for the reach, 32 of them valid with a wider gate, 2 of those gross.
  EXPECT_GE(retried, 50);
  EXPECT_GE(rescued, 20);
  EXPECT_LE(rescued_gross, 3);
}

}  // namespace
}  // namespace odometry_calibration
