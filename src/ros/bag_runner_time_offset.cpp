#include "odometry_calibration/ros/bag_runner.h"

#include <cmath>
#include <cstdio>

#include "odometry_calibration/calibration/calibration_job.h"

namespace odometry_calibration {

BagRunResult runBagsAtEstimatedOffset(const std::vector<std::string>& bag_paths,
                                      CalibrationConfig* config, double start_offset_s,
                                      double end_offset_s,
                                      const std::function<void(const BagProgress&)>& progress,
                                      OffsetPairing* pairing, double tolerance_s,
                                      const std::vector<double>& candidate_intervals_s)
{
  OffsetPairing local;
  OffsetPairing& result = pairing ? *pairing : local;
  result = OffsetPairing();
  result.configured_s = result.estimate_s = config->collector.time_offset_s;
  BagRunResult run =
      runBags(bag_paths, *config, start_offset_s, end_offset_s, progress, candidate_intervals_s);
  if (!config->estimate_time_offset || run.pairs.empty() || run.encoder_history.empty())
    return run;
  CalibrationJobOptions offset_only;
  offset_only.compare_trajectories = false;
  const CalibrationJobResult first =
      runCalibrationJob(*config, run.pairs, run.encoder_history, offset_only);
  if (!first.time_offset || first.time_offset->flat)
    return run;
  result.estimate_s = first.time_offset_s;
  char text[300];
  if (!(std::abs(result.estimate_s - result.configured_s) > tolerance_s)) {
    std::snprintf(text, sizeof(text),
                  "paired at the configured time offset %.3f s (estimated %.3f s, within %.3f s)\n",
                  result.configured_s, result.estimate_s, tolerance_s);
    result.text = text;
    result.search = first.time_offset;
    return run;
  }
  config->collector.time_offset_s = result.estimate_s;
  run = runBags(bag_paths, *config, start_offset_s, end_offset_s, progress, candidate_intervals_s);
  result.paired_again = true;
  std::snprintf(text, sizeof(text),
                "paired again at the estimated time offset %.3f s (configured %.3f s: set "
                "keyframes.time_offset_s to it to pair once)\n",
                result.estimate_s, result.configured_s);
  result.text = text;
  return run;
}

}  // namespace odometry_calibration
