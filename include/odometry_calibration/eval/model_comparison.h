// The paper's model comparison (Tables III/IV): models trained on some pairs, scored on
// others by the ATE and RPE of the integrated test trajectory (eqs. 10-11) and the per-axis
// RMSE of the predicted displacements.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// How one fitted model does on test pairs.
struct ModelScore
{
  std::string model;
  double ate_m = 0.0;  ///< eq. 11 between the chained predictions and the chained measurements
  double rpe_m = 0.0;  ///< eq. 10 over consecutive test pairs
  Eigen::Vector3d rmse_xytheta = Eigen::Vector3d::Zero();  ///< per-axis prediction RMSE
  std::size_t test_pairs = 0;
  double fit_time_s = 0.0;
  std::size_t outliers = 0;  ///< rejected while training
  std::vector<std::string> warnings;
  /// Whether the training fit converged; a row that did not is marked in the table, with
  /// `termination` (its scores are those of wherever the solver stopped).
  bool converged = true;
  std::string termination;
  /// False for a row without a fit here (the nominal model, a saved calibration): its fit time
  /// and outliers show "-"; a row named "nominal" is explained under the table.
  bool fitted = true;
  std::string nominal_model;  ///< the nominal row: which model at its start values
  /// Why the model could not be fitted on these pairs (empty when it was): the table shows the
  /// row as skipped and the reason under it.
  std::string skipped;
  /// The trajectories scored (empty for a skipped row): the keyframe stamps [s] (the first test
  /// pair's start, then each pair's end), and the chained predictions and measured
  /// displacements, sensor poses in the sensor frame of the first keyframe [m, m, rad].
  std::vector<double> stamps_s;
  std::vector<Pose2> predicted, measured;
  /// The sensor's pose in base_link the model holds (a fit that estimated it, the nominal
  /// robot's configured one); none for a model-free model.
  std::optional<Pose2> T_base_sensor;
};

/// The paper's baseline row: `nominal` (a parametric model at its configured start values,
/// unfitted) scored on the test pairs as scoreModel does, named "nominal", `fitted` false.
ModelScore scoreNominal(const MotionModel& nominal, const std::vector<MotionPair>& test);

/// `score` with the fit's time, outliers, warnings and convergence from `report`, and its
/// sensor pose when the fit estimated one.
ModelScore withFitReport(ModelScore score, const ModelReport& report);

/// Scores a fitted model: each test pair's displacement predicted from its encoder samples,
/// chained into a trajectory from the origin and compared with the chain of the measured
/// displacements (the test pairs are taken as consecutive). Throws for fewer than 2 pairs.
ModelScore scoreModel(const MotionModel& model, const std::vector<MotionPair>& test);

/// The comparison as a fixed-width text table, one row per model; a model whose fit did not
/// converge is marked "NOT converged" on its row and named, with the reason, under the table; a
/// skipped model likewise "skipped".
std::string formatComparisonTable(const std::vector<ModelScore>& scores);

/// Which row generalizes best, in words: the scored row (not skipped, converged) with the lowest
/// ATE, how many times lower it is than the next best and than the nominal row, and the ranking
/// of all scored rows by ATE and by RPE (the ATE of a longer drive grows with its length, the RPE
/// does not), e.g. "best on the held-out pairs: gp, ATE 0.0123 m, 2.1x lower than linear (0.0258
/// m), 19.1x lower than nominal (0.2350 m); ranking by ATE: gp < linear < diff_drive < nominal,
/// by RPE: gp < diff_drive < linear < nominal". `where` names the pairs ("the held-out pairs").
/// Empty with fewer than two scored rows.
std::string formatBestModel(const std::vector<ModelScore>& scores, const std::string& where);

/// The scored rows' names (not skipped, converged) from the lowest ATE (RPE) to the highest.
std::vector<std::string> rankByAte(const std::vector<ModelScore>& scores);
std::vector<std::string> rankByRpe(const std::vector<ModelScore>& scores);

/// Fits each model of `models` (makeModel with `options`, in order) on the training pairs and
/// scores it on the test pairs (scoreModel, plus the fit's time, outliers and warnings), then
/// adds the `nominal` row (scoreNominal) when given. Throws std::invalid_argument "the
/// training files hold no pair" without training pairs, or what makeModel and the fit throw.
std::vector<ModelScore> compareModels(const std::vector<std::string>& models,
                                      const ModelFactoryOptions& options,
                                      const std::vector<MotionPair>& training,
                                      const std::vector<MotionPair>& testing,
                                      const MotionModel* nominal = nullptr);

}  // namespace odometry_calibration
