#include "odometry_calibration/calibration/held_out_comparison.h"

#include <cstdio>

#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {

HeldOutComparison compareHeldOut(const CalibrationConfig& config, const CalibrationJobResult& job,
                                 double holdout_fraction,
                                 const std::vector<EncoderSample>& encoder_history)
{
  const PairHoldout split = holdOutLastPairs(job.pairs, holdout_fraction);
  CalibrationJobResult training;
  training.time_offset_s = job.time_offset_s;
  training.pairs = split.training;
  training.model = makeModel(config.model, config.models);
  training.report = training.model->fit(training.pairs);
  HeldOutComparison comparison;
  comparison.training_pairs = split.training.size();
  comparison.test_pairs = split.test.size();
  comparison.border_stamp_s = split.border_stamp_s;
  comparison.first_stamp_s = job.pairs.front().start_stamp_s;
  // The test pairs are at the job's offset already: the history only re-cuts the nominal's.
  CalibrationConfig at_job_offset = config;
  at_job_offset.collector.time_offset_s = job.time_offset_s;
  comparison.scores = scoreHeldOut(at_job_offset, training, split.test, encoder_history);
  return comparison;
}

std::string formatHeldOutComparison(const HeldOutComparison& comparison, double holdout_fraction)
{
  char line[300];
  std::snprintf(line, sizeof(line),
                "held out: the %zu pairs after %.1f s (the last %.0f %%), every model fitted to "
                "the %zu before:\n",
                comparison.test_pairs, comparison.border_stamp_s - comparison.first_stamp_s,
                100.0 * holdout_fraction, comparison.training_pairs);
  return line + formatComparisonTable(comparison.scores) +
         formatBestModel(comparison.scores, "the held-out pairs");
}

}  // namespace odometry_calibration
