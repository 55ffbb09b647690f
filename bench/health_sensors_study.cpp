// The health monitor watching two lasers against mid-run changes (issue 35): the seed sweep of
// test/assistant/health_monitor_sensors_test.cpp (test/support/front_rear_health_run.h). The
// simulator's front/rear robot, each laser's scans paired by PLICP, the wheels and both poses
// fitted jointly on the pairs of the first 124 s, one change at 300 s (the rear laser's yaw
// +2 deg, the front laser's x +3 cm, the right wheel radius +2 %, the separation +3 %) or
// none, one monitor on both lasers' pairs after the fit; a changed run ends 30 s after the
// change, an unchanged twin at 600 s. A study printing tables, not a timing benchmark.
// Usage: study_health_sensors [--seeds 631,632,633,634,635] [--within S] (default 30 s)
#include <algorithm>
#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include "health_study_table.h"
#include "support/front_rear_health_run.h"

namespace {

using namespace odometry_calibration;
using namespace odometry_calibration::front_rear_health;
using namespace odometry_calibration::health_study;

/// Per change: runs, alarms within the window, and how the cause read at the alarm and after.
struct Tally
{
  int runs = 0, detected = 0;
  int at_alarm[5] = {0, 0, 0, 0, 0};  ///< indexed by Naming
  int later[5] = {0, 0, 0, 0, 0};
  double slowest_s = 0.0;
};

void printTally(const std::vector<Change>& changes, const std::vector<Tally>& tallies,
                const std::string& within)
{
  std::printf(
      "\n| change | runs | alarms | slowest alarm after the change [s] | at the alarm: quantity "
      "right / laser or wheels right, quantity open / cannot tell / wrong | %s after the change: "
      "the same |\n|---|---|---|---|---|---|\n",
      within.c_str());
  for (std::size_t c = 0; c < changes.size(); ++c) {
    const Tally& t = tallies[c];
    char slowest[32] = "";
    if (t.detected > 0)
      std::snprintf(slowest, sizeof(slowest), "%.1f", t.slowest_s);
    std::printf("| %s | %d | %d | %s | %d / %d / %d / %d | %d / %d / %d / %d |\n",
                changeName(changes[c]), t.runs, t.detected, slowest, t.at_alarm[0], t.at_alarm[1],
                t.at_alarm[2], t.at_alarm[3], t.later[0], t.later[1], t.later[2], t.later[3]);
  }
}

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> seed_texts = {"631", "632", "633", "634", "635"};
  double within_s = 30.0;
  if (const int status = parseSeedSweep(argc, argv, "study_health_sensors", &seed_texts, &within_s);
      status >= 0)
    return status;
  std::printf(
      "| change | seed | alarm after change [s] | chart that fired | cause at the alarm | cause "
      "%.0f s after the change | statistic |\n|---|---|---|---|---|---|---|\n",
      within_s);
  const std::vector<Change> changes = {Change::kRearYaw, Change::kFrontX, Change::kRightRadius,
                                       Change::kSeparation, Change::kNone};
  std::vector<Tally> tallies(changes.size());
  for (std::size_t c = 0; c < changes.size(); ++c) {
    for (const std::string& seed_text : seed_texts) {
      RunOptions run;
      run.change = changes[c];
      run.seed = static_cast<unsigned>(std::stoul(seed_text));
      run.within_s = within_s;
      const RunResult r = runFrontRear(run);
      Tally& tally = tallies[c];
      ++tally.runs;
      if (r.alarm) {
        ++tally.detected;
        tally.slowest_s = std::max(tally.slowest_s, r.alarm_delay_s);
        ++tally.at_alarm[static_cast<int>(naming(r.at_alarm, changes[c]))];
        ++tally.later[static_cast<int>(naming(r.later, changes[c]))];
      }
      char delay[32] = "none";
      if (r.alarm)
        std::snprintf(delay, sizeof(delay), "%.1f", r.alarm_delay_s);
      const std::string chart = r.alarm ? kLaserNames.at(r.alarm_sensor) : "";
      std::printf("| %s | %u | %s | %s | %s | %s | %.2f |\n", changeName(changes[c]), run.seed,
                  delay, chart.c_str(), r.alarm ? verdictCell(r.at_alarm, kLaserNames).c_str() : "",
                  r.alarm ? verdictCell(r.later, kLaserNames).c_str() : "", r.statistic);
      std::fflush(stdout);
    }
  }
  char within[32];
  std::snprintf(within, sizeof(within), "%.0f s", within_s);
  printTally(changes, tallies, within);
  return 0;
}
