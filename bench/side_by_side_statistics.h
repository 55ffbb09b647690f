// Statistics of the side-by-side PLICP benchmark (bench/plicp_vs_csm_bench.cpp): medians, means
// and the paired bootstrap comparison of two matchers' errors. Header-only benchmark helper; not
// part of the library.
#pragma once

#include <algorithm>
#include <cstddef>
#include <limits>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include <benchmark/benchmark.h>

namespace odometry_calibration {
namespace bench_statistics {

inline double median(std::vector<double> values)
{
  if (values.empty())
    return std::numeric_limits<double>::quiet_NaN();
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

inline double mean(const std::vector<double>& values)
{
  double sum = 0.0;
  for (const double v : values)
    sum += v;
  return values.empty() ? std::numeric_limits<double>::quiet_NaN() : sum / values.size();
}

/// Whether the two medians of an error (translation [mm] or heading [deg], `unit`) differ by more
/// than chance: over the pairs both call valid, the difference of the medians (ours - CSM) with
/// a 95 % interval from 2000 paired bootstrap resamples (the same pairs drawn for both), and the
/// share of pairs where ours is nearer the truth [%]. An interval that holds 0 means the trials
/// cannot tell the two apart.
inline void pairedComparison(benchmark::State& state,
                             const std::vector<std::pair<double, double>>& errors,
                             const std::string& unit)
{
  const std::size_t n = errors.size();
  auto medianDifference = [&](const std::vector<std::size_t>& picks) {
    std::vector<double> ours, csm;
    for (const std::size_t k : picks) {
      ours.push_back(errors[k].first);
      csm.push_back(errors[k].second);
    }
    return median(ours) - median(csm);
  };
  std::vector<std::size_t> all(n);
  for (std::size_t k = 0; k < n; ++k)
    all[k] = k;
  std::mt19937 rng(17);
  std::uniform_int_distribution<std::size_t> pick(0, n - 1);
  std::vector<double> resampled;
  std::vector<std::size_t> picks(n);
  for (int b = 0; b < 2000; ++b) {
    for (std::size_t& k : picks)
      k = pick(rng);
    resampled.push_back(medianDifference(picks));
  }
  std::sort(resampled.begin(), resampled.end());
  std::size_t ours_nearer = 0;
  for (const auto& [ours, csm] : errors)
    ours_nearer += ours < csm ? 1 : 0;
  state.counters["median_diff_" + unit] = medianDifference(all);
  state.counters["median_diff_lo_" + unit] = resampled[50];
  state.counters["median_diff_hi_" + unit] = resampled[1949];
  state.counters["ours_nearer_pct_" + unit] = 100.0 * static_cast<double>(ours_nearer) / n;
}

}  // namespace bench_statistics
}  // namespace odometry_calibration
