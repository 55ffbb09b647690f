#include "odometry_calibration/ros/bag_calibration.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_config_schema.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/report/result_files.h"
#include "odometry_calibration/ros/bag_joint_calibration.h"
#include "odometry_calibration/ros/bag_runner.h"

namespace odometry_calibration {
namespace {

/// --interval auto without keyframes.fit_intervals_s: these candidates [s].
const std::vector<double> kAutoIntervals = {0.3, 0.5, 1.0};

/// How the fitted pairs' interval is found, and which intervals the session pairs besides.
struct IntervalPlan
{
  FitIntervalMode mode = FitIntervalMode::kConfigured;
  double fixed_s = 0.0;
  std::vector<double> candidates_s;
};

IntervalPlan planIntervals(const std::string& option, const CalibrationConfig& config)
{
  IntervalPlan plan;
  if (option == "auto" || (option.empty() && !config.fit_intervals_s.empty())) {
    plan.mode = FitIntervalMode::kChoose;
    plan.candidates_s = config.fit_intervals_s.empty() ? kAutoIntervals : config.fit_intervals_s;
  } else if (!option.empty()) {
    plan.mode = FitIntervalMode::kFixed;
    plan.fixed_s = std::stod(option);
    plan.candidates_s = {plan.fixed_s};
  }
  return plan;
}

void showProgress(const BagProgress& p)
{
  const double rate = p.elapsed_s > 0.0 ? p.messages / p.elapsed_s : 0.0;
  const double eta = p.fraction > 0.0 ? p.elapsed_s * (1.0 - p.fraction) / p.fraction : 0.0;
  std::fprintf(stderr, "\r%5.1f %%  %8.0f msg/s  ETA %5.1f s ", 100.0 * p.fraction, rate, eta);
  if (p.fraction >= 1.0)
    std::fprintf(stderr, "\n");
}

CalibrationConfig loadConfig(const BagCalibrationOptions& options)
{
  // With --model, the configuration as that model needs it (its joints resolved, checked).
  CalibrationConfig config =
      options.model.empty() ? loadCalibrationConfig(options.config_path)
                            : configForModel(readTextFile(options.config_path, "the configuration"),
                                             options.model, "", options.config_path);
  config.collector.background_matching = !options.single_thread;
  for (const std::string& bag : options.test_bags) {
    if (!std::filesystem::is_regular_file(bag))
      throw std::runtime_error("no test bag file '" + bag + "'");
  }
  return config;
}

/// The session's fit of the run's pairs (paired again at the estimated time offset when the
/// configured one is off: the run then takes those pairs, `pairing` says so); throws when none
/// could run.
SessionFit fitRun(BagRunResult* run, const IntervalPlan& plan, double holdout,
                  OffsetPairing* pairing)
{
  CalibrationRequest request;
  request.interval_mode = plan.mode;
  request.fixed_interval_s = plan.fixed_s;
  if (holdout > 0.0)
    request.holdout_fraction = holdout;
  CalibrateOutcome outcome = run->session->calibrate(request);
  takeSessionPairs(run);
  *pairing = outcome.offset_pairing;
  if (!outcome.fit)
    throw std::runtime_error(outcome.message);
  return std::move(*outcome.fit);
}

/// The scores on the test bags (paired at the fitted time offset): text and report table.
std::string scoreTestBags(const BagCalibrationOptions& options, const CalibrationConfig& config,
                          const CalibrationJobResult& job, ResultFiles* files)
{
  CalibrationConfig test_config = config;
  test_config.collector.time_offset_s = job.time_offset_s;
  const BagRunResult test = runBags(options.test_bags, test_config, 0.0, 0.0);
  files->markdown.test_table =
      formatComparisonTable(scoreModelsOnTest(config, job, test.pairs, test.encoder_history));
  files->markdown.test_pairs = test.pairs.size();
  return "\ntest bags: " + std::to_string(test.pairs.size()) + " pairs\n" +
         files->markdown.test_table;
}

/// The scores on the held-out pairs: text and report table.
std::string scoreHoldout(const BagCalibrationOptions& options, const CalibrationConfig& config,
                         const BagRunResult& run, const PairHoldout& split, const SessionFit& fit,
                         ResultFiles* files)
{
  const std::vector<ModelScore> scores =
      scoreHeldOut(config, fit.job, split.test, run.encoder_history);
  files->markdown.holdout_table = formatComparisonTable(scores);
  char note[400];
  std::snprintf(note, sizeof(note),
                "held out: the %zu pairs (T = %.2f s) after %.1f s (the last %.0f %% of the "
                "collection), %zu fitted (T = %.2f s); calibrated: the fitted %s",
                split.test.size(), config.collector.keyframe_interval_s,
                split.border_stamp_s - run.pairs.front().start_stamp_s, 100.0 * options.holdout,
                fit.job.pairs.size(), fit.fit_interval_s, config.model.c_str());
  files->markdown.holdout_note = note;
  if (scores.size() > 1)
    files->markdown.holdout_note +=
        ", nominal: the " + config.prior_model + " start values at time offset 0";
  return "\n" + files->markdown.holdout_note + "\n" + files->markdown.holdout_table;
}

std::string timingLine(const BagRunResult& run, const SessionFit& fit)
{
  char timing[300];
  std::snprintf(timing, sizeof(timing),
                "time: reading %.3f s, scan conversion %.3f s, pairing %.3f s (thread time: "
                "scan preparation %.3f s, matching %.3f s), fitting %.3f s\n",
                run.read_time_s, run.conversion_time_s, run.pairing_time_s,
                run.statistics.preparation_time_s, run.statistics.matching_time_s,
                fit.job.fit_time_s);
  return timing;
}

/// The report's data of the run and of the fit-interval choice.
void describeRun(const BagCalibrationOptions& options, const CalibrationConfig& config,
                 const BagRunResult& run, const SessionFit& fit, ResultFiles* files)
{
  if (fit.choice) {
    for (const FitIntervalScore& score : fit.choice->curve)
      files->plots.fit_interval_curve.emplace_back(score.interval_s, score.validation_rpe_m);
    files->plots.fit_interval_s = fit.choice->interval_s;
    files->plots.fit_interval_evaluation_s = config.collector.keyframe_interval_s;
  }
  files->markdown.fit_interval_note = fit.interval_text.empty() ? "" : fit.interval_text + "\n";
  files->gnuplot = options.gnuplot;
  files->markdown.bags = options.bags;
  files->markdown.data_span_s = run.bag_span_s;
  files->markdown.run_time_s = run.wall_time_s;
  files->markdown.statistics = run.statistics;
  files->markdown.collection_notes = bagRunNotes(run);
}

void writeFiles(const std::string& output_dir, ResultFiles files, std::ostream& out)
{
  const bool controller = !files.controller_yaml.empty();
  const ReportPlots plots = writeResultFiles(output_dir, std::move(files));
  out << "\nwritten: " << output_dir << "/{" << kPairsFileName << ", " << kResultFileName
      << (controller ? std::string(", ") + kControllerFileName : "") << ", " << kTextReportFileName
      << ", " << kReportFileName << ", " << kPlotFolderName << "/}\nreport: " << output_dir << "/"
      << kReportFileName << "\n";
  if (!plots.problem.empty())
    std::fprintf(stderr, "warning: the report has no plots or only some: %s\n",
                 plots.problem.c_str());
}

}  // namespace

void checkBagCalibrationOptions(const BagCalibrationOptions& options)
{
  if (options.config_path.empty() || (options.bags.empty() && !options.print_config))
    throw std::invalid_argument("give --config and at least one bag");
  if (options.end_s > 0.0 && options.end_s <= options.start_s)
    throw std::invalid_argument("--end must come after --start");
  if (!(options.holdout < 1.0))
    throw std::invalid_argument("option --holdout: expected a fraction in (0, 1)");
  if (!options.model.empty())
    requireKnownModel(options.model, "--model");
  if (options.interval.empty() || options.interval == "auto")
    return;
  std::size_t used = 0;
  double interval = 0.0;
  try {
    interval = std::stod(options.interval, &used);
  } catch (const std::exception&) {
  }
  if (used != options.interval.size() || !(interval > 0.0) || !(interval <= 60.0)) {
    throw std::invalid_argument(
        "option --interval: expected 'auto' or a number of seconds in (0, 60], got '" +
        options.interval + "'");
  }
}

int calibrateBags(const BagCalibrationOptions& options, std::ostream& out)
{
  CalibrationConfig config = loadConfig(options);
  if (options.print_config) {
    out << formatEffectiveConfig(config);
    return 0;
  }
  if (config.ego_motion_sources.size() > 1)  // issue 35: several sensors, one joint fit
    return calibrateBagsJointly(options, config, out);
  const std::string output_dir =
      options.output_dir.empty() ? config.output_directory : options.output_dir;
  const IntervalPlan plan = planIntervals(options.interval, config);
  BagRunResult run =
      runBags(options.bags, config, options.start_s, options.end_s,
              options.quiet ? nullptr : std::function<void(const BagProgress&)>(showProgress),
              plan.candidates_s);
  // Fitted at the estimated time offset (paired again when the configured one is off).
  OffsetPairing pairing;
  const SessionFit fit = fitRun(&run, plan, options.holdout, &pairing);
  if (pairing.paired_again)
    config.collector.time_offset_s = pairing.estimate_s;
  const std::string summary = formatBagRunSummary(run) + pairing.text;
  out << summary;
  const PairHoldout split =
      options.holdout > 0.0 ? holdOutLastPairs(run.pairs, options.holdout) : PairHoldout();
  const CalibrationJobResult& job = fit.job;
  std::string text = summary + (fit.interval_text.empty() ? "" : fit.interval_text + "\n") +
                     (job.time_offset ? formatTimeOffset(*job.time_offset) : "") + "\n" +
                     formatModelReport(job.report) + formatNominalComparison(job);
  ResultFiles files = resultFilesForJob(jointLayout(config), job, options.bags.front());
  describeRun(options, config, run, fit, &files);
  if (!options.test_bags.empty())
    text += scoreTestBags(options, config, job, &files);
  if (options.holdout > 0.0)
    text += scoreHoldout(options, config, run, split, fit, &files);
  text += timingLine(run, fit);
  out << text.substr(summary.size());
  // Everything succeeded: write the files together.
  files.text_report = text;
  writeFiles(output_dir, std::move(files), out);
  return calibrationExitStatus(job.report);
}

}  // namespace odometry_calibration
