// Fit and prediction time of the GP motion model against the number of keyframe pairs (issue 12
// targets, three outputs, RBF + linear kernel, hyperparameters optimised: 10 000 pairs under
// 5 s and 50 000 under 20 s with the sparse GP, held-out RMSE within 2 % of the exact GP where
// both run). Pairs come from the simulator (differential drive, 0.3 s keyframes, 2 mm / 2 mrad
// noise); the "Distinct" variants add sub-tick jitter to the encoder counts so that no input
// repeats (the worst case for the duplicate merging). Counters: pairs, distinct inputs and the
// held-out RMSE per axis in units of the noise sigma. Run through scripts/bench.
#include <benchmark/benchmark.h>

#include <cmath>
#include <map>
#include <random>
#include <tuple>
#include <utility>

#include "odometry_calibration/gp/gp_inputs.h"
#include "odometry_calibration/gp/gp_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace {

using namespace odometry_calibration;

constexpr double kInterval = 0.3;
constexpr double kSigma = 0.002;

/// The first n pairs of a long simulated drive (cached: the simulator is not what is timed).
const sim::GeneratedPairs& trainingPairs(int n, bool distinct)
{
  static std::map<std::pair<int, bool>, sim::GeneratedPairs> cache;
  const auto key = std::make_pair(n, distinct);
  auto found = cache.find(key);
  if (found != cache.end()) {
    return found->second;
  }
  sim::PairGeneratorOptions options;
  options.interval_s = kInterval;
  options.duration_s = (n + 2) * kInterval;
  options.seed = 31;
  sim::GeneratedPairs data = sim::generatePairs(options);
  data.pairs.resize(static_cast<std::size_t>(n));
  data.true_motions.resize(static_cast<std::size_t>(n));
  if (distinct) {
    std::mt19937 rng(3);
    std::uniform_real_distribution<double> jitter(-0.5, 0.5);
    for (MotionPair& pair : data.pairs) {
      for (Eigen::Index j = 0; j < pair.encoder_samples.back().values.size(); ++j) {
        pair.encoder_samples.back().values(j) += jitter(rng);
      }
    }
  }
  return cache.emplace(key, std::move(data)).first->second;
}

const sim::GeneratedPairs& testPairs()
{
  static const sim::GeneratedPairs data = [] {
    sim::PairGeneratorOptions options;
    options.interval_s = kInterval;
    options.duration_s = 300.0;
    options.seed = 32;
    return sim::generatePairs(options);
  }();
  return data;
}

Eigen::Index distinctInputs(const sim::GeneratedPairs& data)
{
  Eigen::MatrixXd features(static_cast<Eigen::Index>(data.joints.names.size()),
                           static_cast<Eigen::Index>(data.pairs.size()));
  for (std::size_t i = 0; i < data.pairs.size(); ++i) {
    features.col(static_cast<Eigen::Index>(i)) =
        pairFeatures(data.pairs[i].encoder_samples, data.joints);
  }
  return groupDuplicateInputs(features).size();
}

GpOptions benchOptions(std::size_t max_exact_pairs)
{
  GpOptions options;
  options.kernel = GpKernelType::kRbfPlusLinear;
  options.mean = GpMeanFunction::kLinear;
  options.max_exact_pairs = max_exact_pairs;
  return options;
}

void fit(benchmark::State& state, std::size_t max_exact_pairs, bool distinct)
{
  const sim::GeneratedPairs& train = trainingPairs(static_cast<int>(state.range(0)), distinct);
  GaussianProcessModel model(benchOptions(max_exact_pairs), train.joints);
  ModelReport report;
  for (auto _ : state) {
    report = model.fit(train.pairs);
  }
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  const sim::GeneratedPairs& test = testPairs();
  for (const MotionPair& pair : test.pairs) {
    Eigen::Vector3d error =
        model.predict(pair.encoder_samples).mean.vector() - pair.sensor_motion.vector();
    error(2) = normalizeAngle(error(2));
    sum += error.cwiseAbs2();
  }
  const Eigen::Vector3d rmse = (sum / static_cast<double>(test.pairs.size())).cwiseSqrt() / kSigma;
  state.counters["pairs"] = static_cast<double>(train.pairs.size());
  state.counters["distinct"] = static_cast<double>(distinctInputs(train));
  state.counters["sparse"] = model.output(0).sparse ? 1.0 : 0.0;
  state.counters["outliers"] = static_cast<double>(report.outliers);
  state.counters["rmse_x"] = rmse(0);
  state.counters["rmse_y"] = rmse(1);
  state.counters["rmse_th"] = rmse(2);
}

// Issue 23: the same pairs with the encoder values as a JointState in radians (ticks * 2 pi /
// 4096) or in ticks (second argument 0): the fit must cost the same (duplicates merge alike).
void BM_GpFitUnits(benchmark::State& state)
{
  sim::GeneratedPairs train = trainingPairs(static_cast<int>(state.range(0)), false);
  if (state.range(1) != 0) {
    for (MotionPair& pair : train.pairs) {
      for (EncoderSample& sample : pair.encoder_samples)
        sample.values *= 2.0 * M_PI / 4096.0;
    }
  }
  GaussianProcessModel model(benchOptions(3000), train.joints);
  for (auto _ : state)
    benchmark::DoNotOptimize(model.fit(train.pairs));
  state.counters["inputs"] = static_cast<double>(model.output(0).posterior.basis().cols());
}

// Default regime: exact posterior up to 3000 distinct inputs, sparse above.
void BM_GpFit(benchmark::State& state)
{
  fit(state, 3000, false);
}
// Exact posterior at every size (where feasible).
void BM_GpFitExact(benchmark::State& state)
{
  fit(state, 1000000, false);
}
// Sparse posterior at every size (128 inducing inputs).
void BM_GpFitSparse(benchmark::State& state)
{
  fit(state, 0, false);
}
// No repeated inputs: nothing to merge.
void BM_GpFitDistinctExact(benchmark::State& state)
{
  fit(state, 1000000, true);
}
void BM_GpFitDistinctSparse(benchmark::State& state)
{
  fit(state, 0, true);
}

/// Prediction (mean and covariance) per pair.
void predict(benchmark::State& state, std::size_t max_exact_pairs, bool distinct = false)
{
  const sim::GeneratedPairs& train = trainingPairs(static_cast<int>(state.range(0)), distinct);
  GaussianProcessModel model(benchOptions(max_exact_pairs), train.joints);
  model.fit(train.pairs);
  const sim::GeneratedPairs& test = testPairs();
  std::size_t index = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.predict(test.pairs[index].encoder_samples));
    index = (index + 1) % test.pairs.size();
  }
  state.counters["distinct"] = static_cast<double>(distinctInputs(train));
  int projected = 0;
  for (int axis = 0; axis < 3; ++axis)
    projected += model.output(axis).posterior.projectedMean() ? 1 : 0;
  state.counters["projected_means"] = projected;
}

void BM_GpPredictExact(benchmark::State& state)
{
  predict(state, 1000000);
}
void BM_GpPredictSparse(benchmark::State& state)
{
  predict(state, 0);
}
// The same with the variance from the full Cholesky factor, O(n^2) (what predict() did before
// issue 23): three outputs' means and exact variances at inputs of the posterior.
void BM_GpPredictExactDistinctFullVariance(benchmark::State& state)
{
  const sim::GeneratedPairs& train = trainingPairs(static_cast<int>(state.range(0)), true);
  GaussianProcessModel model(benchOptions(1000000), train.joints);
  model.fit(train.pairs);
  const Eigen::MatrixXd& basis = model.output(0).posterior.basis();
  Eigen::Index index = 0;
  for (auto _ : state) {
    for (int axis = 0; axis < 3; ++axis) {
      const GpPosterior& posterior = model.output(axis).posterior;
      double mean = 0.0, variance = 0.0;
      posterior.predict(basis.col(index), &mean, &variance);
      benchmark::DoNotOptimize(mean);
      benchmark::DoNotOptimize(posterior.exactVariance(basis.col(index)));
    }
    index = (index + 1) % basis.cols();
  }
  state.counters["distinct"] = static_cast<double>(basis.cols());
}

// Issue 23: an exact posterior on ~3000 distinct inputs (no repeats): the mean O(n), the
// variance through the cached low-rank projection, O(M^2).
void BM_GpPredictExactDistinct(benchmark::State& state)
{
  predict(state, 1000000, true);
}

/// Training sets of issue 33's prediction benchmark (BM_GpPredictRobot's first argument).
enum class RobotSet
{
  kDiffDrive = 0,        ///< the default diff-drive pairs (2000-tick encoders)
  kMecanum = 1,          ///< mecanum pairs (four wheels, 1000-tick encoders)
  kCoarseDiffDrive = 2,  ///< diff-drive pairs from 360-tick encoders
};

/// The first n pairs of a long simulated drive of `set`'s robot (cached).
const sim::GeneratedPairs& robotPairs(RobotSet set, int n, unsigned seed)
{
  static std::map<std::tuple<int, int, unsigned>, sim::GeneratedPairs> cache;
  const auto key = std::make_tuple(static_cast<int>(set), n, seed);
  auto found = cache.find(key);
  if (found != cache.end())
    return found->second;
  sim::PairGeneratorOptions options;
  options.interval_s = kInterval;
  options.duration_s = (n + 2) * kInterval;
  options.seed = seed;
  if (set == RobotSet::kMecanum)
    options.robot.type = "mecanum";
  if (set == RobotSet::kCoarseDiffDrive)
    options.robot.parameters["encoder_ticks_per_rev"] = 360.0;
  sim::GeneratedPairs data = sim::generatePairs(options);
  data.pairs.resize(static_cast<std::size_t>(n));
  data.true_motions.resize(static_cast<std::size_t>(n));
  return cache.emplace(key, std::move(data)).first->second;
}

// Issue 33: prediction with covariance per pair, CPU time, on the default exact/sparse regime
// (benchOptions(3000)), for diff-drive, mecanum and 360-tick diff-drive training sets of
// `pairs` pairs (second argument; 300 pairs hold ~200 distinct inputs, the exact variance's
// size; 1300 mecanum pairs ~900 distinct inputs), predicted at the 600 pairs of another drive
// of the same robot.
void BM_GpPredictRobot(benchmark::State& state)
{
  const auto set = static_cast<RobotSet>(state.range(0));
  const sim::GeneratedPairs& train = robotPairs(set, static_cast<int>(state.range(1)), 31);
  GaussianProcessModel model(benchOptions(3000), train.joints);
  model.fit(train.pairs);
  const sim::GeneratedPairs& test = robotPairs(set, 600, 32);  // another drive
  std::size_t index = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(model.predict(test.pairs[index].encoder_samples));
    index = (index + 1) % test.pairs.size();
  }
  state.counters["distinct"] = static_cast<double>(distinctInputs(train));
  state.counters["sparse"] = model.output(0).sparse ? 1.0 : 0.0;
  int projected = 0;
  for (int axis = 0; axis < 3; ++axis)
    projected += model.output(axis).posterior.projectedMean() ? 1 : 0;
  state.counters["projected_means"] = projected;
}

}  // namespace

BENCHMARK(BM_GpPredictRobot)
    ->ArgNames({"robot", "pairs"})
    ->ArgsProduct({{0, 1, 2}, {300, 1300, 3000}})
    ->Unit(benchmark::kMicrosecond)
    ->MeasureProcessCPUTime();
BENCHMARK(BM_GpFit)->Arg(500)->Arg(2000)->Arg(2900)->Arg(10000)->Arg(50000)->Iterations(1)->Unit(
    benchmark::kMillisecond);
BENCHMARK(BM_GpFitExact)
    ->Arg(500)
    ->Arg(2000)
    ->Arg(10000)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GpFitSparse)
    ->Arg(500)
    ->Arg(2000)
    ->Arg(10000)
    ->Arg(50000)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GpFitUnits)
    ->ArgsProduct({{2000}, {0, 1}})
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GpFitDistinctExact)->Arg(500)->Arg(2000)->Iterations(1)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GpFitDistinctSparse)
    ->Arg(500)
    ->Arg(2000)
    ->Arg(10000)
    ->Arg(50000)
    ->Iterations(1)
    ->Unit(benchmark::kMillisecond);
BENCHMARK(BM_GpPredictExact)->Arg(2000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GpPredictSparse)->Arg(2000)->Arg(50000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GpPredictExactDistinct)->Arg(3000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_GpPredictExactDistinctFullVariance)->Arg(3000)->Unit(benchmark::kMicrosecond);

BENCHMARK_MAIN();
