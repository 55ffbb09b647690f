#include "odometry_calibration/report/tricycle_result_yaml.h"

#include <cmath>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {
namespace {

void emitRms(YAML::Emitter& out, const char* key, const ResidualRms& rms)
{
  out << YAML::Key << key << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "translation_m" << YAML::Value << rms.translation_m;
  out << YAML::Key << "rotation_rad" << YAML::Value << rms.rotation_rad;
  out << YAML::Key << "pairs" << YAML::Value << rms.count;
  out << YAML::EndMap;
}

/// parameters: each estimate's value, sigma (.nan when unavailable), initial value and unit.
void emitParameters(YAML::Emitter& out, const std::vector<ParameterEstimate>& estimates)
{
  out << YAML::Key << "parameters" << YAML::Value << YAML::BeginMap;
  for (const ParameterEstimate& estimate : estimates) {
    out << YAML::Key << estimate.name << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "value" << YAML::Value << estimate.value;
    // YAML has .nan; an unavailable sigma is written as such rather than as a made-up number.
    out << YAML::Key << "sigma" << YAML::Value << estimate.sigma;
    out << YAML::Key << "initial" << YAML::Value << estimate.initial;
    out << YAML::Key << "unit" << YAML::Value << estimate.unit;
    out << YAML::EndMap;
  }
  out << YAML::EndMap;
}

/// fit: convergence, counts, starts, chi2 and the residual RMS before and after.
void emitFit(YAML::Emitter& out, const TricycleCalibrationResult& result)
{
  out << YAML::Key << "fit" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "converged" << YAML::Value << result.converged;
  out << YAML::Key << "iterations" << YAML::Value << result.iterations;
  out << YAML::Key << "termination" << YAML::Value << result.termination;
  out << YAML::Key << "pairs" << YAML::Value << result.pair_count;
  out << YAML::Key << "outliers" << YAML::Value << result.outlier_count;
  out << YAML::Key << "gross_outliers" << YAML::Value << result.gross_outliers;
  out << YAML::Key << "starts" << YAML::Value << result.starts;
  out << YAML::Key << "starts_agreed" << YAML::Value << result.starts_agreed;
  out << YAML::Key << "chi2_per_dof" << YAML::Value << result.chi2_per_dof;
  emitRms(out, "residual_rms_before", result.before);
  emitRms(out, "residual_rms_after", result.after);
  emitRms(out, "residual_rms_after_inliers", result.after_inliers);
  out << YAML::EndMap;
}

/// keyframe_interval: the interval and how it was chosen (with the validation curve).
void emitKeyframeInterval(YAML::Emitter& out, const TricycleValidation& validation)
{
  out << YAML::Key << "keyframe_interval" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "interval_s" << YAML::Value << validation.interval_s;
  out << YAML::Key << "chosen" << YAML::Value
      << (validation.interval_chosen           ? "cross_validation"
          : validation.fallback_reason.empty() ? "by_hand"
                                               : "fallback");
  if (validation.interval_chosen) {
    out << YAML::Key << "fold_counts" << YAML::Value << YAML::Flow << validation.fold_counts;
    out << YAML::Key << "validation_curve" << YAML::Value << YAML::BeginSeq;
    for (const IntervalScore& score : validation.curve) {
      out << YAML::Flow << YAML::BeginMap;
      out << YAML::Key << "interval_s" << YAML::Value << score.interval_s;
      out << YAML::Key << "ate_m" << YAML::Value << score.validation_ate_m;
      out << YAML::Key << "pairs" << YAML::Value << score.pairs;
      out << YAML::EndMap;
    }
    out << YAML::EndSeq;
  }
  out << YAML::EndMap;
}

/// holdout: the held-out share's samples and scores, when one was held out.
void emitHoldout(YAML::Emitter& out, const TricycleValidation& validation)
{
  if (!(validation.holdout_fraction > 0.0))
    return;
  const TricycleEvaluation& e = validation.held_out;
  out << YAML::Key << "holdout" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "fraction" << YAML::Value << validation.holdout_fraction;
  out << YAML::Key << "training_samples" << YAML::Value << validation.training_samples;
  out << YAML::Key << "held_out_samples" << YAML::Value << validation.held_out_samples;
  out << YAML::Key << "ate_initial_m" << YAML::Value << e.ate_initial_m;
  out << YAML::Key << "ate_calibrated_m" << YAML::Value << e.ate_calibrated_m;
  out << YAML::Key << "rpe_initial_m" << YAML::Value << e.rpe_initial_m;
  out << YAML::Key << "rpe_calibrated_m" << YAML::Value << e.rpe_calibrated_m;
  out << YAML::EndMap;
}

}  // namespace

std::string tricycleResultToYaml(const TricycleCalibrationResult& result,
                                 const TricycleEvaluation& evaluation, const std::string& source,
                                 const TricycleValidation* validation)
{
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << "tricycle";
  out << YAML::Key << "source" << YAML::Value << source;
  emitParameters(out, result.estimates);
  const Pose2& T = result.calibrated.T_base_sensor;
  out << YAML::Key << "T_base_sensor" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "x_m" << YAML::Value << T.x();
  out << YAML::Key << "y_m" << YAML::Value << T.y();
  out << YAML::Key << "theta_rad" << YAML::Value << T.theta();
  out << YAML::EndMap;
  emitFit(out, result);
  out << YAML::Key << "evaluation" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "ate_initial_m" << YAML::Value << evaluation.ate_initial_m;
  out << YAML::Key << "ate_calibrated_m" << YAML::Value << evaluation.ate_calibrated_m;
  out << YAML::Key << "rpe_initial_m" << YAML::Value << evaluation.rpe_initial_m;
  out << YAML::Key << "rpe_calibrated_m" << YAML::Value << evaluation.rpe_calibrated_m;
  out << YAML::EndMap;
  if (validation != nullptr) {
    emitKeyframeInterval(out, *validation);
    emitHoldout(out, *validation);
  }
  out << YAML::Key << "warnings" << YAML::Value << YAML::BeginSeq;
  for (const std::string& warning : result.warnings) {
    out << warning;
  }
  out << YAML::EndSeq;
  out << YAML::Key << "notes" << YAML::Value << YAML::BeginSeq;
  for (const std::string& note : result.notes)
    out << note;
  out << YAML::EndSeq;
  out << YAML::EndMap;
  return "# odometry_calibration result (tricycle model)\n" + std::string(out.c_str()) + "\n";
}

}  // namespace odometry_calibration
