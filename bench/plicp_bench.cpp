// Time of one PLICP match (both scans prepared, covariance included unless said otherwise):
// synthetic office-room scans of 180, 682 and 1081 rays, and every consecutive pair of the real
// Mines log. Both correspondence searches (angular order, PCL kd-tree) are measured. Each match
// is timed on its own; the counters give the median and mean per match [ms]. Run through
// scripts/bench or scripts/bench_plicp, which print tables.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <random>
#include <string>
#include <vector>

#include "odometry_calibration/scan/plicp.h"
#include "support/mines_log.h"
#include "support/synthetic_scans.h"

namespace {

using namespace odometry_calibration;

/// Times one call [ms].
template <typename Function>
double timeMs(Function&& function)
{
  const auto start = std::chrono::steady_clock::now();
  function();
  return std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - start)
      .count();
}

void reportPerMatch(benchmark::State& state, std::vector<double> times_ms)
{
  if (times_ms.empty()) {
    return;
  }
  double sum = 0.0;
  for (const double t : times_ms) {
    sum += t;
  }
  std::nth_element(times_ms.begin(), times_ms.begin() + times_ms.size() / 2, times_ms.end());
  state.counters["median_ms"] = times_ms[times_ms.size() / 2];
  state.counters["mean_ms"] = sum / static_cast<double>(times_ms.size());
}

PlicpOptions optionsFor(int search)
{
  PlicpOptions options;
  options.correspondence_search =
      search == 0 ? CorrespondenceSearch::kAngularOrder : CorrespondenceSearch::kKdTree;
  return options;
}

/// 64 office-room trials (1 cm noise, 240 deg, perturbed guess) with `rays` rays.
const std::vector<synthetic::Trial>& roomTrials(int rays)
{
  static std::vector<std::pair<int, std::vector<synthetic::Trial>>> cache;
  for (const auto& [count, trials] : cache) {
    if (count == rays) {
      return trials;
    }
  }
  synthetic::LidarModel lidar;
  lidar.ray_count = rays;
  std::mt19937 rng(7);
  std::vector<synthetic::Trial> trials;
  const synthetic::World world = synthetic::officeRoom();
  for (int k = 0; k < 64; ++k) {
    trials.push_back(synthetic::makeTrial(world, lidar, synthetic::TrialOptions(), rng));
  }
  cache.emplace_back(rays, std::move(trials));
  return cache.back().second;
}

/// Args: rays, search (0 angular, 1 kd-tree). One match per iteration, cycling over the trials.
void BM_MatchRoom(benchmark::State& state)
{
  const std::vector<synthetic::Trial>& trials = roomTrials(static_cast<int>(state.range(0)));
  const PlicpOptions options = optionsFor(static_cast<int>(state.range(1)));
  std::vector<double> times_ms;
  std::size_t k = 0;
  int valid = 0;
  for (auto _ : state) {
    const synthetic::Trial& trial = trials[k++ % trials.size()];
    PlicpResult result;
    times_ms.push_back(timeMs([&] {
      result = matchScans(trial.reference, trial.current, trial.guess_ref_new, options);
    }));
    valid += result.valid() ? 1 : 0;
    benchmark::DoNotOptimize(result);
  }
  reportPerMatch(state, times_ms);
  state.counters["valid_share"] = static_cast<double>(valid) / static_cast<double>(k);
}

const std::vector<mines::Record>& minesRecords()
{
  static const std::vector<mines::Record> records =
      mines::loadLog(mines::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR));
  return records;
}

/// Args: covariance (0/1), search (0 angular, 1 kd-tree). One consecutive pair per iteration,
/// cycling over the log, zero initial guess (the reference's setting).
void BM_MatchMinesPair(benchmark::State& state)
{
  const std::vector<mines::Record>& records = minesRecords();
  if (records.size() < 2) {
    state.SkipWithError("Mines log not found under ODOMETRY_CALIBRATION_SHARED_DATA_DIR");
    return;
  }
  PlicpOptions options = optionsFor(static_cast<int>(state.range(1)));
  options.compute_covariance = state.range(0) != 0;
  std::vector<double> times_ms;
  std::size_t k = 0;
  for (auto _ : state) {
    const std::size_t pair = k++ % (records.size() - 1);
    PlicpResult result;
    times_ms.push_back(timeMs([&] {
      result = matchScans(records[pair].scan, records[pair + 1].scan, Pose2(), options);
    }));
    benchmark::DoNotOptimize(result);
  }
  reportPerMatch(state, times_ms);
}

}  // namespace

BENCHMARK(BM_MatchRoom)
    ->ArgNames({"rays", "kdtree"})
    ->ArgsProduct({{180, 682, 1081}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(640);
BENCHMARK(BM_MatchMinesPair)
    ->ArgNames({"covariance", "kdtree"})
    ->Args({0, 0})
    ->Args({1, 0})
    ->Args({1, 1})
    ->Unit(benchmark::kMillisecond)
    ->Iterations(755);

BENCHMARK_MAIN();
