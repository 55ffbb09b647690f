// The held-out table made after a fit on all pairs (the live node's ~calibrate reply): which
// model generalizes best on the last part of the pairs, with every model of compare_models and
// the nominal robot, in the paper's table (ATE/RPE of the chained predictions, eqs. 10-11).
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/calibration_job.h"

namespace odometry_calibration {

struct HeldOutComparison
{
  std::vector<ModelScore> scores;  ///< scoreHeldOut's rows
  std::size_t training_pairs = 0, test_pairs = 0;
  double border_stamp_s = 0.0;  ///< where the held-out part starts [s]
  double first_stamp_s = 0.0;   ///< the first pair's start [s]
};

/// The job's pairs cut by holdOutLastPairs(`holdout_fraction`); config.model and
/// config.compare_models fitted on the first part and, with the nominal robot (re-cut at time
/// offset 0 from `encoder_history` when given), scored on the last (scoreHeldOut). Throws
/// std::invalid_argument when either part would keep fewer than two pairs, and what the
/// model's fit throws.
HeldOutComparison compareHeldOut(const CalibrationConfig& config, const CalibrationJobResult& job,
                                 double holdout_fraction,
                                 const std::vector<EncoderSample>& encoder_history);

/// The comparison in words: which pairs were held out, the table and the best model
/// (formatBestModel), lines ending in '\n'.
std::string formatHeldOutComparison(const HeldOutComparison& comparison, double holdout_fraction);

}  // namespace odometry_calibration
