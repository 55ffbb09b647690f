#include "odometry_calibration/eval/tricycle_report.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/eval/metrics.h"

namespace odometry_calibration {
namespace {

std::vector<Pose2> pick(const std::vector<Pose2>& poses, const std::vector<std::size_t>& indices)
{
  std::vector<Pose2> picked;
  picked.reserve(indices.size());
  for (std::size_t index : indices) {
    picked.push_back(poses.at(index));
  }
  return picked;
}

std::string line(const char* format, ...) __attribute__((format(printf, 1, 2)));
std::string line(const char* format, ...)
{
  char buffer[512];
  va_list args;
  va_start(args, format);
  std::vsnprintf(buffer, sizeof(buffer), format, args);
  va_end(args);
  return std::string(buffer) + "\n";
}

}  // namespace

TricycleEvaluation evaluateTricycle(const TricycleCalibrationResult& result,
                                    const TricycleEncoderLayout& layout,
                                    const std::vector<EncoderSample>& samples,
                                    const std::vector<Pose2>& reference,
                                    const std::vector<std::size_t>& keyframe_indices)
{
  if (samples.size() != reference.size() || samples.size() < 2) {
    throw std::invalid_argument("evaluation needs one reference pose per encoder sample");
  }
  const auto initial = tricycleSensorTrajectory(result.initial, layout, samples, reference.front());
  const auto calibrated =
      tricycleSensorTrajectory(result.calibrated, layout, samples, reference.front());
  TricycleEvaluation evaluation;
  evaluation.ate_initial_m = absoluteTrajectoryError(initial, reference);
  evaluation.ate_calibrated_m = absoluteTrajectoryError(calibrated, reference);
  if (keyframe_indices.size() >= 2) {
    const auto reference_keyframes = pick(reference, keyframe_indices);
    evaluation.rpe_initial_m =
        relativePoseError(pick(initial, keyframe_indices), reference_keyframes);
    evaluation.rpe_calibrated_m =
        relativePoseError(pick(calibrated, keyframe_indices), reference_keyframes);
  }
  evaluation.pose_count = samples.size();
  evaluation.duration_s = samples.back().stamp_s - samples.front().stamp_s;
  return evaluation;
}

std::string formatTricycleReport(const TricycleCalibrationResult& result,
                                 const TricycleEvaluation& evaluation)
{
  std::string text;
  text += "Tricycle calibration report\n";
  text += "===========================\n";
  text += line(
      "pairs: %zu used, %zu inliers, %zu outliers (beyond the Huber threshold: %zu down-weighted, "
      "%zu gross beyond 5 sigma)",
      result.pair_count, result.pair_count - result.outlier_count, result.outlier_count,
      result.outlier_count - result.gross_outliers, result.gross_outliers);
  text += line("solver: %s after %d iterations, %.3f s (%s)",
               result.converged ? "converged" : "NOT converged", result.iterations,
               result.solve_time_s, result.termination.c_str());
  if (result.starts > 1) {
    text += line("starts: %d of %d sensor-yaw starts reached the best fit", result.starts_agreed,
                 result.starts);
  }
  text += "\n";
  text += line("%-16s %12s %14s %12s  %s", "parameter", "initial", "calibrated", "sigma", "unit");
  for (const ParameterEstimate& estimate : result.estimates) {
    text += line("%-16s %12.6g %14.7g %12.3g  %s", estimate.name.c_str(), estimate.initial,
                 estimate.value, estimate.sigma, estimate.unit.c_str());
  }
  if (result.covariance_available) {
    text += line("(sigma from the covariance at the solution, scaled by chi2/dof = %.3g)",
                 result.chi2_per_dof);
  }
  text += "\n";
  text += line("%-34s %12s %12s", "residual RMS per keyframe pair", "translation", "rotation");
  text += line("%-34s %10.4f m %8.5f rad", "  before (initial parameters)",
               result.before.translation_m, result.before.rotation_rad);
  text += line("%-34s %10.4f m %8.5f rad", "  after (all pairs)", result.after.translation_m,
               result.after.rotation_rad);
  text += line("%-34s %10.4f m %8.5f rad", "  after (inliers)", result.after_inliers.translation_m,
               result.after_inliers.rotation_rad);
  text += "\n";
  text += line("sensor trajectory over %.1f s (%zu poses), dead-reckoned from the encoders:",
               evaluation.duration_s, evaluation.pose_count);
  text += line("  ATE (paper eq. 11): initial %.3f m -> calibrated %.3f m",
               evaluation.ate_initial_m, evaluation.ate_calibrated_m);
  text += line("  RPE (paper eq. 10, between keyframes): initial %.4f m -> calibrated %.4f m",
               evaluation.rpe_initial_m, evaluation.rpe_calibrated_m);
  text += "\n";
  if (result.warnings.empty()) {
    text += "observability: all parameters are well determined by this motion\n";
  } else {
    text += "WARNINGS:\n";
    for (const std::string& warning : result.warnings) {
      text += "  - " + warning + "\n";
    }
  }
  for (const std::string& note : result.notes)
    text += "  note: " + note + "\n";
  return text;
}

std::string formatTricycleValidation(const TricycleValidation& validation)
{
  std::string text;
  if (validation.interval_chosen) {
    std::string cuts;
    for (std::size_t count : validation.fold_counts) {
      cuts += (cuts.empty() ? "" : ",") + std::to_string(count);
    }
    text += line("keyframe interval: T = %.2f s, chosen by time-blocked cross-validation",
                 validation.interval_s);
    text += line("  (validation curve: the ATE of each time block's chained %.2f s pairs",
                 validation.evaluation_interval_s);
    text +=
        "   predicted by a fit to the pairs outside it, mean over the blocks of the cuts into " +
        cuts + " blocks)\n";
    text += line("  %8s %8s %16s", "T [s]", "pairs", "validation ATE");
    for (const IntervalScore& score : validation.curve) {
      if (std::isfinite(score.validation_ate_m)) {
        text +=
            line("  %8.2f %8zu %14.3f m%s", score.interval_s, score.pairs, score.validation_ate_m,
                 score.interval_s == validation.interval_s ? "  <- chosen" : "");
      } else {
        text += line("  %8.2f %8zu %16s", score.interval_s, score.pairs, "too few pairs");
      }
    }
  } else if (!validation.fallback_reason.empty()) {
    text += line("keyframe interval: T = %.2f s (not chosen: %s)", validation.interval_s,
                 validation.fallback_reason.c_str());
  } else {
    text += line("keyframe interval: T = %.2f s (set by hand)", validation.interval_s);
  }
  if (validation.holdout_fraction > 0.0) {
    const TricycleEvaluation& e = validation.held_out;
    text += "\n";
    text += line(
        "held out: the last %.0f %% of the samples (%zu samples, %.1f s), never seen by "
        "the fit",
        100.0 * validation.holdout_fraction, validation.held_out_samples, e.duration_s);
    text += line("  ATE (paper eq. 11): nominal %.3f m -> calibrated %.3f m", e.ate_initial_m,
                 e.ate_calibrated_m);
    text += line("  RPE (paper eq. 10, between keyframes): nominal %.4f m -> calibrated %.4f m",
                 e.rpe_initial_m, e.rpe_calibrated_m);
  }
  return text;
}

}  // namespace odometry_calibration
