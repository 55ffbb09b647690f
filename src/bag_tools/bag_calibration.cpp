#include "odometry_calibration/bag_tools/bag_calibration.h"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/config/calibration_config_schema.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/eval/joint_fit_text.h"
#include "odometry_calibration/eval/model_adequacy.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/eval/tum_trajectory.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/report/result_files.h"

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

/// The session's fit of the run's pairs (one source; paired again at the estimated time offset
/// when the configured one is off: the run then takes those pairs, counts and history), and the
/// gyro's against them into `gyro` (with gyro.topic); throws when none could run.
SessionFit fitRun(BagRunResult* run, const IntervalPlan& plan, double holdout,
                  std::optional<GyroFit>* gyro)
{
  CalibrationRequest request;
  request.interval_mode = plan.mode;
  request.fixed_interval_s = plan.fixed_s;
  if (holdout > 0.0)
    request.holdout_fraction = holdout;
  JointCalibrateOutcome joint = run->session->calibrate(request);
  *gyro = joint.gyro;
  CalibrateOutcome& outcome = joint.outcome;
  const CalibrationSession& session = run->session->source(0);
  run->pairs = session.pairs();
  run->encoder_history = session.encoderHistory();
  run->counts = session.counts();
  if (!outcome.fit)
    throw std::runtime_error(outcome.message);
  return std::move(*outcome.fit);
}

/// The scored rows' TUM trajectories into `folder`/ of the trajectory folder. Pairs whose stamps
/// do not increase (test bags recorded out of order) have no TUM file: said on stderr, the run
/// goes on.
void addTrajectories(const std::string& folder, const std::vector<ModelScore>& scores,
                     ResultFiles* files)
{
  try {
    for (auto& [name, content] : tumTrajectoryFiles(scores))
      files->trajectories.emplace_back(folder + "/" + name, std::move(content));
  } catch (const std::invalid_argument& error) {
    std::fprintf(stderr, "warning: no trajectories/%s/: %s\n", folder.c_str(), error.what());
  }
}

/// The scores on the test bags (paired at the fitted time offset): text and report table.
std::string scoreTestBags(const BagCalibrationOptions& options, const CalibrationConfig& config,
                          const CalibrationJobResult& job, ResultFiles* files,
                          std::vector<ModelScore>* scored)
{
  CalibrationConfig test_config = config;
  test_config.collector.time_offset_s = job.time_offset_s;
  test_config.estimate_time_offset = false;  // paired at the fitted offset: nothing to record
  const BagRunResult test = runBags(options.test_bags, test_config, 0.0, 0.0);
  const std::vector<ModelScore> scores =
      scoreModelsOnTest(config, job, test.pairs, test.encoder_history);
  files->markdown.test_table =
      formatComparisonTable(scores) + formatBestModel(scores, "the test bags");
  files->markdown.test_pairs = test.pairs.size();
  addTrajectories("test", scores, files);
  *scored = scores;
  return "\ntest bags: " + std::to_string(test.pairs.size()) + " pairs\n" +
         files->markdown.test_table;
}

/// The scores on the held-out pairs: text and report table.
std::string scoreHoldout(const BagCalibrationOptions& options, const CalibrationConfig& config,
                         const BagRunResult& run, const PairHoldout& split, const SessionFit& fit,
                         ResultFiles* files, std::vector<ModelScore>* scored)
{
  const std::vector<ModelScore> scores =
      scoreHeldOut(config, fit.job, split.test, run.encoder_history);
  files->markdown.holdout_table =
      formatComparisonTable(scores) + formatBestModel(scores, "the held-out pairs");
  addTrajectories("holdout", scores, files);
  *scored = scores;
  char note[400];
  std::snprintf(
      note, sizeof(note),
      "held out: the %zu pairs (T = %.2f s) after %.1f s (the last %.0f %% of the "
      "collection), %zu fitted (T = %.2f s): %s and every model of compare_models fitted to "
      "them",
      split.test.size(), config.collector.keyframe_interval_s,
      split.border_stamp_s - run.pairs.front().start_stamp_s, 100.0 * options.holdout,
      fit.job.pairs.size(), fit.fit_interval_s, config.model.c_str());
  files->markdown.holdout_note = note;
  if (!scores.empty() && scores.back().model == "nominal")
    files->markdown.holdout_note +=
        ", nominal: the " + config.prior_model + " start values at time offset 0";
  return "\n" + files->markdown.holdout_note + "\n" + files->markdown.holdout_table;
}

/// The adequacy check of a parametric fit (eval/model_adequacy.h) with its advice from
/// `scores`, a comparison on `where`; empty for a model-free fit.
std::string adequacyText(const CalibrationConfig& config, const CalibrationJobResult& job,
                         const std::vector<ModelScore>& scores, const std::string& where)
{
  if (job.report.parameters.empty())
    return "";
  const AdequacyCheck check = checkModelAdequacy(*job.model, job.pairs);
  return "\n" + check.text + adequacyAdvice(check, config.model, scores, where);
}

std::string timingLine(const BagRunResult& run, const SessionFit& fit)
{
  char timing[300];
  std::snprintf(timing, sizeof(timing),
                "time: reading %.3f s, scan conversion %.3f s, pairing %.3f s (thread time: "
                "scan preparation %.3f s, matching %.3f s), fitting %.3f s\n",
                run.read_time_s, run.conversion_time_s, run.pairing_time_s,
                run.counts.statistics.preparation_time_s, run.counts.statistics.matching_time_s,
                fit.job.fit_time_s);
  return timing;
}

/// The report's data of source `source`'s run and of its fit-interval choice.
void describeRun(const BagCalibrationOptions& options, const CalibrationConfig& config,
                 const BagRunResult& run, std::size_t source, const SessionFit& fit,
                 ResultFiles* files)
{
  if (fit.choice) {
    for (const FitIntervalScore& score : fit.choice->curve)
      files->plots.fit_interval_curve.emplace_back(score.interval_s, score.validation_error_m);
    files->plots.fit_interval_s = fit.choice->interval_s;
    files->plots.fit_interval_evaluation_s = config.collector.keyframe_interval_s;
    files->plots.fit_interval_criterion = criterionName(fit.choice->criterion);
  }
  files->markdown.fit_interval_note = fit.interval_text.empty() ? "" : fit.interval_text + "\n";
  files->gnuplot = options.gnuplot;
  files->markdown.bags = options.bags;
  files->markdown.data_span_s = run.bag_span_s;
  files->markdown.run_time_s = run.wall_time_s;
  files->markdown.statistics = run.session->source(source).counts().statistics;
  files->markdown.collection_notes = run.session->source(source).collectionNotes();
}

/// The files of source `source`'s fit `fit` (its report's data too), `text` its terminal text.
ResultFiles runFiles(const BagCalibrationOptions& options, const CalibrationConfig& config,
                     const BagRunResult& run, std::size_t source, const SessionFit& fit,
                     const std::string& text)
{
  const CalibrationConfig source_config = configForSource(config, source);
  ResultFiles files =
      resultFilesForJob(jointLayout(source_config), fit.job, fit.fit_interval_s,
                        options.bags.front(), run.session->source(source).sensorFrame());
  describeRun(options, source_config, run, source, fit, &files);
  if (fit.choice) {
    appendToResult(&files.calibration,
                   fitIntervalChoiceYaml(*fit.choice, source_config.collector.keyframe_interval_s));
  }
  files.text_report = text;
  return files;
}

/// result.yaml's `scores:` of the test bags' and the held-out pairs' tables (either may be
/// empty: not scored).
void appendScores(const std::vector<ModelScore>& test_scores, std::size_t test_pairs,
                  const std::vector<ModelScore>& held_out_scores, const std::string& held_out_note,
                  ResultFiles* files)
{
  std::vector<ResultScores> sets;
  if (!test_scores.empty())
    sets.push_back(
        {"test", "the " + std::to_string(test_pairs) + " pairs of the test bags", test_scores});
  if (!held_out_scores.empty())
    sets.push_back({"held_out", held_out_note, held_out_scores});
  appendToResult(&files->calibration, scoresYaml(sets));
}

/// "written: <output_dir>/{a, b/}" and where the report is.
void sayWritten(const std::string& output_dir, const std::vector<std::string>& names,
                std::ostream& out)
{
  out << "\nwritten: " << output_dir << "/{";
  for (std::size_t k = 0; k < names.size(); ++k) {
    const bool folder = names[k] == kPlotFolderName || names[k] == kTrajectoryFolderName ||
                        names[k].rfind("source_", 0) == 0;
    out << (k == 0 ? "" : ", ") << names[k] << (folder ? "/" : "");
  }
  out << "}\n";
}

void writeFiles(const std::string& output_dir, ResultFiles files, std::ostream& out)
{
  std::vector<std::string> names = {kPairsFileName};
  for (const auto& [name, content] : files.calibration.written)
    names.push_back(name);
  names.insert(names.end(), {kTextReportFileName, kReportFileName, kPlotFolderName});
  if (!files.trajectories.empty())
    names.push_back(kTrajectoryFolderName);
  const ReportPlots plots = writeResultFiles(output_dir, std::move(files));
  sayWritten(output_dir, names, out);
  out << "report: " << output_dir << "/" << kReportFileName << "\n";
  if (!plots.problem.empty())
    std::fprintf(stderr, "warning: the report has no plots or only some: %s\n",
                 plots.problem.c_str());
}

/// The options a run of several sources does not take (it fits every source's pairs at its own
/// fit interval and tests nothing): named, so that none is silently ignored; the model must
/// have a joint fit.
void refuseSingleSourceOptions(const BagCalibrationOptions& options,
                               const CalibrationConfig& config)
{
  if (const std::string problem = jointFitModelProblem(config.model); !problem.empty())
    throw std::runtime_error(problem);
  const char* option = !options.test_bags.empty()  ? "--test"
                       : options.holdout > 0.0     ? "--holdout"
                       : !options.interval.empty() ? "--interval"
                                                   : nullptr;
  if (option) {
    throw std::invalid_argument(
        std::string("option ") + option +
        " is not supported with several ego-motion sources (ego_motion.sources): calibrate one "
        "source at a time with a one-source configuration to use it");
  }
}

/// Source `k`'s run and fit alone in words.
std::string describeSource(const CalibrationConfig& config, const BagRunResult& run, std::size_t k,
                           const SessionFit& fit)
{
  const CalibrationJobResult& job = fit.job;
  return "\n=== source " + std::to_string(k) + ": " + egoMotionSources(config)[k].topic + " ===\n" +
         formatBagRunSummary(run, run.session->source(k).counts(),
                             run.session->source(k).collectionNotes()) +
         fit.offset_pairing.text + (job.time_offset ? formatTimeOffset(*job.time_offset) : "") +
         "\n" + formatModelReport(job.report);
}

/// Each file the run read only in part named on stderr (the text report says it too), so that
/// no result from part of a recording goes unnoticed.
void warnOfPartialReads(const BagRunResult& run)
{
  for (const std::string& partial : run.partial_reads)
    std::fprintf(stderr, "warning: %s\n", partial.c_str());
}

/// calibrateBags with one ego-motion source.
int calibrateOneSource(const BagCalibrationOptions& options, CalibrationConfig config,
                       std::ostream& out)
{
  const std::string output_dir =
      options.output_dir.empty() ? config.output_directory : options.output_dir;
  const IntervalPlan plan = planIntervals(options.interval, config);
  BagRunResult run =
      runBags(options.bags, config, options.start_s, options.end_s,
              options.quiet ? nullptr : std::function<void(const BagProgress&)>(showProgress),
              plan.candidates_s);
  warnOfPartialReads(run);
  // Fitted at the estimated time offset (paired again when the configured one is off).
  std::optional<GyroFit> gyro;
  const SessionFit fit = fitRun(&run, plan, options.holdout, &gyro);
  if (fit.offset_pairing.paired_again)
    config.collector.time_offset_s = fit.offset_pairing.estimate_s;
  const std::string summary =
      formatBagRunSummary(run, run.counts, run.session->source(0).collectionNotes()) +
      fit.offset_pairing.text;
  out << summary;
  const PairHoldout split =
      options.holdout > 0.0 ? holdOutLastPairs(run.pairs, options.holdout) : PairHoldout();
  const CalibrationJobResult& job = fit.job;
  std::string text = summary + (fit.interval_text.empty() ? "" : fit.interval_text + "\n") +
                     (job.time_offset ? formatTimeOffset(*job.time_offset) : "") + "\n" +
                     formatModelReport(job.report) + formatNominalComparison(job);
  ResultFiles files = runFiles(options, config, run, 0, fit, "");
  if (gyro) {
    text += "\n" + gyroFitText(*gyro) + "\n";
    appendGyroResult(&files.calibration, *gyro, config.gyro.topic);
  }
  std::vector<ModelScore> test_scores, held_out_scores;
  if (!options.test_bags.empty())
    text += scoreTestBags(options, config, job, &files, &test_scores);
  if (options.holdout > 0.0)
    text += scoreHoldout(options, config, run, split, fit, &files, &held_out_scores);
  appendScores(test_scores, files.markdown.test_pairs, held_out_scores, files.markdown.holdout_note,
               &files);
  text += adequacyText(config, job, held_out_scores.empty() ? test_scores : held_out_scores,
                       held_out_scores.empty() ? "the test bags" : "the held-out pairs");
  text += timingLine(run, fit);
  out << text.substr(summary.size());
  // Everything succeeded: write the files together.
  files.text_report = text;
  writeFiles(output_dir, std::move(files), out);
  return calibrationExitStatus(job);
}

/// calibrateBags with several ego-motion sources.
int calibrateSeveralSources(const BagCalibrationOptions& options, const CalibrationConfig& config,
                            std::ostream& out, const JointFitFunction& fit_jointly)
{
  refuseSingleSourceOptions(options, config);
  if (!config.compare_models.empty()) {
    out << "note: compare_models is not fitted with several ego-motion sources (the joint fit is "
           "of "
        << config.model << " only)\n";
  }
  const std::string output_dir =
      options.output_dir.empty() ? config.output_directory : options.output_dir;
  const BagRunResult run = runBags(options.bags, config, options.start_s, options.end_s, nullptr,
                                   config.fit_intervals_s, fit_jointly);
  warnOfPartialReads(run);
  const JointCalibrateOutcome outcome = run.session->calibrate({});
  if (outcome.alone.size() != run.session->sourceCount())  // a source could not be fitted alone
    throw std::runtime_error(outcome.outcome.message);
  std::vector<ResultFiles> sources;
  std::string text;
  for (std::size_t k = 0; k < outcome.alone.size(); ++k) {
    const std::string source_text = describeSource(config, run, k, outcome.alone[k]);
    text += source_text;
    sources.push_back(runFiles(options, config, run, k, outcome.alone[k], source_text));
  }
  FileSet joint_files;
  std::string failure = outcome.joint ? "" : outcome.joint_failure;
  int status = 0;
  if (outcome.joint) {
    try {  // the joint table joins the text only once its files are made
      const std::string joint_text = text + "\n=== joint fit ===\n" + outcome.text +
                                     (outcome.gyro ? gyroFitText(*outcome.gyro) + "\n" : "");
      joint_files = jointCalibrationFiles(config, *outcome.joint, outcome.inputs,
                                          options.bags.front(), "base_link", joint_text);
      if (outcome.gyro)
        appendGyroResult(&joint_files, *outcome.gyro, config.gyro.topic);
      text = joint_text;
      for (std::size_t k = 0; k < outcome.joint->sensors.size(); ++k)
        status = std::max(status, calibrationExitStatus(sensorModelReport(*outcome.joint, k)));
    } catch (const std::exception& error) {
      failure = error.what();
    }
  }
  if (!failure.empty()) {  // every source's fit alone is still written
    failure =
        "the joint " + config.model + " fit failed after every source was fitted alone: " + failure;
    text += "\n=== joint fit ===\n" + failure + "\n";
    joint_files = failedJointCalibrationFiles(text);
  }
  out << text;
  sayWritten(output_dir, writeJointResultFiles(output_dir, joint_files, std::move(sources)), out);
  if (!failure.empty()) {
    throw std::runtime_error(failure + " (each source's fit alone is in " + output_dir +
                             "/source_<k>/; no joint result.yaml)");
  }
  return status;
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

int calibrateBags(const BagCalibrationOptions& options, std::ostream& out,
                  const JointFitFunction& fit_jointly)
{
  const CalibrationConfig config = loadConfig(options);
  if (options.print_config) {
    out << formatEffectiveConfig(config);
    return 0;
  }
  if (config.ego_motion_sources.size() > 1)
    return calibrateSeveralSources(options, config, out, fit_jointly);
  return calibrateOneSource(options, config, out);
}

}  // namespace odometry_calibration
