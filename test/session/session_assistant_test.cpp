// The session's live assistant wording the health monitor (issue 34): the alarm logged once,
// and once more only when later pairs tell what changed; /diagnostics naming the cause; several
// ego-motion sources watched, each named (issue 35).
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/session/session_assistant.h"
#include "support/health_change_run.h"

namespace odometry_calibration {
namespace {

TEST(SessionAssistant, LogsTheAlarmAndItsCauseAndNamesItOnDiagnostics)
{
  health_runs::RunOptions run;
  run.change = health_runs::Change::kSeparation;
  run.seed = 12;
  const sim::GeneratedPairs data = sim::generatePairs(health_runs::pairOptions(run));
  SessionAssistantOptions options;
  options.guidance = false;
  std::vector<std::string> warnings;
  SessionAssistant assistant(options, CalibrationConfig(), "", "",
                             [&](SessionLogLevel level, const std::string& text) {
                               if (level == SessionLogLevel::kWarn)
                                 warnings.push_back(text);
                             });
  assistant.watch(health_runs::fitBefore(data.pairs, run.fit_at_s), "fit of the first 124 s");
  ASSERT_TRUE(assistant.watching());
  for (const MotionPair& pair : data.pairs) {
    if (pair.start_stamp_s < run.fit_at_s || pair.end_stamp_s > run.change_at_s + 60.0)
      continue;
    assistant.addPair(pair);
    if (pair.end_stamp_s < run.change_at_s) {
      ASSERT_TRUE(warnings.empty()) << warnings.front();
    }
  }
  ASSERT_GE(warnings.size(), 1u);
  EXPECT_LE(warnings.size(), 2u);  // the alarm; its cause once told, if not told with it
  EXPECT_NE(warnings.back().find("calibration health: "), std::string::npos);
  EXPECT_NE(warnings.back().find("the wheel separation"), std::string::npos) << warnings.back();
  std::vector<SessionStatusReport> statuses;
  assistant.addStatuses(&statuses);
  ASSERT_EQ(statuses.size(), 1u);
  EXPECT_EQ(statuses[0].level, SessionStatusReport::Level::kWarn);
  EXPECT_NE(statuses[0].message.find("a wheel change, the wheel separation"), std::string::npos)
      << statuses[0].message;
  EXPECT_GE(assistant.healthStatistic(), 1.0);
}

TEST(SessionAssistant, WatchesEverySourceNamedByItsFrameOrTopic)
{
  // Two sources (issue 35): the front laser with its frame, the rear one by its topic.
  CalibrationConfig config;
  config.ego_motion_sources.resize(2);
  config.ego_motion_sources[0].topic = "/scan_front";
  config.ego_motion_sources[0].frame = "laser_front";
  config.ego_motion_sources[1].topic = "/scan_rear";
  SessionAssistantOptions options;
  options.guidance = false;
  SessionAssistant assistant(options, config, "", "", nullptr);
  auto model = [](const Pose2& pose) {
    DiffDriveOptions diff;
    diff.initial_T_base_sensor = pose;
    return std::shared_ptr<const MotionModel>(std::make_shared<DiffDriveModel>(diff));
  };
  const auto front = model(Pose2(0.3, 0.0, 0.0)), rear = model(Pose2(-0.3, 0.0, M_PI));
  EXPECT_THROW(assistant.watch({front, rear, rear}, "three"), std::invalid_argument);
  assistant.watch({front, rear}, "joint fit");
  ASSERT_TRUE(assistant.watching());
  MotionPair pair;  // an arc: left wheel 1000 ticks, right 1400
  for (int i = 0; i <= 10; ++i)
    pair.encoder_samples.push_back({0.05 * i, Eigen::Vector2d(100.0 * i, 140.0 * i)});
  pair.covariance = Eigen::Matrix3d::Identity() * 1e-4;
  assistant.addPair(pair, 1);
  assistant.addPair(pair, 1);
  std::vector<SessionStatusReport> statuses;
  assistant.addStatuses(&statuses);
  ASSERT_EQ(statuses.size(), 1u);
  std::map<std::string, std::string> values(statuses[0].values.begin(), statuses[0].values.end());
  EXPECT_EQ(values.count("chart laser_front travel (x)"), 1u);
  ASSERT_EQ(values.count("chart /scan_rear travel (x)"), 1u);
  EXPECT_EQ(values["chart /scan_rear travel (x)"], "learning the noise (2 pairs)");
  EXPECT_EQ(values["chart laser_front travel (x)"], "learning the noise (0 pairs)");
  EXPECT_EQ(values["pairs scored"], "2");
}

}  // namespace
}  // namespace odometry_calibration
