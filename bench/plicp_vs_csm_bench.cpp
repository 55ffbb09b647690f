// Our PLICP and the reference implementation (Censi's CSM, sm_icp) side by side, in one process,
// on the same scans with the same first guesses: synthetic office rooms of 180, 682 and 1081 rays
// and a sparse corridor scene (with the true motion), the real Mines log's consecutive and 0.5 s
// keyframe pairs (agreement, path length), and every real CARMEN log of ../shared/data/carmen
// against its SLAM-corrected poses (errors, silent gross failures, the good pairs ours refuses and
// which check refused them; two seeds of the guesses). Each data set is matched in several passes
// a whole set apart, the two matchers interleaved pair by pair (alternating which goes first); a
// pair's time is its fastest pass. Both sides convert the scans themselves inside the timed call
// (ours: Scan -> prepared points and line fits; CSM: Scan -> laser_data, then its own
// preprocessing). Options: each matcher's defaults, covariance on for both (as a calibrator uses
// them; a second row per set with covariance off for both; on the CARMEN logs also ours with the
// line fits' older surface breaks, gap_rule 0, and ours with the ambiguity check's rematches run
// to convergence, covariance 3). BM_CovarianceCostCarmen (plicp_covariance_cost.h) times ours
// alone with the covariance off and on, interleaved, for the on/off ratio. Logs kept aside from
// tuning run with the same protocol through CARMEN_LOGS (registerCarmenLogs). Run
// scripts/bench_plicp_vs_csm for the table.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdlib>
#include <limits>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "odometry_calibration/scan/plicp.h"
#include "support/carmen_log.h"
#include "support/synthetic_scans.h"

#include "csm_matcher.h"
#include "plicp_covariance_cost.h"
#include "plicp_match_cases.h"
#include "side_by_side_statistics.h"

namespace {

using namespace odometry_calibration;
using bench_statistics::mean;
using bench_statistics::median;
using bench_statistics::pairedComparison;
using plicp_bench::carmenCases;
using plicp_bench::kCarmenSecondSeed;
using plicp_bench::kCarmenSeed;
using plicp_bench::kOffsetRad;
using plicp_bench::kReturnSigma;
using plicp_bench::MatchCase;
using plicp_bench::matchWithOurs;
using plicp_bench::minesCases;
using plicp_bench::Outcome;
using plicp_bench::syntheticCases;

constexpr int kPasses = 3;

Outcome matchWithCsm(const MatchCase& pair, bool covariance)
{
  const csm_reference::CsmOutcome outcome =
      csm_reference::matchWithCsm(pair.reference, pair.current, pair.guess_ref_new, covariance);
  return {outcome.valid, outcome.valid ? PlicpStatus::kValid : PlicpStatus::kNoConvergence,
          outcome.T_ref_new, outcome.covariance};
}

/// A silent gross failure when called valid: more than 10 cm or 5 deg from the truth.
bool grossError(const Pose2& error)
{
  return std::hypot(error.x(), error.y()) > 0.10 || std::abs(error.theta()) > 5.0 * M_PI / 180.0;
}

/// Both matchers' outcomes on every case (ours first).
using Outcomes = std::pair<std::vector<Outcome>, std::vector<Outcome>>;

/// Times both matchers on every case (fastest of kPasses interleaved passes per case, the order
/// of the two alternating) and puts the medians and means of the times [ms] and their ratios
/// (CSM / ours) into the counters. Ours with the options of matchWithOurs.
Outcomes timeSideBySide(benchmark::State& state, const std::vector<MatchCase>& cases,
                        bool covariance, bool check_ambiguity, bool gap_rule, double return_sigma,
                        double offset_rad)
{
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
  return {ours, csm};
}

/// The errors against the truth of both matchers' valid matches, over the cases with a truth.
struct TruthErrors
{
  std::vector<double> ours_mm, csm_mm, ours_deg, csm_deg;
  /// (ours, CSM) where both are valid.
  std::vector<std::pair<double, double>> both_mm, both_deg;
  /// Ours valid but more than 5 sigma off along the weakest direction of its own covariance.
  int ours_wild = 0;
  /// Valid silent gross failures (grossError).
  int ours_gross = 0, csm_gross = 0;
};

/// Translation [mm] and heading [deg] error of `T_ref_new` against `truth_ref_new`.
std::pair<double, double> errorMmDeg(const Pose2& truth_ref_new, const Pose2& T_ref_new)
{
  const Pose2 error = between(truth_ref_new, T_ref_new);
  return {1e3 * std::hypot(error.x(), error.y()), std::abs(error.theta()) * 180.0 / M_PI};
}

/// Whether ours is off the truth by more than 5 sigma of its covariance (NEES = e' C^-1 e > 25).
bool beyond5Sigma(const MatchCase& pair, const Outcome& ours)
{
  const Eigen::Vector3d e(ours.T_ref_new.x() - pair.truth_ref_new.x(),
                          ours.T_ref_new.y() - pair.truth_ref_new.y(),
                          normalizeAngle(ours.T_ref_new.theta() - pair.truth_ref_new.theta()));
  return e.dot(ours.covariance.ldlt().solve(e)) > 25.0;
}

/// Gathers both matchers' errors over the cases with a truth (the 5 sigma count when `covariance`).
TruthErrors truthErrors(const std::vector<MatchCase>& cases, const Outcomes& outcomes,
                        bool covariance)
{
  const auto& [ours, csm] = outcomes;
  TruthErrors errors;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    if (!cases[k].has_truth)
      continue;
    const Pose2& truth = cases[k].truth_ref_new;
    errors.ours_gross += ours[k].valid && grossError(between(truth, ours[k].T_ref_new)) ? 1 : 0;
    errors.csm_gross += csm[k].valid && grossError(between(truth, csm[k].T_ref_new)) ? 1 : 0;
    const auto [ours_mm, ours_deg] = errorMmDeg(truth, ours[k].T_ref_new);
    const auto [csm_mm, csm_deg] = errorMmDeg(truth, csm[k].T_ref_new);
    if (ours[k].valid) {
      errors.ours_mm.push_back(ours_mm);
      errors.ours_deg.push_back(ours_deg);
      if (covariance)
        errors.ours_wild += beyond5Sigma(cases[k], ours[k]) ? 1 : 0;
    }
    if (csm[k].valid) {
      errors.csm_mm.push_back(csm_mm);
      errors.csm_deg.push_back(csm_deg);
    }
    if (ours[k].valid && csm[k].valid) {
      errors.both_mm.emplace_back(ours_mm, csm_mm);
      errors.both_deg.emplace_back(ours_deg, csm_deg);
    }
  }
  return errors;
}

/// The errors against the truth as counters: medians of each matcher's valid matches, silent gross
/// failures, ours beyond 5 sigma (with `covariance`), the medians over the pairs both call valid
/// and, from 20 such pairs, the paired comparison of the two (pairedComparison).
void recordTruthErrors(benchmark::State& state, const TruthErrors& errors, bool covariance)
{
  if (!errors.ours_mm.empty() || !errors.csm_mm.empty()) {
    state.counters["ours_err_median_mm"] = median(errors.ours_mm);
    state.counters["csm_err_median_mm"] = median(errors.csm_mm);
    state.counters["ours_err_median_deg"] = median(errors.ours_deg);
    state.counters["csm_err_median_deg"] = median(errors.csm_deg);
    if (covariance)
      state.counters["ours_valid_beyond_5sigma"] = errors.ours_wild;
    state.counters["ours_gross"] = errors.ours_gross;
    state.counters["csm_gross"] = errors.csm_gross;
  }
  if (!errors.both_mm.empty()) {
    // Medians over the pairs both call valid.
    std::vector<double> ours_mm, csm_mm, ours_deg, csm_deg;
    for (std::size_t k = 0; k < errors.both_mm.size(); ++k) {
      ours_mm.push_back(errors.both_mm[k].first);
      csm_mm.push_back(errors.both_mm[k].second);
      ours_deg.push_back(errors.both_deg[k].first);
      csm_deg.push_back(errors.both_deg[k].second);
    }
    state.counters["both_valid"] = static_cast<double>(errors.both_mm.size());
    state.counters["both_ours_median_mm"] = median(ours_mm);
    state.counters["both_csm_median_mm"] = median(csm_mm);
    state.counters["both_ours_median_deg"] = median(ours_deg);
    state.counters["both_csm_median_deg"] = median(csm_deg);
  }
  if (errors.both_mm.size() >= 20) {
    pairedComparison(state, errors.both_mm, "mm");
    pairedComparison(state, errors.both_deg, "deg");
  }
}

/// Where there is no truth, the agreement of the two on the pairs both call valid, as counters:
/// the median gap between their poses [mm] and the sum of the matched distances, ours over CSM's
/// [%].
void recordAgreement(benchmark::State& state, const std::vector<MatchCase>& cases,
                     const Outcomes& outcomes)
{
  const auto& [ours, csm] = outcomes;
  std::vector<double> gap_mm;
  double ours_path_m = 0.0, csm_path_m = 0.0;
  for (std::size_t k = 0; k < cases.size(); ++k) {
    if (cases[k].has_truth || !ours[k].valid || !csm[k].valid)
      continue;
    const Pose2 gap = between(csm[k].T_ref_new, ours[k].T_ref_new);
    gap_mm.push_back(1e3 * std::hypot(gap.x(), gap.y()));
    ours_path_m += std::hypot(ours[k].T_ref_new.x(), ours[k].T_ref_new.y());
    csm_path_m += std::hypot(csm[k].T_ref_new.x(), csm[k].T_ref_new.y());
  }
  if (!gap_mm.empty()) {
    state.counters["median_gap_mm"] = median(gap_mm);
    state.counters["path_ours_vs_csm_pct"] = 100.0 * (ours_path_m / csm_path_m - 1.0);
  }
}

/// Times both matchers on every case (timeSideBySide) and puts speed, validity and accuracy
/// (against the truth, or between the two) into the counters.
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
  const Outcomes outcomes =
      timeSideBySide(state, cases, covariance, check_ambiguity, gap_rule, return_sigma, offset_rad);
  const auto& [ours, csm] = outcomes;
  state.counters["ours_valid"] = static_cast<double>(
      std::count_if(ours.begin(), ours.end(), [](const Outcome& o) { return o.valid; }));
  state.counters["csm_valid"] = static_cast<double>(
      std::count_if(csm.begin(), csm.end(), [](const Outcome& o) { return o.valid; }));
  recordTruthErrors(state, truthErrors(cases, outcomes, covariance), covariance);
  recordAgreement(state, cases, outcomes);
  return outcomes;
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
/// (ambiguity_return_sigma 0, no early stop); covariance 4: on, the check without its turned
/// starts (ambiguity_offset_rad 0); gap_rule 0: our line fits' older surface breaks
/// (line_fit.max_gap_range_m 0). The rows with our defaults and covariance on,
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
/// (3), and ours with the older surface breaks (gap_rule 0); for both seeds on with the check's
/// shifted starts only (4, ambiguity_offset_rad 0); and BM_CovarianceCostCarmen/<log>
/// (plicp_covariance_cost.h). scripts/bench_plicp_vs_csm prints the table and the acceptance.
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
        [path](benchmark::State& state) { covariance_cost::covarianceCostCarmen(state, path); })
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
