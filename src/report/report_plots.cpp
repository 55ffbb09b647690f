#include "odometry_calibration/report/report_plots.h"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/common/histogram.h"

namespace odometry_calibration {

const char* const kTrajectoryPlot = "trajectories.png";
const char* const kResidualPlot = "residuals.png";
const char* const kTimeOffsetPlot = "time_offset.png";
const char* const kFitIntervalPlot = "fit_interval.png";

namespace {

constexpr double kRadToDeg = 180.0 / M_PI;
constexpr std::size_t kHistogramBins = 30;
const char* const kTerminal = "set terminal pngcairo noenhanced font 'sans,10' size ";

std::string number(double value)
{
  if (!std::isfinite(value))
    return "NaN";  // gnuplot skips the point
  char text[32];
  std::snprintf(text, sizeof(text), "%.9g", value);
  return text;
}

void writeText(const std::string& path, const std::string& text)
{
  std::ofstream out(path, std::ios::binary);
  out << text;
  if (!out.flush())
    throw std::runtime_error("cannot write '" + path + "'");
}

std::vector<double> scaled(std::vector<double> values, double factor)
{
  for (double& value : values)
    value *= factor;
  return values;
}

/// trajectories.dat/.gp: positions of the three chained trajectories.
std::string trajectoryScript(const ReportPlotInput& input, const std::string& directory)
{
  const TrajectoryComparison& t = input.trajectories;
  const bool has_nominal = !t.nominal.empty();
  std::ostringstream data;
  data << "# time_s matched_x_m matched_y_m nominal_x_m nominal_y_m calibrated_x_m "
          "calibrated_y_m\n";
  for (std::size_t i = 0; i < t.stamps_s.size(); ++i) {
    data << number(t.stamps_s[i] - t.stamps_s.front()) << ' ' << number(t.matched[i].x()) << ' '
         << number(t.matched[i].y()) << ' '
         << (has_nominal ? number(t.nominal[i].x()) + ' ' + number(t.nominal[i].y())
                         : std::string("NaN NaN"))
         << ' ' << number(t.calibrated[i].x()) << ' ' << number(t.calibrated[i].y()) << '\n';
  }
  writeText(directory + "/trajectories.dat", data.str());
  std::ostringstream script;
  script << "reset\n"
         << kTerminal << "900,750\n"
         << "set output '" << kTrajectoryPlot << "'\n"
         << "set title \"Sensor trajectory: " << t.calibrated_errors.size()
         << " keyframe pairs chained from the first keyframe"
         << (t.gaps > 0 ? " (" + std::to_string(t.gaps) + " rejected intervals skipped)" : "")
         << "\"\n"
         << "set xlabel 'x [m]'\nset ylabel 'y [m]'\nset size ratio -1\nset grid\n"
         << "set key outside bottom center horizontal\n"
         << "plot 'trajectories.dat' using 2:3 with lines lw 2.5 lc rgb '#222222' "
            "title 'scan-matched', \\\n";
  if (has_nominal) {
    script << "     '' using 4:5 with lines lw 1.5 lc rgb '#d62728' "
              "title 'nominal model (raw odometry)', \\\n";
  }
  script << "     '' using 6:7 with lines lw 1.5 lc rgb '#1f77b4' title 'calibrated ("
         << input.calibrated_label << ")', \\\n"
         << "     '' every ::0::0 using 2:3 with points pt 7 ps 1.5 lc rgb '#222222' "
            "title 'start'\n";
  writeText(directory + "/trajectories.gp", script.str());
  return "trajectories.gp";
}

/// One histogram panel's data block: bin centre, nominal count, calibrated count.
void histogramBlock(std::ostringstream& data, const std::vector<double>& nominal,
                    const std::vector<double>& calibrated, double upper, Histogram* nominal_out,
                    Histogram* calibrated_out)
{
  *nominal_out = makeHistogram(nominal, upper, kHistogramBins);
  *calibrated_out = makeHistogram(calibrated, upper, kHistogramBins);
  for (std::size_t b = 0; b < kHistogramBins; ++b) {
    data << number((static_cast<double>(b) + 0.5) * calibrated_out->bin_width) << ' '
         << (nominal.empty() ? std::string("NaN") : std::to_string(nominal_out->counts[b])) << ' '
         << calibrated_out->counts[b] << '\n';
  }
}

std::string overflowNote(const Histogram& nominal, const Histogram& calibrated, bool has_nominal)
{
  if (nominal.overflow + calibrated.overflow == 0)
    return "";
  std::string note = " (beyond the axis:";
  if (has_nominal)
    note += " nominal " + std::to_string(nominal.overflow) + ",";
  return note + " calibrated " + std::to_string(calibrated.overflow) + ")";
}

/// residuals.dat/.gp: histograms of the per-pair errors, translation [mm] and rotation [deg].
std::string residualScript(const ReportPlotInput& input, const std::string& directory)
{
  const TrajectoryComparison& t = input.trajectories;
  const bool has_nominal = !t.nominal_errors.empty();
  const std::vector<double> nominal_mm = scaled(translationErrors(t.nominal_errors), 1000.0);
  const std::vector<double> calibrated_mm = scaled(translationErrors(t.calibrated_errors), 1000.0);
  const std::vector<double> nominal_deg = scaled(rotationErrors(t.nominal_errors), kRadToDeg);
  const std::vector<double> calibrated_deg = scaled(rotationErrors(t.calibrated_errors), kRadToDeg);
  // A common axis per panel: 98 % of all errors on it, the rest counted as beyond.
  const double upper_mm = histogramUpperLimit({nominal_mm, calibrated_mm}, 0.98, 1e-3);
  const double upper_deg = histogramUpperLimit({nominal_deg, calibrated_deg}, 0.98, 1e-4);
  std::ostringstream data;
  Histogram nominal_t, calibrated_t, nominal_r, calibrated_r;
  data << "# translation error: bin centre [mm], pairs (nominal), pairs (calibrated)\n";
  histogramBlock(data, nominal_mm, calibrated_mm, upper_mm, &nominal_t, &calibrated_t);
  data << "\n\n# rotation error: bin centre [deg], pairs (nominal), pairs (calibrated)\n";
  histogramBlock(data, nominal_deg, calibrated_deg, upper_deg, &nominal_r, &calibrated_r);
  writeText(directory + "/residuals.dat", data.str());

  std::ostringstream script;
  script << "reset\n"
         << kTerminal << "1100,480\n"
         << "set output '" << kResidualPlot << "'\n"
         << "set multiplot layout 1,2 title \"Per-pair prediction errors against the scan "
            "matches, "
         << t.calibrated_errors.size() << " pairs"
         << (has_nominal ? ": nominal model (before) and calibrated (after)" : "") << "\"\n"
         << "set style fill transparent solid 0.5 noborder\nset grid ytics\nset ylabel 'pairs'\n"
         << "set key top right\nset yrange [0:*]\n";
  auto panel = [&](int index, const Histogram& nominal, const Histogram& calibrated,
                   const char* label) {
    script << "set boxwidth " << number(calibrated.bin_width) << " absolute\n"
           << "set xrange [0:" << number(calibrated.bin_width * kHistogramBins) << "]\n"
           << "set xlabel \"" << label << overflowNote(nominal, calibrated, has_nominal) << "\"\n"
           << "plot ";
    if (has_nominal) {
      script << "'residuals.dat' index " << index
             << " using 1:2 with boxes lc rgb '#d62728' title 'nominal', \\\n     ";
    }
    script << "'residuals.dat' index " << index << " using 1:3 with boxes lc rgb '#1f77b4' "
           << "title 'calibrated (" << input.calibrated_label << ")'\n";
  };
  panel(0, nominal_t, calibrated_t, "translation error [mm]");
  panel(1, nominal_r, calibrated_r, "rotation error [deg]");
  script << "unset multiplot\n";
  writeText(directory + "/residuals.gp", script.str());
  return "residuals.gp";
}

/// time_offset.dat/.gp: the cost against tau, the estimate marked.
std::string timeOffsetScript(const ReportPlotInput& input, const std::string& directory)
{
  std::ostringstream data;
  data << "# tau_s cost (mean Huber loss of chi^2 of the model refitted at tau)\n";
  for (const auto& [tau, cost] : input.time_offset_curve)
    data << number(tau) << ' ' << number(cost) << '\n';
  writeText(directory + "/time_offset.dat", data.str());
  char label[128];
  std::snprintf(label, sizeof(label), "tau = %.4f s +- %.4f s", input.time_offset_s,
                input.time_offset_sigma_s);
  std::ostringstream script;
  script << "reset\n"
         << kTerminal << "900,500\n"
         << "set output '" << kTimeOffsetPlot << "'\n"
         << "set title 'Encoder-laser time offset: the model refitted at every tau'\n"
         << "set xlabel 'tau [s] (encoder values taken at scan time + tau)'\n"
         << "set ylabel 'cost (mean Huber loss of chi^2)'\nset grid\nset key top center\n"
         << "set arrow from " << number(input.time_offset_s) << ", graph 0 to "
         << number(input.time_offset_s) << ", graph 1 nohead dt 2 lw 1.5 lc rgb '#1f77b4'\n"
         << "set label \"" << label << "\" at " << number(input.time_offset_s)
         << ", graph 0.92 offset 0.8,0 tc rgb '#1f77b4'\n"
         << "plot 'time_offset.dat' using 1:2 with linespoints pt 7 ps 0.7 lw 1.5 "
            "lc rgb '#222222' title 'cost'\n";
  writeText(directory + "/time_offset.gp", script.str());
  return "time_offset.gp";
}

/// fit_interval.dat/.gp: the validation error (RPE or ATE) against the candidate fit interval,
/// the choice marked.
std::string fitIntervalScript(const ReportPlotInput& input, const std::string& directory)
{
  const std::string& criterion = input.fit_interval_criterion;
  std::ostringstream data;
  data << "# interval_s validation_" << (criterion == "ATE" ? "ate" : "rpe")
       << "_m (time-blocked cross-validation)\n";
  for (const auto& [interval, error] : input.fit_interval_curve) {
    if (std::isfinite(error))
      data << number(interval) << ' ' << number(error) << '\n';
  }
  writeText(directory + "/fit_interval.dat", data.str());
  char title[160];
  std::snprintf(title, sizeof(title),
                "Fit interval: validation %s of %.2f s pairs on held-out time blocks",
                criterion.c_str(), input.fit_interval_evaluation_s);
  std::ostringstream script;
  script << "reset\n"
         << kTerminal << "900,500\n"
         << "set output '" << kFitIntervalPlot << "'\n"
         << "set title '" << title << "'\n"
         << "set xlabel 'keyframe interval T of the fitted pairs [s]'\n"
         << "set ylabel 'validation " << criterion << " [m]'\nset grid\nset key top center\n"
         << "set arrow from " << number(input.fit_interval_s) << ", graph 0 to "
         << number(input.fit_interval_s) << ", graph 1 nohead dt 2 lw 1.5 lc rgb '#1f77b4'\n"
         << "set label \"chosen T = " << number(input.fit_interval_s) << " s\" at "
         << number(input.fit_interval_s) << ", graph 0.92 offset 0.8,0 tc rgb '#1f77b4'\n"
         << "plot 'fit_interval.dat' using 1:2 with linespoints pt 7 ps 0.9 lw 1.5 "
            "lc rgb '#222222' title 'validation RPE'\n";
  writeText(directory + "/fit_interval.gp", script.str());
  return "fit_interval.gp";
}

}  // namespace

bool ReportPlots::has(const std::string& image) const
{
  for (const std::string& made : images) {
    if (made == image)
      return true;
  }
  return false;
}

bool isPngFile(const std::string& path)
{
  std::ifstream in(path, std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), {});
  static const std::string kSignature("\x89PNG\r\n\x1a\n", 8);
  return bytes.size() > 8 + 25 + 12 && bytes.compare(0, 8, kSignature) == 0 &&
         bytes.compare(12, 4, "IHDR") == 0 && bytes.compare(bytes.size() - 8, 4, "IEND") == 0;
}

ReportPlots writeReportPlots(const ReportPlotInput& input, const std::string& directory,
                             const GnuplotOptions& gnuplot)
{
  ReportPlots plots;
  std::vector<std::string> scripts, images;
  try {
    scripts.push_back(trajectoryScript(input, directory));
    images.push_back(kTrajectoryPlot);
    scripts.push_back(residualScript(input, directory));
    images.push_back(kResidualPlot);
    if (!input.time_offset_curve.empty()) {
      scripts.push_back(timeOffsetScript(input, directory));
      images.push_back(kTimeOffsetPlot);
    }
    if (!input.fit_interval_curve.empty()) {
      scripts.push_back(fitIntervalScript(input, directory));
      images.push_back(kFitIntervalPlot);
    }
  } catch (const std::exception& error) {
    plots.problem = std::string("the plot data could not be written: ") + error.what();
    return plots;
  }
  plots.problem = runGnuplot(scripts, directory, gnuplot);
  std::string unreadable;
  for (const std::string& image : images) {
    if (isPngFile(directory + "/" + image))
      plots.images.push_back(image);
    else
      unreadable += (unreadable.empty() ? "" : ", ") + image;
  }
  if (plots.problem.empty() && !unreadable.empty())
    plots.problem = "gnuplot did not make a valid PNG of " + unreadable;
  return plots;
}

}  // namespace odometry_calibration
