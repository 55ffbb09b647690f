#include "odometry_calibration/calibration/saved_calibration_score.h"

#include "odometry_calibration/calibration/calibration_job.h"

#include <stdexcept>

#include "odometry_calibration/calibration/time_offset.h"

namespace odometry_calibration {
namespace {

std::string list(const std::vector<std::string>& names)
{
  std::string text;
  for (const std::string& name : names)
    text += (text.empty() ? "" : ", ") + name;
  return "(" + text + ")";
}

}  // namespace

void requireCalibrationJoints(const std::vector<std::string>& calibration_joints,
                              const std::vector<std::string>& joints, const std::string& what)
{
  if (!calibration_joints.empty() && joints != calibration_joints) {
    throw std::runtime_error(what + " carries the joints " + list(joints) +
                             " but the calibration was made with " + list(calibration_joints));
  }
}

std::vector<ModelScore> scoreSavedCalibration(const CalibrationConfig& config,
                                              const CalibrationResult& saved,
                                              const std::vector<MotionPair>& pairs,
                                              const std::vector<EncoderSample>& encoder_history)
{
  if (!saved.model)
    throw std::runtime_error("the saved calibration holds no model");
  if (pairs.size() < 2) {
    throw std::runtime_error("scoring needs at least two pairs, the data gave " +
                             std::to_string(pairs.size()) + ": give a longer drive");
  }
  std::vector<ModelScore> scores;
  try {
    scores.push_back(scoreModel(*saved.model, pairs));
  } catch (const std::invalid_argument& error) {
    // e.g. a diff_drive fitted on joints 2 and 3 scored on two-joint pairs
    throw std::runtime_error(std::string("the data does not fit the saved calibration: ") +
                             error.what());
  }
  scores.back().fitted = false;
  if (saved.has_extrinsic)
    scores.back().T_base_sensor = saved.T_base_sensor;
  if (std::optional<ModelScore> nominal =
          scoreNominalRobot(config, pairs, encoder_history, saved.time_offset_s))
    scores.push_back(std::move(*nominal));
  return scores;
}

}  // namespace odometry_calibration
