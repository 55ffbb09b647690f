// The session's live assistant wording the health monitor (issue 34): the alarm logged once,
// and once more only when later pairs tell what changed; /diagnostics naming the cause.
#include <string>
#include <vector>

#include <gtest/gtest.h>

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

}  // namespace
}  // namespace odometry_calibration
