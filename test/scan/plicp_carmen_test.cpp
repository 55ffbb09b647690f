// The matcher's failures on the real CARMEN logs (../shared/data/carmen, SLAM-corrected poses, see
// its README) may not grow silently: on the first 300 consecutive pairs of each log, from the
// corrected relative pose moved 5 cm in a random direction and turned 3 deg either way (the
// protocol of scripts/bench_plicp_vs_csm, seed 33), the silent gross failures (valid, > 10 cm or
// > 5 deg off the corrected pose) and the refusals (not valid) stay at or below the counts of the
// matcher as it is now. Counted against the corrected poses only (no reference matcher needed).
// Skips, saying so, without the logs.
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

/// Matches the first kPairs consecutive pairs of the log at `path` with the default options.
Counts countFailures(const std::string& path)
{
  const std::vector<carmen::Record> records = carmen::loadLog(path);
  const PlicpOptions options;
  std::mt19937 rng(33);
  std::uniform_real_distribution<double> direction(-M_PI, M_PI);
  std::bernoulli_distribution sign(0.5);
  Counts counts;
  for (std::size_t k = 0; k + 1 < records.size() && k < kPairs; ++k) {
    const Pose2 truth = between(records[k].T_map_robot, records[k + 1].T_map_robot);
    const double bearing = direction(rng);
    const double turn_rad = (sign(rng) ? 3.0 : -3.0) * M_PI / 180.0;
    const Pose2 guess(truth.x() + 0.05 * std::cos(bearing), truth.y() + 0.05 * std::sin(bearing),
                      truth.theta() + turn_rad);
    const PlicpResult result = matchScans(records[k].scan, records[k + 1].scan, guess, options);
    ++counts.pairs;
    if (!result.valid()) {
      ++counts.refused;
      continue;
    }
    const Pose2 error = between(truth, result.T_ref_new);
    counts.gross +=
        std::hypot(error.x(), error.y()) > 0.10 || std::abs(error.theta()) > 5.0 * M_PI / 180.0 ? 1
                                                                                                : 0;
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
      {"freiburg-campus", 21, 33},
      {"infinite-corridor", 12, 11},
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
