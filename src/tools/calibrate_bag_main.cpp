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

#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/eval/trajectory_comparison.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/model_factory.h"
#include "odometry_calibration/report/result_files.h"
#include "odometry_calibration/ros/bag_runner.h"

namespace {

using namespace odometry_calibration;

const char* kUsage =
    "usage: calibrate_bag --config CONFIG.yaml BAG [BAG ...] [options]\n"
    "\n"
    "Reads the bags in timestamp order with the rosbag API, makes keyframe pairs (PLICP scan\n"
    "matching, or the configured ego-motion topic), fits the configured model and writes\n"
    "pairs.csv, result.yaml, report.txt and report.md (the report with plots in plots/, drawn\n"
    "by gnuplot) to the output directory.\n"
    "\n"
    "options:\n"
    "  --output-dir DIR     where to write (default: the config's output_directory)\n"
    "  --model NAME         fit this model instead of the config's (diff_drive, tricycle,\n"
    "                       linear, gp)\n"
    "  --test BAG           score the models on this bag too (repeatable); prints the paper's\n"
    "                       comparison table for the model and the config's compare_models\n"
    "  --start S, --end S   use only [S, E] seconds after the first message\n"
    "  --quiet              no progress display\n"
    "  --single-thread      no matching thread: every match in the pairing thread (same\n"
    "                       results, slower)\n"
    "  --gnuplot PROGRAM    the plotting program (default: gnuplot from PATH; without it the\n"
    "                       report is written without images and says what is missing)\n"
    "\n"
    "exit status: 0 success; 1 bad input (message says what); 2 bad usage; 3 the fit did not\n"
    "converge; 4 the fit warns that some parameter is not determined, or that the time\n"
    "offset sits at the edge of its search range or is not observable\n";

void showProgress(const BagProgress& p)
{
  const double rate = p.elapsed_s > 0.0 ? p.messages / p.elapsed_s : 0.0;
  const double eta = p.fraction > 0.0 ? p.elapsed_s * (1.0 - p.fraction) / p.fraction : 0.0;
  std::fprintf(stderr, "\r%5.1f %%  %8.0f msg/s  ETA %5.1f s ", 100.0 * p.fraction, rate, eta);
  if (p.fraction >= 1.0)
    std::fprintf(stderr, "\n");
}

std::string runSummary(const BagRunResult& run)
{
  std::ostringstream text;
  text << "bags: " << run.bag_span_s << " s of data in " << run.wall_time_s << " s ("
       << (run.wall_time_s > 0 ? run.bag_span_s / run.wall_time_s : 0.0) << "x real time; reading "
       << run.read_time_s << " s, conversion " << run.conversion_time_s << " s, pairing "
       << run.pairing_time_s << " s)\n";
  const CollectorStatistics& s = run.statistics;
  text << "keyframe pairs: " << s.pairs << " from " << s.scans << " scans, " << s.keyframes
       << " keyframes";
  if (s.consecutive_matches > 0) {
    text << ", " << s.consecutive_failures << " of " << s.consecutive_matches
         << " consecutive matches failed, " << s.unverified_pairs << " pairs unverified";
  }
  text << "\n";
  for (const auto& [reason, count] : s.rejected) {
    text << "  rejected " << count << ": " << reason << "\n";
  }
  if (run.bad_joint_states > 0) {
    text << "skipped " << run.bad_joint_states
         << " JointState messages, first: " << run.first_bad_joint_state << "\n";
  }
  for (const std::string& restart : run.restarts)
    text << "restart " << restart << "\n";
  return text.str();
}

}  // namespace

int main(int argc, char** argv)
{
  google::InitGoogleLogging(argv[0]);
  FLAGS_minloglevel = google::GLOG_FATAL;
  std::string config_path, output_dir, model_name;
  GnuplotOptions gnuplot;
  std::vector<std::string> bags, test_bags;
  double start_s = 0.0, end_s = 0.0;
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
    if (!model_name.empty())
      requireKnownModel(model_name, "--model");
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

    const BagRunResult run =
        runBags(bags, config, start_s, end_s,
                quiet ? nullptr : std::function<void(const BagProgress&)>(showProgress));
    const std::string summary = runSummary(run);
    std::cout << summary;

    const auto fit_start = std::chrono::steady_clock::now();
    std::vector<MotionPair> pairs = run.pairs;
    std::string offset_text;
    std::vector<std::string> offset_warnings;
    std::optional<TimeOffsetResult> offset;
    double time_offset_s = config.collector.time_offset_s;
    if (config.estimate_time_offset) {
      if (run.encoder_history.empty()) {
        throw std::runtime_error(
            "time offset estimation needs one continuous encoder stream "
            "(the bags went back in time)");
      }
      TimeOffsetOptions search;
      search.min_s = config.time_offset_search_min_s;
      search.max_s = config.time_offset_search_max_s;
      offset = estimateTimeOffset(
          run.pairs, run.encoder_history, [&]() { return makeModel(config.model, config.models); },
          search);
      if (offset->flat) {
        offset_warnings.push_back(
            "the time offset is not observable from this drive (flat cost curve): kept the "
            "configured " +
            std::to_string(time_offset_s) + " s");
      } else {
        time_offset_s = offset->offset_s;
        if (offset->at_boundary) {
          offset_warnings.push_back("the time offset estimate " + std::to_string(time_offset_s) +
                                    " s lies at the edge of time_offset_search_s: widen it");
        }
      }
      pairs = rewindowPairs(run.pairs, run.encoder_history, time_offset_s);
      std::ostringstream out;
      out << "time offset (encoder values at scan time + tau): tau = " << offset->offset_s
          << " s +- " << offset->sigma_s << " s"
          << (offset->at_boundary ? "  WARNING: at the edge of the search range" : "")
          << "\ncost curve (tau [s], trimmed mean chi^2):";
      for (const auto& [tau, cost] : offset->curve)
        out << " " << tau << ":" << cost;
      offset_text = out.str() + "\n";
    }
    auto model = makeModel(config.model, config.models);
    ModelReport report = model->fit(pairs);
    report.warnings.insert(report.warnings.end(), offset_warnings.begin(), offset_warnings.end());
    const double fit_time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - fit_start).count();
    std::string text = summary + offset_text + "\n" + formatModelReport(report);

    // The evidence: the calibrated model against the scan matches, and the nominal robot (the
    // prior's start values, no time offset) when there is one.
    ResultFiles files;
    const std::shared_ptr<MotionModel> nominal = priorModel(config);
    std::vector<MotionPair> nominal_pairs;
    if (nominal) {
      nominal_pairs = run.encoder_history.empty()
                          ? run.pairs
                          : rewindowPairs(run.pairs, run.encoder_history, 0.0);
      files.markdown.nominal_description =
          "the " + config.prior_model + " start values of the configuration at time offset 0";
    }
    files.markdown.trajectories = compareTrajectories(pairs, *model, nominal_pairs, nominal.get());
    if (nominal && !run.encoder_history.empty()) {
      char line[200];
      std::snprintf(line, sizeof(line),
                    "median per-pair RPE vs the matched displacements: nominal (start values, "
                    "no time offset) %.4f m -> calibrated %.4f m\n",
                    median(translationErrors(files.markdown.trajectories.nominal_errors)),
                    median(translationErrors(files.markdown.trajectories.calibrated_errors)));
      text += line;
    }
    if (!test_bags.empty()) {
      CalibrationConfig test_config = config;
      test_config.collector.time_offset_s = time_offset_s;
      const BagRunResult test = runBags(test_bags, test_config, 0.0, 0.0);
      std::vector<ModelScore> scores;
      std::vector<std::string> names = {config.model};
      for (const std::string& name : config.compare_models) {
        if (name != config.model)
          names.push_back(name);
      }
      for (const std::string& name : names) {
        auto candidate = name == config.model ? std::move(model) : makeModel(name, config.models);
        const ModelReport fitted = name == config.model ? report : candidate->fit(pairs);
        ModelScore score = scoreModel(*candidate, test.pairs);
        score.fit_time_s = fitted.fit_time_s;
        score.outliers = fitted.outliers;
        scores.push_back(score);
        if (name == config.model)
          model = std::move(candidate);
      }
      files.markdown.test_table = formatComparisonTable(scores);
      files.markdown.test_pairs = test.pairs.size();
      text += "\ntest bags: " + std::to_string(test.pairs.size()) + " pairs\n" +
              files.markdown.test_table;
    }
    char timing[300];
    std::snprintf(timing, sizeof(timing),
                  "time: reading %.3f s, scan conversion %.3f s, pairing %.3f s (thread time: "
                  "scan preparation %.3f s, matching %.3f s), fitting %.3f s\n",
                  run.read_time_s, run.conversion_time_s, run.pairing_time_s,
                  run.statistics.preparation_time_s, run.statistics.matching_time_s, fit_time_s);
    text += timing;
    std::cout << text.substr(summary.size());

    // Everything succeeded: write the files together.
    files.pairs = {jointLayout(config), pairs};
    files.result_yaml = modelResultYaml(report, model->toYaml(), bags.front()) +
                        "time_offset_s: " + std::to_string(time_offset_s) + "\n";
    files.text_report = text;
    files.plots.trajectories = files.markdown.trajectories;
    files.plots.calibrated_label = report.model;
    if (offset) {
      files.plots.time_offset_curve = offset->curve;
      files.plots.time_offset_s = offset->offset_s;
      files.plots.time_offset_sigma_s = offset->sigma_s;
    }
    files.gnuplot = gnuplot;
    files.markdown.bags = bags;
    files.markdown.data_span_s = run.bag_span_s;
    files.markdown.run_time_s = run.wall_time_s;
    files.markdown.statistics = run.statistics;
    if (run.bad_joint_states > 0) {
      files.markdown.collection_notes.push_back(
          "skipped " + std::to_string(run.bad_joint_states) +
          " JointState messages, first: " + run.first_bad_joint_state);
    }
    for (const std::string& restart : run.restarts)
      files.markdown.collection_notes.push_back("restart " + restart);
    files.markdown.report = report;
    files.markdown.time_offset = offset;
    files.markdown.time_offset_used_s = time_offset_s;
    const ReportPlots plots = writeResultFiles(output_dir, std::move(files));
    std::cout << "\nwritten: " << output_dir << "/{" << kPairsFileName << ", " << kResultFileName
              << ", " << kTextReportFileName << ", " << kReportFileName << ", " << kPlotFolderName
              << "/}\nreport: " << output_dir << "/" << kReportFileName << "\n";
    if (!plots.problem.empty()) {
      std::cerr << "warning: the report has no plots or only some: " << plots.problem << "\n";
    }
    if (!report.converged)
      return 3;
    return report.warnings.empty() ? 0 : 4;
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
