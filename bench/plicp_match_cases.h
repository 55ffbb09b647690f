// The pairs the PLICP benchmarks of bench/plicp_vs_csm_bench.cpp match, and our matcher run on
// them with one set of options: a pair (scans, first guess, truth), what a matcher returned, our
// matcher with its defaults and the variants the rows compare, and the data sets' pairs
// (synthetic trials, the Mines log, the real CARMEN logs with the seeded guesses of the protocol,
// read once and shared by every row of a log).
// Header-only benchmark helper; not part of the library.
#pragma once

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/scan.h"
#include "support/carmen_log.h"
#include "support/mines_log.h"
#include "support/synthetic_scans.h"

namespace odometry_calibration {
namespace plicp_bench {

/// One pair to match: two scans, the first guess, and the truth when there is one.
struct MatchCase
{
  Scan reference;
  Scan current;
  Pose2 guess_ref_new;
  bool has_truth = false;
  Pose2 truth_ref_new;
};

/// What one matcher returned for one pair.
struct Outcome
{
  bool valid = false;
  /// Ours: the matcher's status (CSM: valid or not, as kValid / kNoConvergence).
  PlicpStatus status = PlicpStatus::kNoConvergence;
  Pose2 T_ref_new;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// The default of PlicpOptions::ambiguity_return_sigma (rematches stop once back at the solution).
inline const double kReturnSigma = PlicpOptions().ambiguity_return_sigma;
/// The default of PlicpOptions::ambiguity_offset_rad (the check's turned starts).
inline const double kOffsetRad = PlicpOptions().ambiguity_offset_rad;

/// Ours with its defaults, covariance as asked; `check_ambiguity` false turns off the ambiguity
/// check of weak matches (which needs the covariance) to show what it costs; `gap_rule` false
/// sets line_fit.max_gap_range_m to 0, the older surface breaks (every gap beyond max_gap_m,
/// whatever the ray spacing); `return_sigma` 0 lets every rematch of the check run to
/// convergence (no early stop); `offset_rad` 0 drops the check's turned starts.
inline Outcome matchWithOurs(const MatchCase& pair, bool covariance, bool check_ambiguity = true,
                             bool gap_rule = true, double return_sigma = kReturnSigma,
                             double offset_rad = kOffsetRad)
{
  PlicpOptions options;
  options.ambiguity_offset_rad = offset_rad;
  options.compute_covariance = covariance;
  options.check_ambiguity = check_ambiguity;
  options.ambiguity_return_sigma = return_sigma;
  if (!gap_rule)
    options.line_fit.max_gap_range_m = 0.0;
  const PlicpResult result = matchScans(pair.reference, pair.current, pair.guess_ref_new, options);
  return {result.valid(), result.status, result.T_ref_new, result.covariance};
}

/// Synthetic trials with the truth (1 cm range noise, 240 deg field of view, guess off by
/// 2-5 cm and 1-3 deg, as in the PLICP tests).
inline std::vector<MatchCase> syntheticCases(const synthetic::World& world, int rays,
                                             double range_max_m, int count)
{
  synthetic::LidarModel lidar;
  lidar.ray_count = rays;
  lidar.range_max_m = range_max_m;
  std::mt19937 rng(11);
  std::vector<MatchCase> cases;
  for (int k = 0; k < count; ++k) {
    const synthetic::Trial trial =
        synthetic::makeTrial(world, lidar, synthetic::TrialOptions(), rng);
    cases.push_back({trial.reference, trial.current, trial.guess_ref_new, true, trial.T_ref_new});
  }
  return cases;
}

inline const std::vector<mines::Record>& minesRecords()
{
  static const std::vector<mines::Record> records =
      mines::loadLog(mines::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR));
  return records;
}

/// The Mines log's pairs `step` scans apart (1: consecutive, zero guess as CSM's users
/// commonly run it; 5: 0.5 s keyframes, guessed from the nominal wheel odometry). Sweep
/// compensation off on both sides (CSM has none), so the two see the same points.
inline std::vector<MatchCase> minesCases(std::size_t step)
{
  const std::vector<mines::Record>& records = minesRecords();
  std::vector<MatchCase> cases;
  for (std::size_t k = 0; k + step < records.size(); k += step) {
    MatchCase pair{records[k].scan, records[k + step].scan, Pose2(), false, Pose2()};
    pair.reference.time_increment_s = 0.0;
    pair.current.time_increment_s = 0.0;
    if (step > 1)
      pair.guess_ref_new = mines::laserMotion(mines::wheelOdometry(records[k], records[k + step]));
    cases.push_back(pair);
  }
  return cases;
}

/// Up to 600 consecutive FLASER pairs of the CARMEN log at `path`, scored against the relative
/// corrected pose; the first guess is that reference moved by 5 cm in a random direction and
/// turned by 3 deg either way (random sign, drawn with `seed`). The same guesses for both sides.
/// Empty when the log cannot be read.
inline std::vector<MatchCase> carmenCasesAt(const std::string& path, unsigned seed)
{
  const std::vector<carmen::Record> records = carmen::loadLog(path);
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> direction(-M_PI, M_PI);
  std::bernoulli_distribution sign(0.5);
  std::vector<MatchCase> cases;
  for (std::size_t k = 0; k + 1 < records.size() && cases.size() < 600; ++k) {
    const Pose2 truth = between(records[k].T_map_robot, records[k + 1].T_map_robot);
    const double bearing = direction(rng);
    const double turn_rad = (sign(rng) ? 3.0 : -3.0) * M_PI / 180.0;
    const Pose2 guess(truth.x() + 0.05 * std::cos(bearing), truth.y() + 0.05 * std::sin(bearing),
                      truth.theta() + turn_rad);
    cases.push_back({records[k].scan, records[k + 1].scan, guess, true, truth});
  }
  return cases;
}

/// The pairs of one CARMEN log with one seed, read once and shared by the rows that use them.
inline std::shared_ptr<const std::vector<MatchCase>> carmenCases(const std::string& path,
                                                                 unsigned seed)
{
  static std::map<std::pair<std::string, unsigned>, std::shared_ptr<const std::vector<MatchCase>>>
      cache;
  auto& cases = cache[{path, seed}];
  if (!cases)
    cases = std::make_shared<const std::vector<MatchCase>>(carmenCasesAt(path, seed));
  return cases;
}

/// The seeds of the CARMEN guesses: the fixed one of every table, and a second.
constexpr unsigned kCarmenSeed = 33;
constexpr unsigned kCarmenSecondSeed = 7;

}  // namespace plicp_bench
}  // namespace odometry_calibration
