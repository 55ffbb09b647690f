// What the covariance costs our PLICP on a real CARMEN log, ours alone (the rows
// BM_CovarianceCostCarmen/<log> of bench/plicp_vs_csm_bench.cpp, the last three tables of
// scripts/bench_plicp_vs_csm): four variants timed pair by pair, and, untimed, the ambiguity
// check's work in correspondence passes and what its widening rematches look like
// (ambiguity_check_passes.h). Header-only benchmark helper; not part of the library.
#pragma once

#include <algorithm>
#include <chrono>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/plicp_ambiguity.h"
#include "odometry_calibration/scan/plicp_match.h"

#include "ambiguity_check_passes.h"
#include "plicp_match_cases.h"
#include "side_by_side_statistics.h"

namespace odometry_calibration {
namespace covariance_cost {

/// Counts the check's passes on every pair of `cases` (ours, defaults, covariance on).
inline ambiguity_passes::CheckPasses countCheckPasses(
    const std::vector<plicp_bench::MatchCase>& cases, ambiguity_passes::WideningEvidence& evidence)
{
  ambiguity_passes::CheckPasses counts;
  const PlicpOptions now;
  PlicpOptions before;
  before.ambiguity_return_sigma = 0.0;
  for (const plicp_bench::MatchCase& pair : cases) {
    const PreparedScan reference = prepareScan(pair.reference, now.line_fit);
    const PreparedScan current = prepareScan(pair.current, now.line_fit);
    std::unique_ptr<NearestPointSearch> search;
    const PlicpResult best = matchOnce(reference, current, pair.guess_ref_new, now, search);
    if (!needsAmbiguityCheck(best, now))
      continue;
    ++counts.checked;
    counts.match += best.iterations + 1;
    int unused = 0;
    counts.rematches_now +=
        ambiguity_passes::rematchPasses(reference, current, best, now, unused, counts.stopped);
    counts.rematches_before += ambiguity_passes::rematchPasses(
        reference, current, best, before, counts.rematches_beyond_3_sigma, unused);
    ambiguity_passes::gatherWideningEvidence(reference, current, best, before, evidence);
  }
  return counts;
}

/// The widening evidence as counters: checked matches widened, of those by one start alone; the
/// widening rematches' passes (median, maximum, and how many take more than the median stopped
/// rematch's 4) and how many passed within 1 and 1.5 sigma of the solution after a small step;
/// the median weakest sigma of the widened and of the other checked matches [mm].
inline void recordWideningEvidence(benchmark::State& state,
                                   const ambiguity_passes::WideningEvidence& evidence)
{
  using bench_statistics::median;
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

/// The check's work per checked match in correspondence passes, as counters: the checked
/// matches, the passes of the match itself, of its four rematches with the early stop, run to
/// convergence, and of those ending beyond 3 sigma; the share of rematches stopped early [%].
inline void recordCheckPasses(benchmark::State& state, const ambiguity_passes::CheckPasses& passes)
{
  const double checked = std::max(passes.checked, 1);
  state.counters["checked"] = passes.checked;
  state.counters["match_passes"] = passes.match / checked;
  state.counters["rematch_passes"] = passes.rematches_now / checked;
  state.counters["rematch_passes_before"] = passes.rematches_before / checked;
  state.counters["rematch_passes_beyond_3_sigma"] = passes.rematches_beyond_3_sigma / checked;
  state.counters["rematches_stopped_pct"] = 100.0 * passes.stopped / (4.0 * checked);
}

/// Ours in variant `which`: 0 covariance off, 1 on (defaults), 2 on with every rematch of the
/// ambiguity check run to convergence (ambiguity_return_sigma 0), 3 on without the check.
inline plicp_bench::Outcome matchVariant(const plicp_bench::MatchCase& pair, int which)
{
  switch (which) {
    case 0:
      return plicp_bench::matchWithOurs(pair, false);
    case 1:
      return plicp_bench::matchWithOurs(pair, true);
    case 2:
      return plicp_bench::matchWithOurs(pair, true, true, true, 0.0);
    default:
      return plicp_bench::matchWithOurs(pair, true, false);
  }
}

/// The fastest time [ms] of each variant (matchVariant) on each pair of `cases`, over
/// `passes` passes in one process, the variants' order rotating from pair to pair and pass to
/// pass: [variant][pair].
inline std::vector<std::vector<double>> timeVariants(
    benchmark::State& state, const std::vector<plicp_bench::MatchCase>& cases, int passes)
{
  constexpr int kVariants = 4;
  std::vector<std::vector<double>> ms(
      kVariants, std::vector<double>(cases.size(), std::numeric_limits<double>::infinity()));
  for (auto _ : state) {
    for (int pass = 0; pass < passes; ++pass) {
      for (std::size_t k = 0; k < cases.size(); ++k) {
        for (int v = 0; v < kVariants; ++v) {
          const int which = static_cast<int>((k + pass + v) % kVariants);
          const auto start = std::chrono::steady_clock::now();
          benchmark::DoNotOptimize(matchVariant(cases[k], which));
          const std::chrono::duration<double, std::milli> took =
              std::chrono::steady_clock::now() - start;
          ms[which][k] = std::min(ms[which][k], took.count());
        }
      }
    }
  }
  return ms;
}

/// What the covariance costs us, ours alone on the CARMEN log at `path` (the fixed seed's
/// guesses), the four variants of matchVariant timed pair by pair (fastest of 5 passes per pair
/// and variant, timeVariants). Counters: the medians [ms] and the on/off ratios of the medians;
/// untimed, the check's work per checked match in correspondence passes (countCheckPasses) and
/// the widening evidence.
inline void covarianceCostCarmen(benchmark::State& state, const std::string& path)
{
  using bench_statistics::median;
  constexpr int kCostPasses = 5;
  const std::vector<plicp_bench::MatchCase>& cases =
      *plicp_bench::carmenCases(path, plicp_bench::kCarmenSeed);
  if (cases.empty()) {
    state.SkipWithError(("cannot read FLASER pairs from " + path).c_str());
    return;
  }
  const std::vector<std::vector<double>> ms = timeVariants(state, cases, kCostPasses);
  const double off = median(ms[0]);
  state.counters["pairs"] = static_cast<double>(cases.size());
  state.counters["off_median_ms"] = off;
  state.counters["on_median_ms"] = median(ms[1]);
  state.counters["on_before_median_ms"] = median(ms[2]);
  state.counters["on_no_check_median_ms"] = median(ms[3]);
  state.counters["ratio_on_off"] = median(ms[1]) / off;
  state.counters["ratio_on_before_off"] = median(ms[2]) / off;
  state.counters["ratio_on_no_check_off"] = median(ms[3]) / off;
  ambiguity_passes::WideningEvidence evidence;
  const ambiguity_passes::CheckPasses passes = countCheckPasses(cases, evidence);
  recordWideningEvidence(state, evidence);
  recordCheckPasses(state, passes);
}

}  // namespace covariance_cost
}  // namespace odometry_calibration
