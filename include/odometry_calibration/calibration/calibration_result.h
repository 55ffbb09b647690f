// The saved calibration (result.yaml): the fitted model, its report, the sensor's pose on the
// robot and the encoder-laser time offset; written by calibrate_bag and the live node's ~save,
// read back by the node on start. Plus the URDF snippet of the laser joint.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// A calibration read back from result.yaml.
struct CalibrationResult
{
  std::shared_ptr<MotionModel> model;  ///< fitted model, ready to predict
  bool has_extrinsic = false;          ///< whether T_base_sensor was estimated
  Pose2 T_base_sensor;                 ///< the sensor's pose in base_link [m, m, rad]
  double time_offset_s = 0.0;          ///< encoder values at scan time + offset [s]
  /// Keyframe interval of the pairs the model was fitted on [s] (a GP predicts windows of this
  /// length); 0: not recorded (older results: the configured interval_s).
  double fit_interval_s = 0.0;
  /// The joints the model was fitted on, in EncoderSample order (empty: not recorded).
  std::vector<std::string> joints;
};

/// result.yaml's text: the report's numbers, the fitted model (enough to predict again), the
/// extrinsic, `time_offset_s` (to the microsecond), `joints` (the joint names, in the model's
/// order) when given and, when > 0, `fit_interval_s` (the fitted pairs' keyframe interval). The
/// one writer of result.yaml, for the node's ~save and calibrate_bag.
std::string calibrationResultYaml(const ModelReport& report, const MotionModel& model,
                                  const std::string& source, double time_offset_s,
                                  const std::vector<std::string>& joints = {},
                                  double fit_interval_s = 0.0);

/// result.yaml's `fit_interval_choice:` block (appended to the file): how `fit_interval_s` was
/// chosen by time-blocked cross-validation (fit_interval.h): `criterion` (RPE or ATE),
/// `evaluation_interval_s` (the interval of the blocks' evaluation pairs [s]), `fold_counts`,
/// and `curve`, one `{interval_s, pairs, validation_error_m}` per candidate (`.inf`: a fold
/// could not be fitted).
std::string fitIntervalChoiceYaml(const FitIntervalChoice& choice, double evaluation_interval_s);

/// One set of pairs the fitted model (and the compared rows) was scored on.
struct ResultScores
{
  std::string data;              ///< its key under `scores:` ("held_out", "test", "fitted")
  std::string description;       ///< which pairs, in words
  std::vector<ModelScore> rows;  ///< scoreModelsOnTest's rows (model_comparison.h)
};

/// result.yaml's `scores:` block (appended to the file): per set, under its `data` key, its
/// `description` and `models`, one row per model: `model`, `pairs` (scored), `ate_m`, `rpe_m`
/// (paper eqs. 11, 10 of the chained predictions), `rmse_x_m`, `rmse_y_m`, `rmse_theta_rad`
/// (per pair), `converged`; a skipped row `{model, skipped}`. Empty without a set.
std::string scoresYaml(const std::vector<ResultScores>& sets);

/// Parses result.yaml's text. Throws std::runtime_error naming `source` and what is missing.
CalibrationResult parseCalibrationResult(const std::string& text, const std::string& source);

/// Reads result.yaml. Throws std::runtime_error if it cannot be read or parsed.
CalibrationResult readCalibrationResult(const std::string& path);

/// A URDF <joint> element placing the laser on the robot (fixed joint, planar pose: z and
/// roll/pitch are not observable from planar motion and are left at zero, said in a comment).
std::string laserJointUrdf(const Pose2& T_base_laser, const std::string& base_frame,
                           const std::string& laser_frame);

}  // namespace odometry_calibration
