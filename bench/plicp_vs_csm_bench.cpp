// Our PLICP and the reference implementation (Censi's CSM, sm_icp) side by side, in one process,
// on the same scans with the same first guesses (issue 16): synthetic office rooms of 180, 682
// and 1081 rays and a sparse corridor scene (with the true motion), the real Mines log's
// consecutive and 0.5 s keyframe pairs (agreement, path length), and every real CARMEN log of
// ../shared/data/carmen against its SLAM-corrected poses (errors, silent gross failures, the
// good pairs ours refuses and which check refused them; two seeds of the guesses). Each data
// set is matched in several passes a whole set apart, the two matchers interleaved pair by pair
// (alternating which goes first); a pair's time is its fastest pass. Both sides convert the scans
// themselves inside the timed call (ours: Scan -> prepared points and line fits; CSM: Scan ->
// laser_data, then its own preprocessing). Options: each matcher's defaults, covariance on for both
// (as a calibrator uses them; a second row per set with covariance off for both; on the CARMEN
// logs also ours with the line fits' surface breaks of before issue 33, gap_rule 0, and ours with
// the ambiguity check's rematches run to convergence, covariance 3). BM_CovarianceCostCarmen times
// ours alone with the covariance off and on, interleaved, for the on/off ratio. Logs kept aside
// from tuning run with the same protocol through CARMEN_LOGS (registerCarmenLogs). Run
// scripts/bench_plicp_vs_csm for the table.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/plicp_ambiguity.h"
#include "odometry_calibration/scan/plicp_match.h"
#include "support/carmen_log.h"
#include "support/mines_log.h"
#include "support/synthetic_scans.h"

#include "ambiguity_check_passes.h"
#include "csm_matcher.h"
#include "side_by_side_statistics.h"

namespace {

using namespace odometry_calibration;
using ambiguity_passes::CheckPasses;
using ambiguity_passes::gatherWideningEvidence;
using ambiguity_passes::rematchPasses;
using ambiguity_passes::WideningEvidence;
using bench_statistics::mean;
using bench_statistics::median;
using bench_statistics::pairedComparison;

constexpr int kPasses = 3;

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

Outcome matchWithCsm(const MatchCase& pair, bool covariance)
{
  const csm_reference::CsmOutcome outcome =
      csm_reference::matchWithCsm(pair.reference, pair.current, pair.guess_ref_new, covariance);
  return {outcome.valid, outcome.valid ? PlicpStatus::kValid : PlicpStatus::kNoConvergence,
          outcome.T_ref_new, outcome.covariance};
}

/// The default of PlicpOptions::ambiguity_return_sigma (rematches stop once back at the solution).
const double kReturnSigma = PlicpOptions().ambiguity_return_sigma;
/// The default of PlicpOptions::ambiguity_offset_rad (the check's turned starts).
const double kOffsetRad = PlicpOptions().ambiguity_offset_rad;

/// Ours with its defaults, covariance as asked; `check_ambiguity` false turns off the ambiguity
/// check of weak matches (which needs the covariance) to show what it costs; `gap_rule` false
/// sets line_fit.max_gap_range_m to 0, the surface breaks of before issue 33 (every gap beyond
/// max_gap_m, whatever the ray spacing); `return_sigma` 0 lets every rematch of the check run to
/// convergence, as before issue 33's early stop; `offset_rad` 0 drops the check's turned starts.
Outcome matchWithOurs(const MatchCase& pair, bool covariance, bool check_ambiguity = true,
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

/// A silent gross failure when called valid: more than 10 cm or 5 deg from the truth.
bool grossError(const Pose2& error)
{
  return std::hypot(error.x(), error.y()) > 0.10 || std::abs(error.theta()) > 5.0 * M_PI / 180.0;
}

/// Both matchers' outcomes on every case (ours first).
using Outcomes = std::pair<std::vector<Outcome>, std::vector<Outcome>>;

/// Times both matchers on every case (fastest of kPasses interleaved passes per case) and puts
/// speed, validity and accuracy (against the truth, or between the two) into the counters.
Outcomes runSideBySide(benchmark::State& state, const std::vector<MatchCase>& cases,
                       bool covariance, bool check_ambiguity = true, bool gap_rule = true,
                       double return_sigma = kReturnSigma, double offset_rad = kOffsetRad)
{
  if (cases.empty()) {
    state.SkipWithError(
        "no data (the Mines and CARMEN logs are read from ODOMETRY_CALIBRATION_SHARED_DATA_DIR)");
    return {};
  }
  sm_debug_write(0);
  const std::size_t n = cases.size();
  std::vector<double> ours_ms(n, std::numeric_limits<double>::infinity()), csm_ms = ours_ms;
  std::vector<Outcome> ours(n), csm(n);
  for (auto _ : state) {
    for (int pass = 0; pass < kPasses; ++pass) {
      for (std::size_t k = 0; k < n; ++k) {
        auto timeOurs = [&] {
          const auto start = std::chrono::steady_clock::now();
          ours[k] = matchWithOurs(cases[k], covariance, check_ambiguity, gap_rule, return_sigma,
                                  offset_rad);
          const std::chrono::duration<double, std::milli> took =
              std::chrono::steady_clock::now() - start;
          ours_ms[k] = std::min(ours_ms[k], took.count());
        };
        auto timeCsm = [&] {
          const auto start = std::chrono::steady_clock::now();
          csm[k] = matchWithCsm(cases[k], covariance);
          const std::chrono::duration<double, std::milli> took =
              std::chrono::steady_clock::now() - start;
          csm_ms[k] = std::min(csm_ms[k], took.count());
        };
        if ((k + pass) % 2 == 0) {
          timeOurs();
          timeCsm();
        } else {
          timeCsm();
          timeOurs();
        }
      }
    }
  }
  state.counters["pairs"] = static_cast<double>(n);
  state.counters["ours_median_ms"] = median(ours_ms);
  state.counters["csm_median_ms"] = median(csm_ms);
  state.counters["ratio_median"] = median(csm_ms) / median(ours_ms);
  state.counters["ours_mean_ms"] = mean(ours_ms);
  state.counters["csm_mean_ms"] = mean(csm_ms);
  state.counters["ratio_mean"] = mean(csm_ms) / mean(ours_ms);
  std::vector<double> ours_err_mm, csm_err_mm, ours_err_deg, csm_err_deg, gap_mm;
  // (ours, CSM) where both are valid
  std::vector<std::pair<double, double>> both_err_mm, both_err_deg;
  double ours_path_m = 0.0, csm_path_m = 0.0;
  int ours_valid = 0, csm_valid = 0, ours_wild = 0, ours_gross = 0, csm_gross = 0;
  const auto gross = grossError;
  for (std::size_t k = 0; k < n; ++k) {
    ours_valid += ours[k].valid ? 1 : 0;
    csm_valid += csm[k].valid ? 1 : 0;
    if (cases[k].has_truth) {
      const Pose2 ours_error = between(cases[k].truth_ref_new, ours[k].T_ref_new);
      const Pose2 csm_error = between(cases[k].truth_ref_new, csm[k].T_ref_new);
      ours_gross += ours[k].valid && gross(ours_error) ? 1 : 0;
      csm_gross += csm[k].valid && gross(csm_error) ? 1 : 0;
      if (ours[k].valid) {
        ours_err_mm.push_back(1e3 * std::hypot(ours_error.x(), ours_error.y()));
        ours_err_deg.push_back(std::abs(ours_error.theta()) * 180.0 / M_PI);
        // Off by more than 5 sigma along the weakest direction of its own covariance.
        if (covariance) {
          const Eigen::Vector3d e(
              ours[k].T_ref_new.x() - cases[k].truth_ref_new.x(),
              ours[k].T_ref_new.y() - cases[k].truth_ref_new.y(),
              normalizeAngle(ours[k].T_ref_new.theta() - cases[k].truth_ref_new.theta()));
          const double nees = e.dot(ours[k].covariance.ldlt().solve(e));
          ours_wild += nees > 25.0 ? 1 : 0;
        }
      }
      if (csm[k].valid) {
        csm_err_mm.push_back(1e3 * std::hypot(csm_error.x(), csm_error.y()));
        csm_err_deg.push_back(std::abs(csm_error.theta()) * 180.0 / M_PI);
      }
      if (ours[k].valid && csm[k].valid) {
        both_err_mm.emplace_back(1e3 * std::hypot(ours_error.x(), ours_error.y()),
                                 1e3 * std::hypot(csm_error.x(), csm_error.y()));
        both_err_deg.emplace_back(std::abs(ours_error.theta()) * 180.0 / M_PI,
                                  std::abs(csm_error.theta()) * 180.0 / M_PI);
      }
    } else if (ours[k].valid && csm[k].valid) {
      const Pose2 gap = between(csm[k].T_ref_new, ours[k].T_ref_new);
      gap_mm.push_back(1e3 * std::hypot(gap.x(), gap.y()));
      ours_path_m += std::hypot(ours[k].T_ref_new.x(), ours[k].T_ref_new.y());
      csm_path_m += std::hypot(csm[k].T_ref_new.x(), csm[k].T_ref_new.y());
    }
  }
  state.counters["ours_valid"] = ours_valid;
  state.counters["csm_valid"] = csm_valid;
  if (!ours_err_mm.empty() || !csm_err_mm.empty()) {
    state.counters["ours_err_median_mm"] = median(ours_err_mm);
    state.counters["csm_err_median_mm"] = median(csm_err_mm);
    state.counters["ours_err_median_deg"] = median(ours_err_deg);
    state.counters["csm_err_median_deg"] = median(csm_err_deg);
    if (covariance)
      state.counters["ours_valid_beyond_5sigma"] = ours_wild;
    state.counters["ours_gross"] = ours_gross;
    state.counters["csm_gross"] = csm_gross;
  }
  if (!both_err_mm.empty()) {
    // Medians over the pairs both call valid.
    std::vector<double> ours_mm, csm_mm, ours_deg, csm_deg;
    for (std::size_t k = 0; k < both_err_mm.size(); ++k) {
      ours_mm.push_back(both_err_mm[k].first);
      csm_mm.push_back(both_err_mm[k].second);
      ours_deg.push_back(both_err_deg[k].first);
      csm_deg.push_back(both_err_deg[k].second);
    }
    state.counters["both_valid"] = static_cast<double>(both_err_mm.size());
    state.counters["both_ours_median_mm"] = median(ours_mm);
    state.counters["both_csm_median_mm"] = median(csm_mm);
    state.counters["both_ours_median_deg"] = median(ours_deg);
    state.counters["both_csm_median_deg"] = median(csm_deg);
  }
  if (both_err_mm.size() >= 20) {
    pairedComparison(state, both_err_mm, "mm");
    pairedComparison(state, both_err_deg, "deg");
  }
  if (!gap_mm.empty()) {
    state.counters["median_gap_mm"] = median(gap_mm);
    // Sum of the matched distances, ours over CSM's, on the pairs both call valid [%].
    state.counters["path_ours_vs_csm_pct"] = 100.0 * (ours_path_m / csm_path_m - 1.0);
  }
  return {ours, csm};
}

/// Synthetic trials with the truth (1 cm range noise, 240 deg field of view, guess off by
/// 2-5 cm and 1-3 deg, as in the PLICP tests).
std::vector<MatchCase> syntheticCases(const synthetic::World& world, int rays, double range_max_m,
                                      int count)
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

const std::vector<mines::Record>& minesRecords()
{
  static const std::vector<mines::Record> records =
      mines::loadLog(mines::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR));
  return records;
}

/// The Mines log's pairs `step` scans apart (1: consecutive, zero guess as CSM's users
/// commonly run it; 5: 0.5 s keyframes, guessed from the nominal wheel odometry). Sweep
/// compensation off on both sides (CSM has none), so the two see the same points.
std::vector<MatchCase> minesCases(std::size_t step)
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
std::vector<MatchCase> carmenCasesAt(const std::string& path, unsigned seed)
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

/// Which check refused a pair ours does not call valid: its status ("degenerate", "poor overlap",
/// "no convergence", ...), or "ambiguity" when the same match without the ambiguity check is valid
/// (the check found a clearly better degenerate fit and made the match degenerate).
std::string refusingCheck(const MatchCase& pair, const Outcome& ours)
{
  if (ours.status == PlicpStatus::kDegenerate && matchWithOurs(pair, true, false).valid)
    return "ambiguity";
  return toString(ours.status);
}

/// The pairs on which CSM's answer is good (valid, within 10 cm / 5 deg of the SLAM pose) and ours
/// refuses, and which check refused each (counters refused_good, csm_good, "refused_by:<check>").
void countRefusedGood(benchmark::State& state, const std::vector<MatchCase>& cases,
                      const Outcomes& outcomes)
{
  const auto& [ours, csm] = outcomes;
  int csm_good = 0, refused_good = 0;
  std::map<std::string, int> by_check;
  for (std::size_t k = 0; k < cases.size() && k < ours.size(); ++k) {
    if (!csm[k].valid || grossError(between(cases[k].truth_ref_new, csm[k].T_ref_new)))
      continue;
    ++csm_good;
    if (ours[k].valid)
      continue;
    ++refused_good;
    ++by_check[refusingCheck(cases[k], ours[k])];
  }
  state.counters["csm_good"] = csm_good;
  state.counters["refused_good"] = refused_good;
  for (const auto& [check, count] : by_check)
    state.counters["refused_by:" + check] = count;
}

/// The pairs of one CARMEN log with one seed, read once and shared by the rows that use them.
std::shared_ptr<const std::vector<MatchCase>> carmenCases(const std::string& path, unsigned seed)
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

bool sameOutcome(const Outcome& a, const Outcome& b)
{
  return a.valid == b.valid && a.T_ref_new.vector() == b.T_ref_new.vector() &&
         a.covariance == b.covariance;
}

/// What the ambiguity check does to our matches (untimed, defaults with covariance on): how many
/// valid matches it widens (covariance other than without the check), with the early stop of its
/// rematches (now) and with every rematch run to convergence (before), and how many matches of
/// the two differ at all (validity, pose or covariance).
void countWidened(benchmark::State& state, const std::vector<MatchCase>& cases,
                  double offset_rad = kOffsetRad)
{
  int widened_now = 0, widened_before = 0, differ = 0;
  for (const MatchCase& pair : cases) {
    const Outcome unchecked = matchWithOurs(pair, true, false);
    const Outcome now = matchWithOurs(pair, true, true, true, kReturnSigma, offset_rad);
    const Outcome before = matchWithOurs(pair, true, true, true, 0.0, offset_rad);
    widened_now += now.valid && unchecked.valid && now.covariance != unchecked.covariance ? 1 : 0;
    widened_before +=
        before.valid && unchecked.valid && before.covariance != unchecked.covariance ? 1 : 0;
    differ += sameOutcome(now, before) ? 0 : 1;
  }
  state.counters["ours_widened"] = widened_now;
  state.counters["ours_widened_before"] = widened_before;
  state.counters["ours_differ_from_before"] = differ;
}

/// One CARMEN log with one seed's guesses. covariance 2: covariance on, our ambiguity check off
/// (CSM as with covariance 1); covariance 3: on, every rematch of our check run to convergence
/// (ambiguity_return_sigma 0, before its early stop); covariance 4: on, the check without its
/// turned starts (ambiguity_offset_rad 0); gap_rule 0: our line fits' surface breaks
/// as before issue 33 (line_fit.max_gap_range_m 0). The rows with our defaults and covariance on,
/// and those of covariance 4, also count the refused good pairs and which check refused them, and
/// the widened matches.
void sideBySideCarmen(benchmark::State& state, const std::string& path, unsigned seed,
                      int covariance, bool gap_rule)
{
  const auto cases = carmenCases(path, seed);
  if (cases->empty()) {
    state.SkipWithError(("cannot read FLASER pairs from " + path).c_str());
    return;
  }
  const double offset_rad = covariance == 4 ? 0.0 : kOffsetRad;
  const Outcomes outcomes = runSideBySide(state, *cases, covariance != 0, covariance != 2, gap_rule,
                                          covariance == 3 ? 0.0 : kReturnSigma, offset_rad);
  if ((covariance == 1 || covariance == 4) && gap_rule) {
    countRefusedGood(state, *cases, outcomes);
    countWidened(state, *cases, offset_rad);
  }
}

/// Counts the check's passes on every pair of `cases` (ours, defaults, covariance on).
CheckPasses countCheckPasses(const std::vector<MatchCase>& cases, WideningEvidence& evidence)
{
  CheckPasses counts;
  const PlicpOptions now;
  PlicpOptions before;
  before.ambiguity_return_sigma = 0.0;
  for (const MatchCase& pair : cases) {
    const PreparedScan reference = prepareScan(pair.reference, now.line_fit);
    const PreparedScan current = prepareScan(pair.current, now.line_fit);
    std::unique_ptr<NearestPointSearch> search;
    const PlicpResult best = matchOnce(reference, current, pair.guess_ref_new, now, search);
    if (!needsAmbiguityCheck(best, now))
      continue;
    ++counts.checked;
    counts.match += best.iterations + 1;
    int unused = 0;
    counts.rematches_now += rematchPasses(reference, current, best, now, unused, counts.stopped);
    counts.rematches_before +=
        rematchPasses(reference, current, best, before, counts.rematches_beyond_3_sigma, unused);
    gatherWideningEvidence(reference, current, best, before, evidence);
  }
  return counts;
}

/// The widening evidence as counters: checked matches widened, of those by one start alone; the
/// widening rematches' passes (median, maximum, and how many take more than the median stopped
/// rematch's 4) and how many passed within 1 and 1.5 sigma of the solution after a small step;
/// the median weakest sigma of the widened and of the other checked matches [mm].
void recordWideningEvidence(benchmark::State& state, const WideningEvidence& evidence)
{
  state.counters["widened_checks"] = evidence.widened;
  state.counters["widened_by_one_start"] = evidence.widened_by_one_start;
  std::vector<double> passes(evidence.passes.begin(), evidence.passes.end());
  state.counters["widening_rematches"] = static_cast<double>(passes.size());
  state.counters["widening_passes_median"] = passes.empty() ? 0.0 : median(passes);
  state.counters["widening_passes_max"] =
      passes.empty() ? 0.0 : *std::max_element(passes.begin(), passes.end());
  state.counters["widening_over_4_passes"] = static_cast<double>(
      std::count_if(passes.begin(), passes.end(), [](double p) { return p > 4.0; }));
  state.counters["widening_within_1_sigma"] = evidence.within_1_sigma;
  state.counters["widening_within_1_5_sigma"] = evidence.within_1_5_sigma;
  if (!evidence.sigma_widened_m.empty())
    state.counters["sigma_widened_median_mm"] = 1e3 * median(evidence.sigma_widened_m);
  if (!evidence.sigma_kept_m.empty())
    state.counters["sigma_kept_median_mm"] = 1e3 * median(evidence.sigma_kept_m);
}

/// What the covariance costs us (issue 33), ours alone, four variants timed pair by pair in one
/// process, their order rotating from pair to pair and pass to pass (fastest of kCostPasses per
/// pair and variant): covariance off, on (defaults), on with every rematch of the ambiguity check
/// run to convergence (ambiguity_return_sigma 0, before its early stop), and on without the
/// check. Counters: the medians [ms] and the on/off ratios of the medians; untimed, the check's
/// work per checked match in correspondence passes (countCheckPasses).
void covarianceCostCarmen(benchmark::State& state, const std::string& path)
{
  constexpr int kCostPasses = 5;
  const std::vector<MatchCase>& cases = *carmenCases(path, kCarmenSeed);
  if (cases.empty()) {
    state.SkipWithError(("cannot read FLASER pairs from " + path).c_str());
    return;
  }
  const auto variant = [](const MatchCase& pair, int which) {
    switch (which) {
      case 0:
        return matchWithOurs(pair, false);
      case 1:
        return matchWithOurs(pair, true);
      case 2:
        return matchWithOurs(pair, true, true, true, 0.0);
      default:
        return matchWithOurs(pair, true, false);
    }
  };
  constexpr int kVariants = 4;
  std::vector<std::vector<double>> ms(
      kVariants, std::vector<double>(cases.size(), std::numeric_limits<double>::infinity()));
  for (auto _ : state) {
    for (int pass = 0; pass < kCostPasses; ++pass) {
      for (std::size_t k = 0; k < cases.size(); ++k) {
        for (int v = 0; v < kVariants; ++v) {
          const int which = static_cast<int>((k + pass + v) % kVariants);
          const auto start = std::chrono::steady_clock::now();
          benchmark::DoNotOptimize(variant(cases[k], which));
          const std::chrono::duration<double, std::milli> took =
              std::chrono::steady_clock::now() - start;
          ms[which][k] = std::min(ms[which][k], took.count());
        }
      }
    }
  }
  const double off = median(ms[0]);
  state.counters["pairs"] = static_cast<double>(cases.size());
  state.counters["off_median_ms"] = off;
  state.counters["on_median_ms"] = median(ms[1]);
  state.counters["on_before_median_ms"] = median(ms[2]);
  state.counters["on_no_check_median_ms"] = median(ms[3]);
  state.counters["ratio_on_off"] = median(ms[1]) / off;
  state.counters["ratio_on_before_off"] = median(ms[2]) / off;
  state.counters["ratio_on_no_check_off"] = median(ms[3]) / off;
  WideningEvidence evidence;
  const CheckPasses passes = countCheckPasses(cases, evidence);
  recordWideningEvidence(state, evidence);
  const double checked = std::max(passes.checked, 1);
  state.counters["checked"] = passes.checked;
  state.counters["match_passes"] = passes.match / checked;
  state.counters["rematch_passes"] = passes.rematches_now / checked;
  state.counters["rematch_passes_before"] = passes.rematches_before / checked;
  state.counters["rematch_passes_beyond_3_sigma"] = passes.rematches_beyond_3_sigma / checked;
  state.counters["rematches_stopped_pct"] = 100.0 * passes.stopped / (4.0 * checked);
}

void BM_SideBySideRoom(benchmark::State& state)
{
  static const std::vector<MatchCase> cases180 =
      syntheticCases(synthetic::officeRoom(), 180, 20.0, 1000);
  static const std::vector<MatchCase> cases682 =
      syntheticCases(synthetic::officeRoom(), 682, 20.0, 1000);
  static const std::vector<MatchCase> cases1081 =
      syntheticCases(synthetic::officeRoom(), 1081, 20.0, 1000);
  const int rays = static_cast<int>(state.range(0));
  runSideBySide(state,
                rays == 180   ? cases180
                : rays == 682 ? cases682
                              : cases1081,
                state.range(1) != 0);
}

void BM_SideBySideSparseCorridor(benchmark::State& state)
{
  // A 2 m corridor seen to 5.6 m (the URG-04LX's range): the along-axis motion is barely
  // constrained; a matcher should say so rather than report a confident wrong value.
  static const std::vector<MatchCase> cases = syntheticCases(synthetic::corridor(), 682, 5.6, 200);
  runSideBySide(state, cases, state.range(0) != 0);
}

void BM_SideBySideMines(benchmark::State& state)
{
  static const std::vector<MatchCase> consecutive = minesCases(1);
  static const std::vector<MatchCase> keyframes = minesCases(5);
  runSideBySide(state, state.range(0) == 1 ? consecutive : keyframes, state.range(1) != 0);
}

}  // namespace

BENCHMARK(BM_SideBySideRoom)
    ->ArgNames({"rays", "covariance"})
    ->ArgsProduct({{180, 682, 1081}, {1, 0}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SideBySideSparseCorridor)
    ->ArgNames({"covariance"})
    ->Arg(1)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_SideBySideMines)
    ->ArgNames({"step", "covariance"})
    ->ArgsProduct({{1, 5}, {1, 0}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);

/// Every CARMEN log in the shared data folder (../shared/data/carmen: every *.log.gz and *.log)
/// and those CARMEN_LOGS=path[:path...] adds (corrected CARMEN logs, gzip'ed or plain, e.g. logs
/// kept aside from tuning): rows BM_SideBySideCarmen/<log>/seed:S/covariance:C/gap_rule:G with our
/// defaults and covariance on for the fixed seed and the second, and for the fixed seed also
/// covariance off, on without our ambiguity check (2), on with its rematches run to convergence
/// (3), and ours with the surface breaks of before issue 33 (gap_rule 0); for both seeds on with
/// the check's shifted starts only (4, ambiguity_offset_rad 0); and
/// BM_CovarianceCostCarmen/<log>. scripts/bench_plicp_vs_csm prints the table and the acceptance.
void registerCarmenLogs()
{
  std::vector<std::string> paths =
      carmen::logsIn(std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/carmen");
  if (const char* list = std::getenv("CARMEN_LOGS")) {
    std::stringstream extra(list);
    std::string path;
    while (std::getline(extra, path, ':')) {
      if (!path.empty() && std::find(paths.begin(), paths.end(), path) == paths.end())
        paths.push_back(path);
    }
  }
  struct Row
  {
    unsigned seed;
    int covariance;
    bool gap_rule;
  };
  const Row rows[] = {{kCarmenSeed, 1, true}, {kCarmenSecondSeed, 1, true}, {kCarmenSeed, 0, true},
                      {kCarmenSeed, 2, true}, {kCarmenSeed, 3, true},       {kCarmenSeed, 1, false},
                      {kCarmenSeed, 4, true}, {kCarmenSecondSeed, 4, true}};
  for (const std::string& path : paths) {
    const std::string log = carmen::logName(path);
    for (const Row& row : rows) {
      const std::string name = "BM_SideBySideCarmen/" + log + "/seed:" + std::to_string(row.seed) +
                               "/covariance:" + std::to_string(row.covariance) +
                               "/gap_rule:" + std::to_string(row.gap_rule ? 1 : 0);
      benchmark::RegisterBenchmark(name.c_str(),
                                   [path, row](benchmark::State& state) {
                                     sideBySideCarmen(state, path, row.seed, row.covariance,
                                                      row.gap_rule);
                                   })
          ->Iterations(1)
          ->Unit(benchmark::kMillisecond);
    }
    benchmark::RegisterBenchmark(
        ("BM_CovarianceCostCarmen/" + log).c_str(),
        [path](benchmark::State& state) { covarianceCostCarmen(state, path); })
        ->Iterations(1)
        ->Unit(benchmark::kMillisecond);
  }
}

int main(int argc, char** argv)
{
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv))
    return 1;
  registerCarmenLogs();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
