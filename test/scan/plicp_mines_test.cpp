// Acceptance of issue 11 on real scans: every consecutive pair of the Mines ParisTech log
// (../shared/data/mines/exp1.dat, 682-ray Hokuyo URG-04LX, see its README), and how much the
// keyframe matches depend on their guess (issue 16). Skips without it.
#include <cmath>
#include <cstdio>
#include <map>
#include <vector>

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
  // Within 2 % of the nominal odometry; measured -1.83 %. The nominal odometry is uncalibrated
  // (the bag calibration finds the wheel radii a few percent below nominal).
  EXPECT_LT(std::abs(run.distanceDifference()), 0.02);
}

TEST_F(PlicpMinesAcceptance, AZeroGuessFindsTheSameDistance)
{
  // A matcher that stays near its initial guess in feature-poor stretches reads short from a
  // zero guess. Measured: -1.90 % from a zero guess against -1.83 % from the odometry guess.
  const MinesRun from_odometry = runMines(records_, false);
  const MinesRun from_zero = runMines(records_, true);
  print("zero guess", from_zero);
  EXPECT_GE(static_cast<double>(from_zero.converged) / from_zero.pairs, 0.99);
  EXPECT_LT(std::abs(from_zero.distanceDifference() - from_odometry.distanceDifference()), 0.005);
}

/// Keyframe pairs 5 scans (about 0.5 s) apart, as the calibration's, each matched from the chain
/// of the consecutive matches between them scaled by 0.97 and by 1.03: 100 (sum of the matched
/// distances from the long guess / the same from the short guess - 1) [%] over the pairs valid
/// from both, with its standard error. A matcher that stays near its guess where a scene fixes the
/// motion weakly reads positive; the calibration then keeps part of the nominal parameters' error.
struct KeyframeLean
{
  double percent = 0.0;             ///< 100 (sum from the long guess / sum from the short - 1)
  double standard_error_pct = 0.0;  ///< of percent, the pairs taken as independent
  double rms_difference_mm = 0.0;   ///< RMS over the pairs of (from long guess - from short)
  int pairs = 0;                    ///< valid from both guesses
};

KeyframeLean keyframeLean(const std::vector<mines::Record>& records, const PlicpOptions& options)
{
  std::vector<PreparedScan> scans;
  for (std::size_t k = 0; k < records.size(); ++k) {
    scans.push_back(
        prepareScan(records[k].scan, options.line_fit, mines::laserVelocity(records, k)));
  }
  std::vector<Pose2> consecutive;
  for (std::size_t k = 0; k + 1 < records.size(); ++k) {
    const Pose2 guess =
        k == 0 ? Pose2() : mines::laserMotion(mines::wheelOdometry(records[k - 1], records[k]));
    const PlicpResult result = matchScans(scans[k], scans[k + 1], guess, options);
    consecutive.push_back(result.converged() ? result.T_ref_new : guess);
  }
  double long_m = 0.0;
  double short_m = 0.0;
  std::vector<double> differences_m;  // per pair: from the long guess - from the short one
  for (std::size_t k = 0; k + 5 < records.size(); k += 5) {
    Pose2 chain;
    for (std::size_t j = k; j < k + 5; ++j) {
      chain = chain * consecutive[j];
    }
    const PlicpResult from_long =
        matchScans(scans[k], scans[k + 5], se2Exp(1.03 * se2Log(chain)), options);
    const PlicpResult from_short =
        matchScans(scans[k], scans[k + 5], se2Exp(0.97 * se2Log(chain)), options);
    if (!from_long.valid() || !from_short.valid()) {
      continue;
    }
    const double long_pair_m = std::hypot(from_long.T_ref_new.x(), from_long.T_ref_new.y());
    const double short_pair_m = std::hypot(from_short.T_ref_new.x(), from_short.T_ref_new.y());
    long_m += long_pair_m;
    short_m += short_pair_m;
    differences_m.push_back(long_pair_m - short_pair_m);
  }
  KeyframeLean lean;
  lean.pairs = static_cast<int>(differences_m.size());
  lean.percent = 100.0 * (long_m / short_m - 1.0);
  const double n = static_cast<double>(differences_m.size());
  const double mean_m = (long_m - short_m) / n;
  double sum2 = 0.0;
  for (const double d : differences_m) {
    sum2 += (d - mean_m) * (d - mean_m);
  }
  lean.standard_error_pct = 100.0 * std::sqrt(n * sum2 / (n - 1.0)) / short_m;
  double squares = 0.0;
  for (const double d : differences_m) {
    squares += d * d;
  }
  lean.rms_difference_mm = 1e3 * std::sqrt(squares / n);
  return lean;
}

/// keyframeLean of the log with the fixed trimming keeping `keep` of the correspondences.
KeyframeLean leanWithKeep(const std::vector<mines::Record>& records, double keep)
{
  PlicpOptions options;
  options.trim_keep_fraction = keep;
  const KeyframeLean lean = keyframeLean(records, options);
  std::printf(
      "[ plicp    ] Mines, keyframes 5 scans apart, guess x1.03 vs x0.97, keep %.2f: "
      "%+.3f %% (+-%.3f), per pair %.2f mm RMS, over %d pairs\n",
      keep, lean.percent, lean.standard_error_pct, lean.rms_difference_mm, lean.pairs);
  return lean;
}

TEST_F(PlicpMinesAcceptance, KeyframeMatchesHardlyDependOnTheirGuess)
{
  // Measured with the default trimming (keep 95 %): the sum +0.21 % (standard error 0.21), each
  // pair 7.6 mm RMS apart (a few pairs, far apart and fast, converge elsewhere). A matcher that
  // returned its guess would read +6 %.
  const KeyframeLean lean = leanWithKeep(records_, PlicpOptions().trim_keep_fraction);
  EXPECT_GE(lean.pairs, 140);
  EXPECT_LT(std::abs(lean.percent), 0.3);
  EXPECT_LT(lean.rms_difference_mm, 12.0);
}

TEST_F(PlicpMinesAcceptance, KeepingEveryCorrespondenceMakesRealKeyframesDependOnTheirGuess)
{
  // Why the default keeps 95 %: on these real scans keeping 98 % or all of the correspondences
  // (only the adaptive threshold trims) moves each keyframe match with its guess 2-3 times as
  // much (18.7 and 26.6 mm RMS against 8.3), although in the simulated Mines-like corridors
  // keeping all removes a lean of the sums (issue 16, docs/scan_matching.md). Fails when that
  // stops being so, or when the option is not applied: then the default deserves another look.
  EXPECT_DOUBLE_EQ(PlicpOptions().trim_keep_fraction, 0.95);
  const KeyframeLean kept = leanWithKeep(records_, 0.95);
  leanWithKeep(records_, 0.98);
  const KeyframeLean all = leanWithKeep(records_, 1.0);
  EXPECT_GE(all.pairs, 140);
  EXPECT_GT(all.rms_difference_mm, 2.0 * kept.rms_difference_mm);
}

}  // namespace
}  // namespace odometry_calibration
