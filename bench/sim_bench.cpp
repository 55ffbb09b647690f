// Simulator throughput: the 60-minute, 10 Hz, 720-ray scenario written as a bag (target:
// under 60 s), and the cost of one simulated scan. Run through scripts/bench.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdio>
#include <string>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/world.h"

namespace {

using namespace odometry_calibration;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

void BM_Simulate60MinuteBag(benchmark::State& state)
{
  const sim::Scenario scenario = sim::loadScenarioYaml(
      kConfig + "/sim/scenarios/benchmark_60min.yaml", kConfig + "/sim/worlds");
  const std::string bag =
      "/tmp/odometry_calibration_bench_60min." + std::to_string(::getpid()) + ".bag";
  sim::SimulationSummary summary;
  for (auto _ : state) {
    summary = simulateToBag(scenario, bag, "");
  }
  std::FILE* file = std::fopen(bag.c_str(), "rb");
  if (file) {
    std::fseek(file, 0, SEEK_END);
    state.counters["bag_MB"] = static_cast<double>(std::ftell(file)) / 1e6;
    std::fclose(file);
  }
  std::remove(bag.c_str());
  state.counters["scans"] = static_cast<double>(summary.scans);
  state.counters["x_realtime"] =
      benchmark::Counter(scenario.duration_s, benchmark::Counter::kIsIterationInvariantRate);
}

void BM_RayCast720RayScanInOffice(benchmark::State& state)
{
  const sim::World world = sim::loadWorldYaml(kConfig + "/sim/worlds/office.yaml");
  const double fov = 4.71238898;
  for (auto _ : state) {
    double sum = 0.0;
    for (int i = 0; i < 720; ++i) {
      sum += world.castRay(Eigen::Vector2d(0.3, -0.2), -0.5 * fov + i * fov / 719, 20.0);
    }
    benchmark::DoNotOptimize(sum);
  }
}

}  // namespace

BENCHMARK(BM_Simulate60MinuteBag)->Iterations(1)->Unit(benchmark::kSecond);
BENCHMARK(BM_RayCast720RayScanInOffice)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
