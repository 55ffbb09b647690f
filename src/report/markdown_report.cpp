#include "odometry_calibration/report/markdown_report.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "odometry_calibration/eval/metrics.h"

namespace odometry_calibration {
namespace {

constexpr double kRadToDeg = 180.0 / M_PI;

std::string format(const char* pattern, double value)
{
  if (!std::isfinite(value))
    return "-";
  char text[64];
  std::snprintf(text, sizeof(text), pattern, value);
  return text;
}

/// Text for a table cell: '|' escaped (solver messages contain it).
std::string cell(const std::string& text)
{
  std::string escaped;
  for (const char c : text) {
    if (c == '|')
      escaped += '\\';
    escaped += c;
  }
  return escaped;
}

double rms(const std::vector<double>& values)
{
  double sum = 0.0;
  for (const double value : values)
    sum += value * value;
  return values.empty() ? 0.0 : std::sqrt(sum / static_cast<double>(values.size()));
}

void image(std::ostringstream& out, const MarkdownReportInput& input, const char* file,
           const std::string& caption)
{
  if (input.plots.has(file))
    out << "\n![" << caption << "](" << input.plot_folder << "/" << file << ")\n";
  else
    out << "\n*(plot `" << file << "` not made: see \"Plots\" above)*\n";
}

void summary(std::ostringstream& out, const MarkdownReportInput& input)
{
  const ModelReport& r = input.report;
  out << "| | |\n|---|---|\n| bags |";
  for (std::size_t i = 0; i < input.bags.size(); ++i)
    out << (i ? ", " : " ") << "`" << cell(input.bags[i]) << "`";
  out << " |\n| data | " << format("%.1f", input.data_span_s) << " s, read and paired in "
      << format("%.2f", input.run_time_s) << " s ("
      << format("%.0f", input.run_time_s > 0 ? input.data_span_s / input.run_time_s : 0.0)
      << "x real time) |\n"
      << "| model | `" << r.model << "` |\n"
      << "| fit | " << (r.converged ? "converged" : "**NOT converged**") << " after "
      << r.iterations << " iterations, " << format("%.3f", r.fit_time_s) << " s ("
      << cell(r.termination) << ") |\n"
      << "| pairs | " << r.pairs_used << " used, " << r.rejected << " rejected, " << r.down_weighted
      << " down-weighted |\n"
      << (r.starts > 1
              ? "| starts | " + std::to_string(r.starts_agreed) + " of " +
                    std::to_string(r.starts) + " sensor-yaw starts reached the best fit |\n"
              : std::string())
      << "| verdict | "
      << (r.warnings.empty()
              ? "no warning"
              : "**" + std::to_string(r.warnings.size()) + " warning(s)**: see below")
      << " |\n";
}

void plotsNote(std::ostringstream& out, const MarkdownReportInput& input)
{
  if (input.plots.problem.empty())
    return;
  out << "\n## Plots\n\n> **Some plots are missing: " << input.plots.problem
      << ".**\n> The calibration itself is complete. The plot data and gnuplot scripts are in `"
      << input.plot_folder << "/`; with gnuplot installed, `cd " << input.plot_folder
      << " && gnuplot *.gp` draws them.\n";
}

void parameters(std::ostringstream& out, const ModelReport& r)
{
  out << "\n## Parameters\n\n";
  if (r.parameters.empty()) {
    out << "The `" << r.model << "` model has no named parameters.\n";
  } else {
    out << "| parameter | initial | estimate | σ | unit |\n|---|---:|---:|---:|---|\n";
    for (const ParameterEstimate& p : r.parameters) {
      out << "| " << p.name << " | " << format("%.6g", p.initial) << " | "
          << format("%.7g", p.value) << " | " << format("%.3g", p.sigma) << " | " << p.unit
          << " |\n";
    }
  }
  if (r.has_extrinsic) {
    out << "\nSensor pose in `base_link`: x " << format("%.4f", r.T_base_sensor.x()) << " m, y "
        << format("%.4f", r.T_base_sensor.y()) << " m, yaw "
        << format("%.5f", r.T_base_sensor.theta()) << " rad ("
        << format("%.2f", r.T_base_sensor.theta() * kRadToDeg) << "°).\n";
  }
  if (r.before.count == 0) {  // model-free: no start values, no "before"
    out << "\nResidual RMS per pair: translation " << format("%.4f", r.after.translation_m)
        << " m, rotation " << format("%.5f", r.after.rotation_rad)
        << " rad (a model without start values; the nominal model, when configured, is compared "
           "below).\n";
    return;
  }
  out << "\nResidual RMS per pair: translation " << format("%.4f", r.before.translation_m)
      << " m → " << format("%.4f", r.after.translation_m) << " m, rotation "
      << format("%.5f", r.before.rotation_rad) << " rad → " << format("%.5f", r.after.rotation_rad)
      << " rad (before: the start values).\n";
}

void observability(std::ostringstream& out, const ModelReport& r)
{
  out << "\n## Observability\n\n";
  if (r.warnings.empty()) {
    out << "No warning: the drive determines every parameter of the model, and the fit has no "
           "adequacy or time-offset warning.\n";
  }
  for (const std::string& warning : r.warnings)
    out << "- **WARNING**: " << warning << "\n";
  for (const std::string& note : r.notes)
    out << (r.warnings.empty() ? "\n- note: " : "- note: ") << note << "\n";
}

void timeOffset(std::ostringstream& out, const MarkdownReportInput& input)
{
  out << "\n## Time offset\n\n";
  if (!input.time_offset) {
    out << "Not estimated (`keyframes.estimate_time_offset` is off): the configured offset τ = "
        << format("%.4f", input.time_offset_used_s) << " s was used.\n";
    return;
  }
  const TimeOffsetResult& t = *input.time_offset;
  out << "Encoder values are taken at scan time + τ. Estimated τ = " << format("%.4f", t.offset_s)
      << " s ± " << format("%.4f", t.sigma_s) << " s"
      << (t.offset_s < 0   ? " (the encoders run ahead of the laser)"
          : t.offset_s > 0 ? " (the encoders lag behind the laser)"
                           : "")
      << "; the final fit used τ = " << format("%.4f", input.time_offset_used_s) << " s.";
  if (t.flat)
    out << " **The cost curve is flat: τ is not observable from this drive.**";
  if (t.at_boundary)
    out << " **The minimum lies at the edge of the search range: widen it.**";
  out << "\n";
  image(out, input, kTimeOffsetPlot, "time-offset cost curve");
}

void residuals(std::ostringstream& out, const MarkdownReportInput& input)
{
  const TrajectoryComparison& t = input.trajectories;
  out << "\n## Per-pair errors before and after\n\n"
      << "Prediction error of each keyframe pair against its scan-matched displacement ("
      << t.calibrated_errors.size() << " pairs";
  if (!input.nominal_description.empty())
    out << "; before: the nominal model, " << input.nominal_description;
  out << ").\n\n| model | median translation [m] | RMS translation [m] | median rotation [rad] "
         "| RMS rotation [rad] |\n|---|---:|---:|---:|---:|\n";
  auto row = [&](const std::string& name, const std::vector<Pose2>& errors) {
    const std::vector<double> translation = translationErrors(errors);
    const std::vector<double> rotation = rotationErrors(errors);
    out << "| " << name << " | " << format("%.4f", median(translation)) << " | "
        << format("%.4f", rms(translation)) << " | " << format("%.5f", median(rotation)) << " | "
        << format("%.5f", rms(rotation)) << " |\n";
  };
  if (!t.nominal_errors.empty())
    row("nominal (before)", t.nominal_errors);
  row("calibrated `" + input.report.model + "` (after)", t.calibrated_errors);
  image(out, input, kResidualPlot, "histograms of the per-pair errors before and after");
}

void trajectories(std::ostringstream& out, const MarkdownReportInput& input)
{
  const TrajectoryComparison& t = input.trajectories;
  out << "\n## Trajectories\n\n"
      << "The sensor's path chained over the " << t.calibrated_errors.size()
      << " keyframe pairs from the first keyframe: scan-matched displacements, "
      << (t.nominal.empty() ? "" : "the nominal model's predictions (raw odometry), ")
      << "the calibrated model's predictions";
  if (t.gaps > 0)
    out << " (" << t.gaps << " rejected intervals are skipped by all three alike)";
  out << ". Distances to the scan-matched path (ATE: paper eq. 11):\n\n"
      << "| trajectory | ATE [m] | end point off by [m] |\n|---|---:|---:|\n";
  auto row = [&](const std::string& name, const std::vector<Pose2>& poses) {
    const Pose2 end = between(poses.back(), t.matched.back());
    out << "| " << name << " | " << format("%.3f", absoluteTrajectoryError(poses, t.matched))
        << " | " << format("%.3f", std::hypot(end.x(), end.y())) << " |\n";
  };
  if (!t.nominal.empty())
    row("nominal model", t.nominal);
  row("calibrated `" + input.report.model + "`", t.calibrated);
  image(out, input, kTrajectoryPlot, "scan-matched, nominal and calibrated trajectories");
}

void collection(std::ostringstream& out, const MarkdownReportInput& input)
{
  const CollectorStatistics& s = input.statistics;
  out << "\n## Pair collection\n\n"
      << "- " << s.scans << " scans, " << s.keyframes << " keyframes, " << s.pairs << " pairs\n";
  if (s.consecutive_matches > 0) {
    out << "- consistency check: " << s.consecutive_matches << " consecutive-scan matches, "
        << s.consecutive_failures << " failed; " << s.unverified_pairs
        << " pairs kept unverified\n";
  }
  if (s.scale_check_pairs > 0) {
    const double error_pct = s.keyframeVersusChainStandardErrorPercent();
    out << "- scale check: over " << s.scale_check_pairs << " pairs the keyframe matches read "
        << format("%+.2f", s.keyframeVersusChainPercent()) << " %"
        << (std::isfinite(error_pct) ? " (standard error " + format("%.2f", error_pct) + " %)"
                                     : std::string())
        << " longer than the consecutive matches chained over the same interval: how far the "
           "matcher's two scales disagree on this data (0 for an unbiased matcher; not the "
           "error of the fitted parameters)\n";
  }
  if (s.rejected.empty())
    out << "- no keyframe interval rejected\n";
  for (const auto& [reason, count] : s.rejected)
    out << "- rejected " << count << ": " << reason << "\n";
  for (const std::string& note : input.collection_notes)
    out << "- " << note << "\n";
}

}  // namespace

std::string markdownReport(const MarkdownReportInput& input)
{
  std::ostringstream out;
  out << "# Calibration report: `" << input.report.model << "`\n\n";
  summary(out, input);
  plotsNote(out, input);
  parameters(out, input.report);
  observability(out, input.report);
  timeOffset(out, input);
  residuals(out, input);
  trajectories(out, input);
  collection(out, input);
  if (!input.fit_interval_note.empty()) {
    out << "\n## Fit interval\n\n" << input.fit_interval_note << "\n";
    image(out, input, kFitIntervalPlot, "validation curve of the fit interval");
  }
  if (!input.test_table.empty()) {
    out << "\n## Test bags\n\n"
        << input.test_pairs
        << " pairs; per model: ATE and RPE of the chained predictions (paper eqs. 10-11), "
           "per-axis RMSE:\n\n```\n"
        << input.test_table << "```\n";
  }
  if (!input.holdout_table.empty()) {
    out << "\n## Held-out pairs\n\n"
        << input.holdout_note
        << "; ATE and RPE of the chained predictions (paper eqs. 10-11), per-axis RMSE:\n\n```\n"
        << input.holdout_table << "```\n";
  }
  if (!input.files.empty()) {
    out << "\n## Files\n\n";
    for (const std::string& file : input.files)
      out << "- " << file << "\n";
  }
  return out.str();
}

}  // namespace odometry_calibration
