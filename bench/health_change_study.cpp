// The health monitor against mid-run changes (issue 34): a study printing a table, not a timing
// benchmark. For each seed: a 600 s random drive of a simulated differential drive (pairs every
// 0.5 s with 2 mm / 1.5 mrad of noise, no scans), diff_drive fitted on the first 124 s, one
// change at 300 s (right wheel radius +2 %, wheel separation +3 %, laser yaw +1.5 deg, laser x
// +3 cm) or none (the unchanged twin, same seed, all 476 s after the fit monitored), and the
// monitor on every pair after the fit (test/support/health_change_run.h). Per run it prints the
// alarm's delay after the change, the cause named with the alarm and 30 s after the change, and
// when the heading chart was ready after the fit; then per change the counts the issue's
// acceptance asks for (docs/live_assistant.md quotes the default run's table).
// Usage: study_health_changes [--seeds 201,202,203,204,205] [--within S] (default 30 s)
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "health_study_table.h"
#include "support/health_change_run.h"

namespace {

using namespace odometry_calibration;
using namespace odometry_calibration::health_runs;
using namespace odometry_calibration::health_study;

struct Tally
{
  int runs = 0, detected = 0, kind_right = 0, kind_wrong = 0, quantity_told = 0, quantity_right = 0,
      false_alarms = 0;
};

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> seed_texts = {"201", "202", "203", "204", "205"};
  double within_s = 30.0;
  if (const int status = parseSeedSweep(argc, argv, "study_health_changes", &seed_texts, &within_s);
      status >= 0)
    return status;
  const std::vector<Change> changes = {Change::kRightRadius, Change::kSeparation, Change::kLaserYaw,
                                       Change::kLaserX, Change::kNone};
  std::printf(
      "| change | seed | alarm after change [s] | cause at the alarm | cause %.0f s after "
      "the change | heading chart ready after the fit [s] |\n|---|---|---|---|---|---|\n",
      within_s);
  std::vector<Tally> tallies(changes.size());
  for (std::size_t c = 0; c < changes.size(); ++c) {
    for (const std::string& seed_text : seed_texts) {
      RunOptions run;
      run.change = changes[c];
      run.seed = static_cast<unsigned>(std::stoul(seed_text));
      run.verdict_after_s = within_s;
      const RunResult result = runChange(run);
      Tally& tally = tallies[c];
      ++tally.runs;
      if (changes[c] == Change::kNone) {
        tally.false_alarms += result.alarm ? 1 : 0;
        std::printf("| %s | %u | %s | | | %.1f |\n", changeName(changes[c]), run.seed,
                    result.alarm ? "FALSE ALARM" : "none", result.heading_ready_s);
        continue;
      }
      const bool detected = result.alarm && result.alarm_delay_s >= 0.0 &&
                            result.alarm_delay_s <= within_s && result.later_valid;
      tally.detected += detected ? 1 : 0;
      const ChangeVerdict& verdict = result.later;
      if (detected && verdict.kind_told) {
        const bool right = verdict.kind == expectedKind(changes[c]);
        tally.kind_right += right ? 1 : 0;
        tally.kind_wrong += right ? 0 : 1;
        if (verdict.quantity_told) {
          ++tally.quantity_told;
          tally.quantity_right += namedRightly(verdict, changes[c], true) ? 1 : 0;
        }
      }
      std::printf("| %s | %u | %.1f | %s | %s | %.1f |\n", changeName(changes[c]), run.seed,
                  result.alarm_delay_s, verdictCell(result.at_alarm).c_str(),
                  detected ? verdictCell(verdict).c_str() : "(not detected in time)",
                  result.heading_ready_s);
    }
  }
  std::printf(
      "\n| change | runs | detected within %.0f s | kind right / wrong | quantity told "
      "(right) | false alarms |\n|---|---|---|---|---|---|\n",
      within_s);
  for (std::size_t c = 0; c < changes.size(); ++c) {
    const Tally& t = tallies[c];
    std::printf("| %s | %d | %d | %d / %d | %d (%d) | %d |\n", changeName(changes[c]), t.runs,
                t.detected, t.kind_right, t.kind_wrong, t.quantity_told, t.quantity_right,
                t.false_alarms);
  }
  return 0;
}
