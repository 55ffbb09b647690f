// Scoring a saved calibration (result.yaml) on new data without refitting: the check of last
// month's calibration on today's drive. The same table as the comparison (model_comparison.h,
// paper eqs. 10-11 and per-axis RMSE), with the configured nominal robot as the baseline row.
#pragma once

#include <string>
#include <vector>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/eval/model_comparison.h"

namespace odometry_calibration {

/// Throws std::runtime_error "<what> carries the joints (a, b) but the calibration was made
/// with (c, d)" unless `joints` equals `calibration_joints` (an empty `calibration_joints`, an
/// older result.yaml, is not checked here; the model then checks the joint count itself).
void requireCalibrationJoints(const std::vector<std::string>& calibration_joints,
                              const std::vector<std::string>& joints, const std::string& what);

/// The saved model (row named after it, `fitted` false: nothing is refitted) on `pairs`, which
/// were collected at the saved time offset, then the nominal robot (the configuration's prior,
/// unfitted, row "nominal"), on the pairs re-cut at time offset 0 from `encoder_history` when
/// that is given and the saved offset is not 0. Throws std::runtime_error for fewer than two
/// pairs or pairs that do not carry the model's joints, naming the problem.
std::vector<ModelScore> scoreSavedCalibration(const CalibrationConfig& config,
                                              const CalibrationResult& saved,
                                              const std::vector<MotionPair>& pairs,
                                              const std::vector<EncoderSample>& encoder_history);

}  // namespace odometry_calibration
