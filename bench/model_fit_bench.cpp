// Fit and prediction time of the parametric and linear models against the number of pairs
// (the GP's are in gp_bench.cpp). Pairs: 3000 simulated 0.3 s pairs, repeated to larger sizes
// (the cost depends on the count, not on the values). Run through scripts/bench.
#include <benchmark/benchmark.h>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/linear_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace {

using namespace odometry_calibration;

const sim::GeneratedPairs& basePairs()
{
  static const sim::GeneratedPairs pairs = [] {
    sim::PairGeneratorOptions options;
    options.robot = {"diff_drive", {{"wheel_radius_left_m", 0.0765}}};
    options.duration_s = 900.0;
    options.interval_s = 0.3;
    return sim::generatePairs(options);
  }();
  return pairs;
}

std::vector<MotionPair> pairsOfSize(std::size_t n)
{
  const auto& base = basePairs().pairs;
  std::vector<MotionPair> pairs;
  pairs.reserve(n);
  for (std::size_t i = 0; i < n; ++i)
    pairs.push_back(base[i % base.size()]);
  return pairs;
}

DiffDriveOptions nominal()
{
  DiffDriveOptions options;
  options.initial_left_radius_m = options.initial_right_radius_m = 0.077;
  options.initial_separation_m = 0.33;
  options.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  return options;
}

// Second argument: the global starts (yaw_starts; 1 = the single start of before issue 23).
void BM_DiffDriveFit(benchmark::State& state)
{
  const auto pairs = pairsOfSize(static_cast<std::size_t>(state.range(0)));
  DiffDriveOptions options = nominal();
  options.yaw_starts = static_cast<int>(state.range(1));
  for (auto _ : state) {
    DiffDriveModel model(options);
    benchmark::DoNotOptimize(model.fit(pairs));
  }
}

void BM_LinearFit(benchmark::State& state)
{
  const auto pairs = pairsOfSize(static_cast<std::size_t>(state.range(0)));
  for (auto _ : state) {
    LinearModel model({basePairs().joints});
    benchmark::DoNotOptimize(model.fit(pairs));
  }
}

void BM_DiffDrivePredict(benchmark::State& state)
{
  DiffDriveModel model(nominal());
  model.fit(pairsOfSize(2000));
  const auto& samples = basePairs().pairs[7].encoder_samples;
  for (auto _ : state)
    benchmark::DoNotOptimize(model.predict(samples));
}

void BM_LinearPredict(benchmark::State& state)
{
  LinearModel model({basePairs().joints});
  model.fit(pairsOfSize(2000));
  const auto& samples = basePairs().pairs[7].encoder_samples;
  for (auto _ : state)
    benchmark::DoNotOptimize(model.predict(samples));
}

}  // namespace

BENCHMARK(BM_DiffDriveFit)
    ->ArgsProduct({{500, 2000, 10000, 50000}, {1, 8}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_LinearFit)->Arg(500)->Arg(2000)->Arg(10000)->Arg(50000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_DiffDrivePredict)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_LinearPredict)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
