// Time of the whole tricycle fit on the real dataset (target: under 1 s), and of its parts.
// Run through scripts/bench, which prints a table.
#include <benchmark/benchmark.h>

#include <fstream>
#include <string>

#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace {

using namespace odometry_calibration;

const std::string kDatasetPath =
    std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/tricycle/dataset.txt";

Eigen::Matrix3d defaultCovariance()
{
  const TricycleCalibrationOptions options;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  covariance.diagonal() << options.translation_sigma_m * options.translation_sigma_m,
      options.translation_sigma_m * options.translation_sigma_m,
      options.rotation_sigma_rad * options.rotation_sigma_rad;
  return covariance;
}

void BM_ParseDataset(benchmark::State& state)
{
  for (auto _ : state) {
    benchmark::DoNotOptimize(loadTricycleDataset(kDatasetPath));
  }
}

void BM_FitTricycle(benchmark::State& state)
{
  const TricycleDataset dataset = loadTricycleDataset(kDatasetPath);
  const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
  const TricycleParameters nominal = tricycleNominalFromHeader(dataset.header);
  const auto samples = decodeTricycleEncoders(dataset, layout);
  const double interval_s = static_cast<double>(state.range(0)) / 1000.0;
  const auto pairs = tricyclePairs(dataset, samples, interval_s, defaultCovariance());
  for (auto _ : state) {
    benchmark::DoNotOptimize(calibrateTricycle(pairs, layout, nominal, {}));
  }
  state.counters["pairs"] = static_cast<double>(pairs.size());
}

// Everything the command does: parse, decode, pair, fit (covariance included).
void BM_EndToEnd(benchmark::State& state)
{
  for (auto _ : state) {
    const TricycleDataset dataset = loadTricycleDataset(kDatasetPath);
    const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
    const auto samples = decodeTricycleEncoders(dataset, layout);
    const auto pairs = tricyclePairs(dataset, samples, 0.5, defaultCovariance());
    benchmark::DoNotOptimize(
        calibrateTricycle(pairs, layout, tricycleNominalFromHeader(dataset.header), {}));
  }
}

}  // namespace

BENCHMARK(BM_ParseDataset)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_FitTricycle)->Arg(100)->Arg(500)->Arg(1000)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EndToEnd)->Unit(benchmark::kMillisecond);

int main(int argc, char** argv)
{
  if (!std::ifstream(kDatasetPath)) {
    std::fprintf(stderr, "dataset not found: %s (the benchmark reads ../shared/data)\n",
                 kDatasetPath.c_str());
    return 1;
  }
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
