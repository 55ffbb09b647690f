// calibrate_bag: reads bags directly (no playback), pairs keyframes with the same code as the
// live node, fits the configured model, and writes the pairs, the result and a report.
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include <glog/logging.h>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/report/result_files.h"
#include "odometry_calibration/ros/bag_message_reader.h"
#include "odometry_calibration/ros/bag_runner.h"

namespace {

using namespace odometry_calibration;

const char* kUsage =
    "usage: calibrate_bag --config CONFIG.yaml BAG [BAG ...] [options]\n"
    "\n"
    "Reads the bags in timestamp order with the rosbag API, makes keyframe pairs (PLICP scan\n"
    "matching, or the configured ego-motion topic), fits the configured model and writes\n"
    "pairs.csv, result.yaml, report.txt and report.md (the report with plots in plots/, drawn\n"
    "by gnuplot) to the output directory, and for diff_drive, skid_steer and mecanum fits\n"
    "controller.yaml (the geometry as the robot's controller takes it).\n"
    "\n"
    "options:\n"
    "  --output-dir DIR     where to write (default: the config's output_directory)\n"
    "  --model NAME         fit this model instead of the config's (diff_drive, tricycle,\n"
    "                       mecanum, skid_steer, linear, gp)\n"
    "  --test BAG           score the models on this bag too (repeatable); prints the paper's\n"
    "                       comparison table for the model, the config's compare_models and\n"
    "                       the nominal robot (prior_model's start values, not fitted)\n"
    "  --start S, --end S   use only [S, E] seconds after the first message\n"
    "  --holdout F          hold out the pairs of the last fraction F (0 < F < 1) of the\n"
    "                       collection: fit on the others, score calibrated and nominal\n"
    "                       models on them\n"
    "  --interval T|auto    keyframe interval of the fitted pairs [s] (default: the config's\n"
    "                       keyframes.interval_s); auto: chosen among keyframes.\n"
    "                       fit_intervals_s (the default when set; else 0.3, 0.5, 1.0 s) by\n"
    "                       time-blocked cross-validation (the bags are paired once per\n"
    "                       interval); held-out and validation scores always use pairs at\n"
    "                       keyframes.interval_s\n"
    "  --quiet              no progress display\n"
    "  --single-thread      no matching thread: every match in the pairing thread (same\n"
    "                       results, slower)\n"
    "  --gnuplot PROGRAM    the plotting program (default: gnuplot from PATH; without it the\n"
    "                       report is written without images and says what is missing)\n"
    "\n"
    "exit status: 0 success; 1 bad input (message says what); 2 bad usage; 3 the fit did not\n"
    "converge; 4 the fit warns that some parameter is not determined, or that the time\n"
    "offset sits at the edge of its search range or is not observable\n";

/// The fitted pairs' interval: the configured one (no extra pass), a given one, or one chosen by
/// cross-validation (calibration/fit_interval.h) among keyframes.fit_intervals_s (when set, also
/// without --interval) or kAutoIntervals.
struct FitIntervalRun
{
  double interval_s = 0.0;                       ///< the fitted pairs' interval [s]
  std::optional<std::vector<MotionPair>> pairs;  ///< the fitted pairs; none: the evaluation ones
  std::optional<FitIntervalChoice> choice;       ///< the cross-validation, when it ran
  std::string text;                              ///< what was done, in words (empty: nothing)
};

const std::vector<double> kAutoIntervals = {0.3, 0.5, 1.0};

FitIntervalRun chooseBagFitInterval(const std::string& option, const std::vector<std::string>& bags,
                                    const CalibrationConfig& config, const BagRunResult& run,
                                    const std::vector<MotionPair>& evaluation, double border_s,
                                    double start_s, double end_s)
{
  FitIntervalRun result;
  const double configured = config.collector.keyframe_interval_s;
  result.interval_s = configured;
  const bool automatic = option == "auto" || (option.empty() && !config.fit_intervals_s.empty());
  if (option.empty() && !automatic)
    return result;
  const std::vector<double> intervals = !automatic ? std::vector<double>{std::stod(option)}
                                        : config.fit_intervals_s.empty() ? kAutoIntervals
                                                                         : config.fit_intervals_s;
  // The pairs of each candidate interval as collected (before any time-offset re-cut).
  std::vector<IntervalPairs> collected;
  for (const double interval : intervals) {
    IntervalPairs candidate{interval, {}};
    if (std::abs(interval - configured) < 1e-9) {
      candidate.pairs = evaluation;
    } else {
      CalibrationConfig at_interval = config;
      at_interval.collector.keyframe_interval_s = interval;
      candidate.pairs = pairsEndingBy(runBags(bags, at_interval, start_s, end_s).pairs, border_s);
    }
    collected.push_back(std::move(candidate));
  }
  if (!automatic) {
    result.interval_s = collected.front().interval_s;
    result.pairs = std::move(collected.front().pairs);
    char text[160];
    std::snprintf(text, sizeof(text), "fit interval T = %.2f s (--interval): %zu pairs\n",
                  result.interval_s, result.pairs->size());
    result.text = text;
    return result;
  }
  // The time offset belongs to the robot, not to T: found once on the evaluation pairs, then
  // every candidate is cut at it, so the cross-validation compares intervals only.
  std::vector<IntervalPairs> candidates = collected;
  std::vector<MotionPair> evaluation_at_offset = evaluation;
  if (config.estimate_time_offset) {
    CalibrationJobOptions offset_only;
    offset_only.compare_trajectories = false;
    const CalibrationJobResult offset_job =
        runCalibrationJob(config, evaluation, run.encoder_history, offset_only);
    evaluation_at_offset = offset_job.pairs;
    for (IntervalPairs& candidate : candidates) {
      candidate.pairs =
          rewindowPairs(candidate.pairs, run.encoder_history, offset_job.time_offset_s);
    }
  }
  result.choice = chooseFitInterval(config, candidates, evaluation_at_offset);
  for (IntervalPairs& candidate : collected) {
    if (candidate.interval_s == result.choice->interval_s) {
      result.interval_s = candidate.interval_s;
      result.pairs = std::move(candidate.pairs);  // the job re-cuts them at its own offset
    }
  }
  result.text = formatFitIntervalChoice(*result.choice, configured);
  return result;
}

void showProgress(const BagProgress& p)
{
  const double rate = p.elapsed_s > 0.0 ? p.messages / p.elapsed_s : 0.0;
  const double eta = p.fraction > 0.0 ? p.elapsed_s * (1.0 - p.fraction) / p.fraction : 0.0;
  std::fprintf(stderr, "\r%5.1f %%  %8.0f msg/s  ETA %5.1f s ", 100.0 * p.fraction, rate, eta);
  if (p.fraction >= 1.0)
    std::fprintf(stderr, "\n");
}

}  // namespace

int main(int argc, char** argv)
{
  google::InitGoogleLogging(argv[0]);
  // A corrupted bag index makes rosbag read outside its buffers: exit 1 naming the bag.
  containBagReadFaults();
  FLAGS_minloglevel = google::GLOG_FATAL;
  std::string config_path, output_dir, model_name, interval_option;
  GnuplotOptions gnuplot;
  std::vector<std::string> bags, test_bags;
  double start_s = 0.0, end_s = 0.0, holdout = 0.0;
  bool quiet = !isatty(STDERR_FILENO);
  bool single_thread = false;
  try {
    ArgumentParser parser;
    parser.option("--config", &config_path)
        .option("--output-dir", &output_dir)
        .option("--model", &model_name)
        .option("--gnuplot", &gnuplot.program)
        .repeatedOption("--test", &test_bags)
        .number("--start", &start_s, 0.0)
        .number("--end", &end_s, 0.0)
        .number("--holdout", &holdout, 0.0)
        .option("--interval", &interval_option)
        .flag("--quiet", &quiet)
        .flag("--single-thread", &single_thread)
        .positionals(&bags);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    if (config_path.empty() || bags.empty()) {
      throw std::invalid_argument("give --config and at least one bag");
    }
    if (end_s > 0.0 && end_s <= start_s) {
      throw std::invalid_argument("--end must come after --start");
    }
    if (!(holdout < 1.0)) {
      throw std::invalid_argument("option --holdout: expected a fraction in (0, 1)");
    }
    if (!model_name.empty())
      requireKnownModel(model_name, "--model");
    if (!interval_option.empty() && interval_option != "auto") {
      std::size_t used = 0;
      double interval = 0.0;
      try {
        interval = std::stod(interval_option, &used);
      } catch (const std::exception&) {
      }
      if (used != interval_option.size() || !(interval > 0.0) || !(interval <= 60.0)) {
        throw std::invalid_argument(
            "option --interval: expected 'auto' or a number of seconds "
            "in (0, 60], got '" +
            interval_option + "'");
      }
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    // With --model, the configuration as that model needs it (its joints resolved, checked).
    CalibrationConfig config = model_name.empty()
                                   ? loadCalibrationConfig(config_path)
                                   : configForModel(readTextFile(config_path, "the configuration"),
                                                    model_name, "", config_path);
    config.collector.background_matching = !single_thread;
    if (output_dir.empty())
      output_dir = config.output_directory;
    for (const std::string& bag : test_bags) {
      if (!std::filesystem::is_regular_file(bag)) {
        throw std::runtime_error("no test bag file '" + bag + "'");
      }
    }

    // Paired at the estimated time offset (a second pass when the configured one is off).
    OffsetPairing offset_pairing;
    const BagRunResult run = runBagsAtEstimatedOffset(
        bags, &config, start_s, end_s,
        quiet ? nullptr : std::function<void(const BagProgress&)>(showProgress), &offset_pairing);
    const std::string summary = formatBagRunSummary(run) + offset_pairing.text;
    std::cout << summary;

    PairHoldout holdout_split;
    if (holdout > 0.0) {
      holdout_split = holdOutLastPairs(run.pairs, holdout);
    }
    const std::vector<MotionPair>& evaluation_pairs =
        holdout > 0.0 ? holdout_split.training : run.pairs;
    const FitIntervalRun fit_interval = chooseBagFitInterval(
        interval_option, bags, config, run, evaluation_pairs,
        holdout > 0.0 ? holdout_split.border_stamp_s : INFINITY, start_s, end_s);
    CalibrationJobOptions job_options;
    if (!fit_interval.pairs && holdout <= 0.0)  // the very pairs the offset was searched on
      job_options.time_offset_search = offset_pairing.search;
    const CalibrationJobResult job =
        runCalibrationJob(config, fit_interval.pairs ? *fit_interval.pairs : evaluation_pairs,
                          run.encoder_history, job_options);
    std::string text = summary + fit_interval.text +
                       (job.time_offset ? formatTimeOffset(*job.time_offset) : "") + "\n" +
                       formatModelReport(job.report) + formatNominalComparison(job);
    ResultFiles files = resultFilesForJob(jointLayout(config), job, bags.front());
    if (fit_interval.choice) {
      for (const FitIntervalScore& score : fit_interval.choice->curve)
        files.plots.fit_interval_curve.emplace_back(score.interval_s, score.validation_rpe_m);
      files.plots.fit_interval_s = fit_interval.choice->interval_s;
      files.plots.fit_interval_evaluation_s = config.collector.keyframe_interval_s;
    }
    files.markdown.fit_interval_note = fit_interval.text;
    if (!test_bags.empty()) {
      CalibrationConfig test_config = config;
      test_config.collector.time_offset_s = job.time_offset_s;
      const BagRunResult test = runBags(test_bags, test_config, 0.0, 0.0);
      files.markdown.test_table =
          formatComparisonTable(scoreModelsOnTest(config, job, test.pairs, test.encoder_history));
      files.markdown.test_pairs = test.pairs.size();
      text += "\ntest bags: " + std::to_string(test.pairs.size()) + " pairs\n" +
              files.markdown.test_table;
    }
    if (holdout > 0.0) {
      const std::vector<ModelScore> scores =
          scoreHeldOut(config, job, holdout_split.test, run.encoder_history);
      files.markdown.holdout_table = formatComparisonTable(scores);
      char note[400];
      std::snprintf(note, sizeof(note),
                    "held out: the %zu pairs (T = %.2f s) after %.1f s (the last %.0f %% of the "
                    "collection), %zu fitted (T = %.2f s); calibrated: the fitted %s",
                    holdout_split.test.size(), config.collector.keyframe_interval_s,
                    holdout_split.border_stamp_s - run.pairs.front().start_stamp_s, 100.0 * holdout,
                    job.pairs.size(), fit_interval.interval_s, config.model.c_str());
      files.markdown.holdout_note = note;
      if (scores.size() > 1) {
        files.markdown.holdout_note +=
            ", nominal: the " + config.prior_model + " start values at time offset 0";
      }
      text += "\n" + files.markdown.holdout_note + "\n" + files.markdown.holdout_table;
    }
    char timing[300];
    std::snprintf(timing, sizeof(timing),
                  "time: reading %.3f s, scan conversion %.3f s, pairing %.3f s (thread time: "
                  "scan preparation %.3f s, matching %.3f s), fitting %.3f s\n",
                  run.read_time_s, run.conversion_time_s, run.pairing_time_s,
                  run.statistics.preparation_time_s, run.statistics.matching_time_s,
                  job.fit_time_s);
    text += timing;
    std::cout << text.substr(summary.size());

    // Everything succeeded: write the files together.
    files.text_report = text;
    files.gnuplot = gnuplot;
    files.markdown.bags = bags;
    files.markdown.data_span_s = run.bag_span_s;
    files.markdown.run_time_s = run.wall_time_s;
    files.markdown.statistics = run.statistics;
    files.markdown.collection_notes = bagRunNotes(run);
    const bool controller = !files.controller_yaml.empty();
    const ReportPlots plots = writeResultFiles(output_dir, std::move(files));
    std::cout << "\nwritten: " << output_dir << "/{" << kPairsFileName << ", " << kResultFileName
              << (controller ? std::string(", ") + kControllerFileName : "") << ", "
              << kTextReportFileName << ", " << kReportFileName << ", " << kPlotFolderName
              << "/}\nreport: " << output_dir << "/" << kReportFileName << "\n";
    if (!plots.problem.empty()) {
      std::cerr << "warning: the report has no plots or only some: " << plots.problem << "\n";
    }
    return calibrationExitStatus(job.report);
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
