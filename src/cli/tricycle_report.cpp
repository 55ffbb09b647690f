#include "odometry_calibration/cli/tricycle_report.h"

#include <cmath>
#include <cstdarg>
#include <cstdio>

namespace odometry_calibration {
namespace {

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

/// The nominal robot's row of `rows` (scoreNominal's, "nominal"); none when it is missing.
const ModelScore* nominalRow(const std::vector<ModelScore>& rows)
{
  for (const ModelScore& row : rows) {
    if (row.model == "nominal" && !row.fitted)
      return &row;
  }
  return nullptr;
}

/// The ATE and RPE lines of `rows` (the calibrated model first), the nominal's called `before`.
std::string trajectoryErrorLines(const std::vector<ModelScore>& rows, const char* before)
{
  const ModelScore& calibrated = rows.front();
  const ModelScore* nominal = nominalRow(rows);
  const double nan = std::nan("");
  return line("  ATE (paper eq. 11): %s %.3f m -> calibrated %.3f m", before,
              nominal ? nominal->ate_m : nan, calibrated.ate_m) +
         line("  RPE (paper eq. 10, between keyframes): %s %.4f m -> calibrated %.4f m", before,
              nominal ? nominal->rpe_m : nan, calibrated.rpe_m);
}

/// The validation curve's lines (fit.choice).
std::string validationCurve(const FitIntervalChoice& choice, double evaluation_interval_s)
{
  std::string cuts;
  for (std::size_t count : choice.fold_counts)
    cuts += (cuts.empty() ? "" : ",") + std::to_string(count);
  std::string text = line("keyframe interval: T = %.2f s, chosen by time-blocked cross-validation",
                          choice.interval_s);
  text += line("  (validation curve: the %s of each time block's chained %.2f s pairs",
               criterionName(choice.criterion), evaluation_interval_s);
  text += "   predicted by a fit to the pairs outside it, mean over the blocks of the cuts into " +
          cuts + " blocks)\n";
  text += line("  %8s %8s %16s", "T [s]", "pairs",
               (std::string("validation ") + criterionName(choice.criterion)).c_str());
  for (const FitIntervalScore& score : choice.curve) {
    if (std::isfinite(score.validation_error_m)) {
      text +=
          line("  %8.2f %8zu %14.3f m%s", score.interval_s, score.pairs, score.validation_error_m,
               score.interval_s == choice.interval_s ? "  <- chosen" : "");
    } else {
      text += line("  %8.2f %8zu %16s", score.interval_s, score.pairs, "too few pairs");
    }
  }
  return text;
}

}  // namespace

std::string formatTricycleInterval(const SessionFit& fit, double evaluation_interval_s)
{
  if (fit.choice)
    return validationCurve(*fit.choice, evaluation_interval_s);
  if (!fit.interval_problem.empty()) {
    return line("keyframe interval: T = %.2f s (not chosen: %s)", fit.fit_interval_s,
                fit.interval_problem.c_str());
  }
  return line("keyframe interval: T = %.2f s (set by hand)", fit.fit_interval_s);
}

std::string formatTricycleHeldOut(const TricycleHeldOut& held_out)
{
  return line(
             "held out: the last %.0f %% of the samples (%zu samples, %.1f s), never seen by "
             "the fit",
             100.0 * held_out.fraction, held_out.samples, held_out.duration_s) +
         trajectoryErrorLines(held_out.rows, "nominal");
}

std::string formatTricycleReport(const TricycleCalibrationResult& result,
                                 const std::vector<ModelScore>& fitted)
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
  const std::vector<double>& stamps_s = fitted.front().stamps_s;
  text += line("sensor trajectory over %.1f s (%zu poses), dead-reckoned from the encoders:",
               stamps_s.empty() ? 0.0 : stamps_s.back() - stamps_s.front(), stamps_s.size());
  text += trajectoryErrorLines(fitted, "initial");
  text += "\n";
  if (result.warnings.empty()) {
    text += "observability: all parameters are well determined by this motion\n";
  } else {
    text += "WARNINGS:\n";
    for (const std::string& warning : result.warnings)
      text += "  - " + warning + "\n";
  }
  for (const std::string& note : result.notes)
    text += "  note: " + note + "\n";
  return text;
}

}  // namespace odometry_calibration
