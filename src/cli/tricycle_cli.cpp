#include "odometry_calibration/cli/tricycle_cli.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <utility>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/cli/tricycle_report.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "odometry_calibration/models/tricycle_model.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {
namespace {

/// The interval when the drive is too short to choose one (or the candidate nearest it) [s].
constexpr double kFallbackIntervalS = 0.5;

}  // namespace

std::string tricycleCliUsage()
{
  return "usage: calibrate_tricycle DATASET [options]\n"
         "\n"
         "Calibrates a front-wheel-drive tricycle (Ksteer, Ktraction, axis_length, steer_offset)\n"
         "and its sensor's pose on base_link from a log in the tricycle dataset format, starting\n"
         "from the nominal values in the log's header. Prints a report, writes a YAML result.\n"
         "\n"
         "options:\n"
         "  --output PATH            result YAML (result.yaml's keys, the interval's choice and\n"
         "                           the scores), written atomically (default\n"
         "                           tricycle_calibration.yaml; '' to skip)\n"
         "  --interval S|auto        keyframe spacing T [s]; auto (default): chosen by\n"
         "                           time-blocked cross-validation among the candidates\n"
         "  --interval-candidates L  comma-separated candidate T [s] of auto (default\n"
         "                           0.25,0.35,0.5,0.7,1,1.4,2,2.8,4,5.6,8)\n"
         "  --folds N,M,...          cuts of the cross-validation into N, M, ... time blocks\n"
         "                           (default 2,3,4,5,6)\n"
         "  --holdout F              hold out the last fraction F of the samples (0 < F < 1):\n"
         "                           fit on the rest, report the errors on them (default: none)\n"
         "  --translation-sigma M    assumed sigma of a measured displacement's x, y [m]\n"
         "                           (default 0.01)\n"
         "  --rotation-sigma RAD     assumed sigma of a measured heading change [rad]\n"
         "                           (default 0.01)\n"
         "  --huber K                Huber threshold [sigma] (default 3; 0 = plain least squares)\n"
         "  --max-iterations N       solver iteration cap per solve (default 500)\n"
         "  -h, --help               this text\n"
         "\n"
         "exit status: 0 success; 1 bad input; 2 bad usage; 3 the solver did not converge;\n"
         "4 the fit converged but the report warns that some parameter is not determined by\n"
         "this drive (see WARNINGS): the YAML is written, do not use those numbers blindly\n";
}

namespace {

/// --interval (a number > 0, or auto), --interval-candidates and --folds (whole numbers in
/// [2, 100]) into the options, checked together.
void setIntervalOptions(const std::string& interval, const std::vector<std::string>& candidates,
                        const std::vector<std::string>& folds, TricycleCliOptions& options)
{
  if (interval != "auto") {
    options.keyframe_interval_s = parseNumberArgument("--interval", interval);
    if (!(options.keyframe_interval_s > 0.0)) {
      throw ArgumentError("option --interval: the keyframe spacing must be > 0 s (or auto)");
    }
  }
  if (!candidates.empty()) {
    options.interval_selection.candidates_s.clear();
    for (const std::string& candidate : candidates) {
      options.interval_selection.candidates_s.push_back(
          parseNumberArgument("--interval-candidates", candidate));
    }
  }
  if (!folds.empty()) {
    options.interval_selection.fold_counts.clear();
    for (const std::string& count : folds) {
      const double value = parseNumberArgument("--folds", count, 2.0);
      if (value > 100 || std::floor(value) != value) {
        throw ArgumentError("option --folds: expected whole numbers in [2, 100], got '" + count +
                            "'");
      }
      options.interval_selection.fold_counts.push_back(static_cast<std::size_t>(value));
    }
  }
  const std::vector<double>& candidates_s = options.interval_selection.candidates_s;
  for (std::size_t i = 0; i < candidates_s.size(); ++i) {
    if (!(candidates_s[i] > 0.0) || !std::isfinite(candidates_s[i]) ||
        (i > 0 && !(candidates_s[i] > candidates_s[i - 1]))) {
      throw ArgumentError(
          "option --interval-candidates: candidate intervals must be increasing numbers > 0 s");
    }
  }
}

/// Refuses a holdout share outside [0, 1), sigmas not > 0, a negative Huber threshold and an
/// iteration cap that is not a whole number in [1, 1e6]; sets the cap.
void setFitOptions(double max_iterations, TricycleCliOptions& options)
{
  if (!(options.holdout_fraction >= 0.0 && options.holdout_fraction < 1.0)) {
    throw ArgumentError("option --holdout: expected a fraction in (0, 1) (0 = none)");
  }
  if (!(options.calibration.translation_sigma_m > 0.0)) {
    throw ArgumentError("option --translation-sigma: expected a standard deviation > 0 m");
  }
  if (!(options.calibration.rotation_sigma_rad > 0.0)) {
    throw ArgumentError("option --rotation-sigma: expected a standard deviation > 0 rad");
  }
  if (options.calibration.huber_threshold < 0.0) {
    throw ArgumentError("option --huber: expected a threshold >= 0 (0 = no robust loss)");
  }
  if (max_iterations < 1 || max_iterations > 1e6 || std::floor(max_iterations) != max_iterations) {
    throw ArgumentError("option --max-iterations: expected a whole number in [1, 1e6]");
  }
  options.calibration.max_iterations = static_cast<int>(max_iterations);
}

}  // namespace

TricycleCliOptions parseTricycleCliArguments(const std::vector<std::string>& arguments)
{
  TricycleCliOptions options;
  std::vector<std::string> datasets;
  double max_iterations = options.calibration.max_iterations;
  std::string interval = "auto";
  std::vector<std::string> candidates;
  std::vector<std::string> folds;
  ArgumentParser parser;
  parser.option("--output", &options.output_path)
      .option("--interval", &interval)
      .listOption("--interval-candidates", &candidates)
      .listOption("--folds", &folds)
      .number("--holdout", &options.holdout_fraction)
      .number("--translation-sigma", &options.calibration.translation_sigma_m)
      .number("--rotation-sigma", &options.calibration.rotation_sigma_rad)
      .number("--huber", &options.calibration.huber_threshold)
      .number("--max-iterations", &max_iterations)
      .positionals(&datasets);
  if (!parser.parse(arguments)) {
    options.help = true;
    return options;
  }
  setIntervalOptions(interval, candidates, folds, options);
  setFitOptions(max_iterations, options);
  if (datasets.empty()) {
    throw ArgumentError("missing the dataset file");
  }
  if (datasets.size() > 1) {
    throw ArgumentError("only one dataset file is accepted, got '" + datasets[0] + "' and '" +
                        datasets[1] + "'");
  }
  options.dataset_path = datasets[0];
  try {
    validate(options.calibration);
  } catch (const std::invalid_argument& error) {
    throw ArgumentError(error.what());
  }
  return options;
}

namespace {

/// The session's configuration of a tracker log (docs/models.md, "The tricycle"): the log's two
/// joints as its header describes them (the steering an absolute angle, the traction a 32-bit
/// counter; the glitch filter, made for a live publisher's bugs, off: on the real log it takes
/// traction readings for glitches and loses pairs), the tracker's poses as the sensor's
/// (`ego_motion.source: pose`, with the fit's sigmas), no time offset (encoders and poses share
/// each row's stamp), and the keyframes at the shortest candidate (the evaluation pairs every
/// interval is scored on) with the others as fit-interval candidates, or with the one interval
/// given (the keyframes at it when it is shorter).
CalibrationConfig trackerLogConfig(const TricycleEncoderLayout& layout,
                                   const TricycleParameters& nominal,
                                   const TricycleCliOptions& options)
{
  CalibrationConfig config;
  config.model = "tricycle";
  config.prior_model = "tricycle";
  config.ego_motion = EgoMotionSource::kPose;
  config.ego_motion_topic = "tracker";
  config.ego_motion_sigma_m = options.calibration.translation_sigma_m;
  config.ego_motion_sigma_rad = options.calibration.rotation_sigma_rad;
  config.estimate_time_offset = false;
  config.output_directory.clear();
  const auto steering = static_cast<std::size_t>(layout.steering_index);
  const auto traction = static_cast<std::size_t>(layout.traction_index);
  config.joints.resize(2);
  config.joints[steering] = {
      "steering", EncoderKind::kAbsolute, layout.steering_ticks_per_turn, 0, 0.0, 1.0};
  config.joints[traction] = {
      "traction", EncoderKind::kIncremental, layout.traction_ticks_per_turn, 32, 0.0, 1.0};
  for (const JointConfig& joint : config.joints) {
    config.models.joints.names.push_back(joint.name);
    config.models.joints.kinds.push_back(joint.kind);
  }
  config.models.tricycle.layout = layout;
  config.models.tricycle.initial = nominal;
  config.models.tricycle.calibration = options.calibration;
  const std::vector<double>& candidates_s = options.interval_selection.candidates_s;
  const double given_s = options.keyframe_interval_s;
  config.collector.keyframe_interval_s =
      given_s > 0.0 ? std::min(given_s, candidates_s.front()) : candidates_s.front();
  if (given_s > config.collector.keyframe_interval_s)
    config.fit_intervals_s = {given_s};
  else if (!(given_s > 0.0))
    config.fit_intervals_s.assign(candidates_s.begin() + 1, candidates_s.end());
  return config;
}

/// How the session finds the fitted pairs' interval: chosen among the candidates, or the one
/// given (the keyframes' own, or the one other collected).
void setIntervalMode(const CalibrationConfig& config, const TricycleCliOptions& options,
                     CalibrationRequest* request)
{
  request->fold_counts = options.interval_selection.fold_counts;
  if (!(options.keyframe_interval_s > 0.0)) {
    request->interval_mode = FitIntervalMode::kChoose;
  } else if (config.fit_intervals_s.empty()) {
    request->interval_mode = FitIntervalMode::kConfigured;
  } else {
    request->interval_mode = FitIntervalMode::kFixed;
    request->fixed_interval_s = options.keyframe_interval_s;
  }
}

/// The candidate interval nearest kFallbackIntervalS [s].
double nearestCandidate(const std::vector<double>& candidates_s)
{
  return *std::min_element(candidates_s.begin(), candidates_s.end(), [](double a, double b) {
    return std::abs(a - kFallbackIntervalS) < std::abs(b - kFallbackIntervalS);
  });
}

/// A session that fits what it is fed and writes nothing: no saved calibration, no pairs file,
/// no odometry or assistant.
SessionOptions trackerLogSessionOptions(const std::string& dataset_path)
{
  SessionOptions session;
  session.load_saved_calibration = false;
  session.resume_pairs = false;
  session.min_pairs = 1;  // the model says what it lacks
  session.min_pairs_name.clear();
  session.odometry = false;
  session.assistant = false;
  session.adopt_fits = false;
  session.source = dataset_path;
  session.default_sensor_frame = "sensor";
  session.topics = {"the log's encoders", "the log's tracker poses"};
  return session;
}

/// Every row of the log into `session`: each row's encoder readings, then its
/// tracker pose at the same stamp; then the end of the input.
void feedRows(const TricycleDataset& dataset, const TricycleEncoderLayout& layout,
              CalibrationSession* session)
{
  for (const TricycleDatasetRow& row : dataset.rows) {
    Eigen::VectorXd raw(2);
    raw(layout.steering_index) = row.steering_ticks;
    raw(layout.traction_index) = row.traction_ticks;
    session->addJointPositions(row.stamp_s, raw);
    session->addSensorPose(row.stamp_s, row.T_world_sensor, "sensor");
  }
  session->flush();
}

/// The session's run over a tracker log: its configuration, its fit, and every row's keyframe
/// pairs at the evaluation interval (the shortest candidate, or the one interval given) with the
/// encoder history they were cut from.
struct TrackerLogRun
{
  CalibrationConfig config;
  SessionFit fit;
  std::vector<MotionPair> pairs;
  std::vector<EncoderSample> encoder_history;
};

/// The session's run over every row of the tracker log, fitted on the pairs that end by
/// `fit_until_stamp_s` (the last fitted row's stamp): pairing, interval choice
/// (calibration/fit_interval.h, by the ATE of a tracker's poses) and the tricycle fit. Throws
/// std::invalid_argument with the session's message when no fit ran (too few pairs).
TrackerLogRun fitTrackerLog(const TricycleDataset& dataset, const TricycleEncoderLayout& layout,
                            const TricycleParameters& nominal, double fit_until_stamp_s,
                            const TricycleCliOptions& options)
{
  TrackerLogRun run;
  run.config = trackerLogConfig(layout, nominal, options);
  CalibrationSession session(run.config, "", options.dataset_path,
                             trackerLogSessionOptions(options.dataset_path));
  feedRows(dataset, layout, &session);
  CalibrationRequest request;
  request.model = run.config.model;
  request.models = run.config.models;
  setIntervalMode(run.config, options, &request);
  request.fit_until_stamp_s = fit_until_stamp_s;
  CalibrateOutcome outcome = session.calibrate(request);
  if (outcome.fit && !outcome.fit->interval_problem.empty()) {
    // Too short a drive to cross-validate: the candidate nearest kFallbackIntervalS, and why.
    const std::string problem = outcome.fit->interval_problem;
    request.interval_mode = FitIntervalMode::kFixed;
    request.fixed_interval_s = nearestCandidate(options.interval_selection.candidates_s);
    outcome = session.calibrate(request);
    if (outcome.fit)
      outcome.fit->interval_problem = problem;
  }
  if (!outcome.fit)
    throw std::invalid_argument(outcome.message);
  run.fit = std::move(*outcome.fit);
  run.pairs = session.pairs();
  run.encoder_history = session.encoderHistory();
  return run;
}

/// The tricycle's own result of the session's fit, with the warnings the session added (an
/// interval it could not choose).
TricycleCalibrationResult tricycleResult(const SessionFit& fit)
{
  const auto* model = dynamic_cast<const TricycleModel*>(fit.job.model.get());
  if (model == nullptr || !model->lastCalibration())
    throw std::logic_error("the session's fit is not a tricycle fit");
  TricycleCalibrationResult result = *model->lastCalibration();
  for (const std::string& warning : fit.job.report.warnings) {
    if (std::find(result.warnings.begin(), result.warnings.end(), warning) == result.warnings.end())
      result.warnings.push_back(warning);
  }
  return result;
}

/// The encoder layout and the nominal parameters of the log's header; a refusal names the log.
std::pair<TricycleEncoderLayout, TricycleParameters> readHeader(const TricycleDataset& dataset,
                                                                const std::string& path)
{
  try {
    return {tricycleLayoutFromHeader(dataset.header), tricycleNominalFromHeader(dataset.header)};
  } catch (const std::invalid_argument& error) {
    throw std::invalid_argument(path + ": " + error.what());
  }
}

/// The calibrated model and the nominal robot scored on `pairs` by the common scorer
/// (calibration_job.h's scoreHeldOut: each pair's displacement predicted from its encoder
/// samples, chained, ATE and RPE against the chained tracker displacements, paper eqs. 11, 10).
/// Throws std::invalid_argument naming `what` and `option` when fewer than two pairs remain.
std::vector<ModelScore> scoreStretch(const TrackerLogRun& run, const std::vector<MotionPair>& pairs,
                                     const std::string& what, const std::string& option)
{
  if (pairs.size() < 2) {
    throw std::invalid_argument(what + " hold " + std::to_string(pairs.size()) +
                                " keyframe pair(s) of " +
                                formatNumber(run.config.collector.keyframe_interval_s) +
                                " s; scoring them needs at least 2: " + option);
  }
  return scoreHeldOut(run.config, run.fit.job, pairs, run.encoder_history);
}

/// The --output document: the common result.yaml (calibration_result.h: the fit, the model,
/// its joints and interval), how the interval was chosen and the scores of each stretch.
std::string trackerResultYaml(const TrackerLogRun& run, const std::string& source,
                              const std::vector<ResultScores>& scores)
{
  const CalibrationJobResult& job = run.fit.job;
  std::string yaml = calibrationResultYaml(job.report, *job.model, source, job.time_offset_s,
                                           run.config.models.joints.names, run.fit.fit_interval_s);
  if (run.fit.choice)
    yaml += fitIntervalChoiceYaml(*run.fit.choice, run.config.collector.keyframe_interval_s);
  return yaml + scoresYaml(scores);
}

/// "the 0.25 s keyframe pairs of `which` (N samples, D s)": the pairs of the rows [first, last).
std::string stretchDescription(const TricycleDataset& dataset, std::size_t first, std::size_t last,
                               double interval_s, const std::string& which)
{
  char text[200];
  std::snprintf(text, sizeof(text), "the %.2f s keyframe pairs of %s (%zu samples, %.1f s)",
                interval_s, which.c_str(), last - first,
                dataset.rows[last - 1].stamp_s - dataset.rows[first].stamp_s);
  return text;
}

/// "40 %": a fraction in percent, rounded.
std::string percent(double fraction)
{
  char text[32];
  std::snprintf(text, sizeof(text), "%.0f %%", 100.0 * fraction);
  return text;
}

/// Prints the run's first line and its interval's lines.
void printRun(const TricycleCliOptions& options, const TrackerLogRun& run, std::size_t rows,
              std::size_t training_end, std::ostream& out)
{
  out << "dataset: " << options.dataset_path << " (" << rows << " samples";
  if (options.holdout_fraction > 0.0)
    out << ", the first " << training_end << " fitted";
  out << ", " << run.fit.job.pairs.size() << " keyframe pairs at T = " << run.fit.fit_interval_s
      << " s)\n\n";
  out << formatTricycleInterval(run.fit, run.config.collector.keyframe_interval_s);
}

/// The held-out rows [training_end, end): their span and their pairs' scores.
TricycleHeldOut scoreHeldOutRows(const TricycleDataset& dataset, const TrackerLogRun& run,
                                 double fraction, std::size_t training_end)
{
  TricycleHeldOut held_out;
  held_out.fraction = fraction;
  held_out.samples = dataset.rows.size() - training_end;
  held_out.duration_s = dataset.rows.back().stamp_s - dataset.rows[training_end].stamp_s;
  held_out.rows =
      scoreStretch(run, pairsStartingFrom(run.pairs, dataset.rows[training_end].stamp_s),
                   "the held-out samples", "hold out a larger part (--holdout)");
  return held_out;
}

/// Calibrates on a loaded dataset of at least two samples through the calibration session
/// (its pairing, interval choice and fit on the fitted rows), scores the fit on the fitted rows'
/// keyframe pairs (and on the held-out ones), prints the report and writes the result; the exit
/// status: 3 not converged, 4 converged with warnings, 0 otherwise.
int calibrateDataset(const TricycleDataset& dataset, const TricycleCliOptions& options,
                     std::ostream& out)
{
  const auto [layout, nominal] = readHeader(dataset, options.dataset_path);
  const std::size_t rows = dataset.rows.size();
  // The fit sees the first rows only; the held-out ones score it.
  const bool holdout = options.holdout_fraction > 0.0;
  const std::size_t training_end = holdout ? holdoutStart(rows, options.holdout_fraction) : rows;
  const double fitted_until_s = dataset.rows[training_end - 1].stamp_s;
  const TrackerLogRun run = fitTrackerLog(dataset, layout, nominal, fitted_until_s, options);
  const TricycleCalibrationResult result = tricycleResult(run.fit);
  const double interval_s = run.config.collector.keyframe_interval_s;
  std::vector<ResultScores> scores = {
      {"fitted", stretchDescription(dataset, 0, training_end, interval_s, "the fitted samples"),
       scoreStretch(run, pairsEndingBy(run.pairs, fitted_until_s), "the fitted samples",
                    "fit a longer log")}};
  std::optional<TricycleHeldOut> held_out;
  if (holdout) {  // scored before anything is printed: too few held-out pairs stop the run
    held_out = scoreHeldOutRows(dataset, run, options.holdout_fraction, training_end);
    scores.push_back(
        {"held_out",
         stretchDescription(dataset, training_end, rows, interval_s,
                            "the last " + percent(options.holdout_fraction) + " of the samples") +
             ", never seen by the fit",
         held_out->rows});
  }
  printRun(options, run, rows, training_end, out);
  if (held_out)
    out << "\n" << formatTricycleHeldOut(*held_out);
  out << "\n" << formatTricycleReport(result, scores.front().rows);
  if (!options.output_path.empty()) {
    writeFileAtomically(options.output_path, trackerResultYaml(run, options.dataset_path, scores));
    out << "\nresult written to " << options.output_path << "\n";
  }
  if (!result.converged)
    return 3;
  return result.warnings.empty() ? 0 : 4;
}

}  // namespace

int runTricycleCli(const TricycleCliOptions& options, std::ostream& out, std::ostream& err)
{
  try {
    const TricycleDataset dataset = loadTricycleDataset(options.dataset_path);
    if (dataset.last_line_unterminated) {
      err << "warning: " << options.dataset_path
          << " does not end with a line end: the file may be truncated (its last sample, line "
          << dataset.rows.back().line << ", is used as read)\n";
    }
    if (dataset.rows.size() < 2) {
      err << "error: " << options.dataset_path << " holds "
          << (dataset.rows.empty() ? "no samples" : "a single sample")
          << "; a calibration needs a drive of many samples\n";
      return 1;
    }
    return calibrateDataset(dataset, options, out);
  } catch (const std::exception& error) {
    err << "error: " << error.what() << "\n";
    return 1;
  }
}

}  // namespace odometry_calibration
