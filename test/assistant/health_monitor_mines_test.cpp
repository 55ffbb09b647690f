// The health monitor (issue 18) on the real Mines rover log (../shared/data/mines, 74.6 s; skips
// without it): pairs collected as calibrate_bag does (config/mines.yaml), diff_drive fitted on
// the first half, the monitor's noise learnt on those pairs, then the second half scored, once
// unchanged and once with the right wheel's ticks scaled by 1.01 from the midpoint on (as if
// its radius had shrunk by 1 %). Measures the detection delay and the named cause
// (docs/live_assistant.md).
#include <cmath>
#include <cstdio>

#include <gtest/gtest.h>

#include "odometry_calibration/assistant/health_monitor.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "support/mines_log.h"

namespace odometry_calibration {
namespace {

/// The log's pairs with the right wheel's tick increments after `change_s` scaled.
std::vector<MotionPair> collectPairs(const CalibrationConfig& config,
                                     const std::vector<mines::Record>& records, double change_s,
                                     double right_scale)
{
  PairCollector collector(encoderChannels(config), config.collector, priorPredictor(config));
  std::vector<MotionPair> pairs;
  auto take = [&](const std::vector<CollectorEvent>& events) {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        pairs.push_back(event.pair);
    }
  };
  double right_at_change = std::nan("");
  for (const mines::Record& record : records) {
    double right = record.right_ticks;
    if (record.stamp_s >= change_s) {
      if (std::isnan(right_at_change))
        right_at_change = right;
      right = right_at_change + right_scale * (right - right_at_change);
    }
    Eigen::VectorXd accepted;
    take(collector.addEncoders(record.stamp_s, Eigen::Vector2d(record.left_ticks, right),
                               &accepted));
    take(collector.addScan(record.stamp_s, record.scan));
  }
  take(collector.flush());
  return pairs;
}

struct Outcome
{
  bool alarm = false;
  ChangeVerdict cause;   ///< at the alarm
  double delay_s = 0.0;  ///< after the midpoint
  std::string message;
  double statistic = 0.0;
  std::size_t scored = 0;
};

Outcome monitorSecondHalf(const CalibrationConfig& config, const std::vector<MotionPair>& pairs,
                          double midpoint_s)
{
  std::vector<MotionPair> first, second;
  for (const MotionPair& pair : pairs)
    (pair.end_stamp_s <= midpoint_s ? first : second).push_back(pair);
  auto model = std::shared_ptr<MotionModel>(makeModel("diff_drive", config.models));
  const ModelReport report = model->fit(first);
  EXPECT_TRUE(report.converged) << report.termination;
  HealthMonitorOptions options;
  options.burn_in_pairs = 20;  // a 37 s half has only ~70 pairs
  HealthMonitor monitor(model, options);
  for (const MotionPair& pair : first)
    monitor.addPair(pair);  // learns the noise (in-sample: the fit's own pairs)
  Outcome outcome;
  const std::size_t before = monitor.status().pairs;
  for (const MotionPair& pair : second) {
    if (monitor.addPair(pair)) {
      outcome.alarm = true;
      outcome.delay_s = pair.end_stamp_s - midpoint_s;
      break;
    }
  }
  const HealthStatus status = monitor.status();
  outcome.message = status.message;
  outcome.cause = status.cause;
  outcome.statistic = status.statistic;
  outcome.scored = status.pairs - before;
  return outcome;
}

TEST(HealthMonitorMines, InjectedRightWheelChangeIsDetectedAndTheUnchangedLogIsQuiet)
{
  const auto records = mines::loadLog(mines::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR));
  if (records.empty())
    GTEST_SKIP() << "Mines log not found under " << ODOMETRY_CALIBRATION_SHARED_DATA_DIR;
  CalibrationConfig config =
      loadCalibrationConfig(std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/mines.yaml");
  const double midpoint_s = 0.5 * (records.front().stamp_s + records.back().stamp_s);

  const Outcome unchanged =
      monitorSecondHalf(config, collectPairs(config, records, midpoint_s, 1.0), midpoint_s);
  std::printf("Mines, unchanged: %s; %zu pairs scored after the midpoint\n",
              unchanged.message.c_str(), unchanged.scored);
  EXPECT_FALSE(unchanged.alarm) << unchanged.message;
  EXPECT_GT(unchanged.scored, 40u);

  // With the sweep compensated by the encoders' motion over each sweep (the default), the
  // scans themselves carry part of a tick change, and within the 37 s half only a 5 % change
  // raises the alarm; with compensate_sweep off the laser is independent of the encoders and
  // 3 % is found (docs/live_assistant.md: an open finding; 2 % was, before pairs lasted T within
  // half a scan period: statistic 0.49 now). 1 % was found too, after 20 s,
  // while each chart's centre was a median of its first 20 in-sample values; the self-starting
  // centre (issue 34: a centre fixed from 20 values is off by 0.28 sigma, a drift towards false
  // alarms) leaves it at a statistic of 0.54 by the log's end.
  for (const double scale : {1.01, 1.05}) {
    const Outcome changed =
        monitorSecondHalf(config, collectPairs(config, records, midpoint_s, scale), midpoint_s);
    std::printf("Mines, right wheel ticks x%.2f after %.1f s: alarm %s after %.1f s: %s\n", scale,
                midpoint_s - records.front().stamp_s, changed.alarm ? "raised" : "NOT raised",
                changed.delay_s, changed.message.c_str());
    if (scale > 1.02) {
      EXPECT_TRUE(changed.alarm) << changed.message;
      // A wheel's ticks: never named a mounting change (which radius is not asserted: the
      // along-track residual that tells left from right is weak on this log).
      EXPECT_FALSE(changed.cause.kind_told && changed.cause.kind == ChangeKind::kMounting)
          << changed.message;
    }
  }
  CalibrationConfig uncompensated = config;
  uncompensated.collector.compensate_sweep = false;
  for (const double scale : {1.01, 1.02, 1.03, 1.05}) {
    const Outcome independent = monitorSecondHalf(
        uncompensated, collectPairs(uncompensated, records, midpoint_s, scale), midpoint_s);
    std::printf(
        "Mines, sweep not compensated, right wheel ticks x%.2f: alarm %s after %.1f s: %s\n", scale,
        independent.alarm ? "raised" : "NOT raised", independent.delay_s,
        independent.message.c_str());
    if (scale > 1.025) {
      EXPECT_TRUE(independent.alarm) << independent.message;
      EXPECT_LT(independent.delay_s, 30.0);
      EXPECT_FALSE(independent.cause.kind_told && independent.cause.kind == ChangeKind::kMounting)
          << independent.message;
    }
  }
}

}  // namespace
}  // namespace odometry_calibration
