// The paper's model comparison (Tables III/IV): models trained on some pairs, scored on
// others by the ATE and RPE of the integrated test trajectory (eqs. 10-11) and the per-axis
// RMSE of the predicted displacements.
#pragma once

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
};

/// The paper's baseline row: `nominal` (a parametric model at its configured start values,
/// unfitted) scored on the test pairs as scoreModel does, named "nominal", `fitted` false.
ModelScore scoreNominal(const MotionModel& nominal, const std::vector<MotionPair>& test);

/// `score` with the fit's time, outliers, warnings and convergence from `report`.
ModelScore withFitReport(ModelScore score, const ModelReport& report);

/// Scores a fitted model: each test pair's displacement predicted from its encoder samples,
/// chained into a trajectory from the origin and compared with the chain of the measured
/// displacements (the test pairs are taken as consecutive). Throws for fewer than 2 pairs.
ModelScore scoreModel(const MotionModel& model, const std::vector<MotionPair>& test);

/// The comparison as a fixed-width text table, one row per model; a model whose fit did not
/// converge is marked "NOT converged" on its row and named, with the reason, under the table; a
/// skipped model likewise "skipped".
std::string formatComparisonTable(const std::vector<ModelScore>& scores);

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
