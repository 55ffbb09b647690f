// Acceptance of issue 11 on real scans: every consecutive pair of the Mines ParisTech log
// (../shared/data/mines/exp1.dat, 682-ray Hokuyo URG-04LX, see its README). Skips without it.
#include <cmath>
#include <cstdio>
#include <map>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/plicp.h"
#include "support/mines_log.h"

namespace odometry_calibration {
namespace {

struct MinesRun
{
  int pairs = 0;
  int converged = 0;
  double matched_m = 0.0;   // summed |translation| of the laser, matched (odometry if failed)
  double odometry_m = 0.0;  // summed |translation| of the laser, nominal wheel odometry
  std::map<std::string, int> statuses;

  double distanceDifference() const { return matched_m / odometry_m - 1.0; }
};

/// Matches every consecutive pair, the scans compensated for the motion during their sweep
/// (velocity from the nominal odometry), from the odometry guess or from a zero guess.
MinesRun runMines(const std::vector<mines::Record>& records, bool zero_guess)
{
  const PlicpOptions options;
  std::vector<PreparedScan> scans;
  for (std::size_t k = 0; k < records.size(); ++k) {
    scans.push_back(
        prepareScan(records[k].scan, options.line_fit, mines::laserVelocity(records, k)));
  }
  MinesRun run;
  for (std::size_t k = 0; k + 1 < records.size(); ++k) {
    const Pose2 odometry = mines::laserMotion(mines::wheelOdometry(records[k], records[k + 1]));
    // Initial guess: the nominal odometry, one line earlier: the README's encoder counters run
    // about 0.1-0.2 s (one line) ahead of the scans on the same line.
    const Pose2 guess = zero_guess ? Pose2()
                        : k == 0
                            ? odometry
                            : mines::laserMotion(mines::wheelOdometry(records[k - 1], records[k]));
    const PlicpResult result = matchScans(scans[k], scans[k + 1], guess, options);
    ++run.pairs;
    ++run.statuses[toString(result.status)];
    const Pose2& used = result.converged() ? result.T_ref_new : odometry;
    run.converged += result.converged() ? 1 : 0;
    run.matched_m += std::hypot(used.x(), used.y());
    run.odometry_m += std::hypot(odometry.x(), odometry.y());
  }
  return run;
}

void print(const char* label, const MinesRun& run)
{
  std::printf("[ plicp    ] Mines, %s:", label);
  for (const auto& [status, count] : run.statuses) {
    std::printf(" %s: %d;", status.c_str(), count);
  }
  std::printf(
      "\n[ plicp    ] Mines, %s: %d of %d pairs converge (%.1f %%); matched %.3f m vs nominal "
      "odometry %.3f m of the laser: %+.2f %%\n",
      label, run.converged, run.pairs, 100.0 * run.converged / run.pairs, run.matched_m,
      run.odometry_m, 100.0 * run.distanceDifference());
}

class PlicpMinesAcceptance : public ::testing::Test
{
protected:
  void SetUp() override
  {
    const std::string path = mines::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR);
    records_ = mines::loadLog(path);
    if (records_.empty()) {
      GTEST_SKIP() << "Mines log not found: " << path;
    }
    ASSERT_EQ(records_.size(), 756u);
  }

  std::vector<mines::Record> records_;
};

TEST_F(PlicpMinesAcceptance, ConsecutivePairsConvergeAndAgreeWithOdometryOnDistance)
{
  const MinesRun run = runMines(records_, false);
  print("odometry guess", run);
  EXPECT_GE(static_cast<double>(run.converged) / run.pairs, 0.99);
  // Issue 11 asks for 2 %; measured -1.80 %. Without the motion compensation -2.15 %, without
  // the surface-extent margin -2.19 %. The nominal odometry is uncalibrated (the bag
  // calibration finds the wheel radii a few percent below nominal).
  EXPECT_LT(std::abs(run.distanceDifference()), 0.02);
}

TEST_F(PlicpMinesAcceptance, AZeroGuessFindsTheSameDistance)
{
  // A matcher that stays near its initial guess in feature-poor stretches reads short from a
  // zero guess: before the surface-extent margin and the motion compensation, -5.0 % against
  // -2.2 % from the odometry guess. Now -1.88 % against -1.80 %.
  const MinesRun from_odometry = runMines(records_, false);
  const MinesRun from_zero = runMines(records_, true);
  print("zero guess", from_zero);
  EXPECT_GE(static_cast<double>(from_zero.converged) / from_zero.pairs, 0.99);
  EXPECT_LT(std::abs(from_zero.distanceDifference() - from_odometry.distanceDifference()), 0.005);
}

}  // namespace
}  // namespace odometry_calibration
