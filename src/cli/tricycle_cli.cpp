#include "odometry_calibration/cli/tricycle_cli.h"

#include <algorithm>
#include <cmath>
#include <utility>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/data/keyframes.h"
#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "odometry_calibration/eval/tricycle_report.h"
#include "odometry_calibration/models/tricycle_model.h"
#include "odometry_calibration/report/tricycle_result_yaml.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {
namespace {

/// The interval when the drive is too short to choose one (or the candidate nearest it) [s].
constexpr double kFallbackIntervalS = 0.5;

/// Indices of the keyframes T apart (the first sample, then each window's end), for the RPE.
std::vector<std::size_t> keyframeIndices(const std::vector<EncoderSample>& samples,
                                         double interval_s)
{
  std::vector<double> stamps_s;
  for (const EncoderSample& sample : samples) {
    stamps_s.push_back(sample.stamp_s);
  }
  std::vector<std::size_t> keyframes = {0};
  for (const KeyframeWindow& window : selectKeyframeWindows(stamps_s, interval_s)) {
    keyframes.push_back(window.last);
  }
  return keyframes;
}

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
         "  --output PATH            result YAML, written atomically (default\n"
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

/// The first `count` elements of `all`, or the rest after them.
template <typename T>
std::vector<T> head(const std::vector<T>& all, std::size_t count)
{
  return std::vector<T>(all.begin(), all.begin() + static_cast<std::ptrdiff_t>(count));
}
template <typename T>
std::vector<T> tail(const std::vector<T>& all, std::size_t count)
{
  return std::vector<T>(all.begin() + static_cast<std::ptrdiff_t>(count), all.end());
}

/// The session's configuration of a tracker log (docs/models.md, "The tricycle"): the log's two
/// joints as its header describes them (the steering an absolute angle, the traction a 32-bit
/// counter; the glitch filter, made for a live publisher's bugs, off: on the real log it takes
/// traction readings for glitches and loses pairs), the tracker's poses as the sensor's
/// (`ego_motion.source: pose`, with the fit's sigmas), no time offset (encoders and poses share
/// each row's stamp), and the keyframes at the shortest candidate with the others as fit-interval
/// candidates, or at the one interval given.
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
  if (options.keyframe_interval_s > 0.0) {
    config.collector.keyframe_interval_s = options.keyframe_interval_s;
  } else {
    config.collector.keyframe_interval_s = candidates_s.front();
    config.fit_intervals_s.assign(candidates_s.begin() + 1, candidates_s.end());
  }
  return config;
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

/// The first `row_count` rows of the log into `session`: each row's encoder readings, then its
/// tracker pose at the same stamp; then the end of the input.
void feedRows(const TricycleDataset& dataset, const TricycleEncoderLayout& layout,
              std::size_t row_count, CalibrationSession* session)
{
  for (std::size_t i = 0; i < row_count; ++i) {
    const TricycleDatasetRow& row = dataset.rows[i];
    Eigen::VectorXd raw(2);
    raw(layout.steering_index) = row.steering_ticks;
    raw(layout.traction_index) = row.traction_ticks;
    session->addJointPositions(row.stamp_s, raw);
    session->addSensorPose(row.stamp_s, row.T_world_sensor, "sensor");
  }
  session->flush();
}

/// How the session's fit found its interval, as the report gives it: the validation curve when
/// chosen, else why not.
TricycleValidation intervalValidation(const SessionFit& fit, const TricycleCliOptions& options)
{
  TricycleValidation validation;
  validation.interval_s = fit.fit_interval_s;
  if (options.keyframe_interval_s > 0.0)
    return validation;
  if (!fit.choice) {
    validation.fallback_reason = fit.interval_problem;
    return validation;
  }
  validation.interval_chosen = true;
  validation.fold_counts = options.interval_selection.fold_counts;
  validation.evaluation_interval_s = options.interval_selection.candidates_s.front();
  for (const FitIntervalScore& score : fit.choice->curve)
    validation.curve.push_back({score.interval_s, score.validation_error_m, score.pairs});
  return validation;
}

/// The session's fit of the tracker log's first `row_count` rows: pairing, interval choice
/// (calibration/fit_interval.h, by the ATE of a tracker's poses) and the tricycle fit. Throws
/// std::invalid_argument with the session's message when no fit ran (too few pairs).
SessionFit fitTrackerLog(const TricycleDataset& dataset, const TricycleEncoderLayout& layout,
                         const TricycleParameters& nominal, std::size_t row_count,
                         const TricycleCliOptions& options)
{
  const CalibrationConfig config = trackerLogConfig(layout, nominal, options);
  CalibrationSession session(config, "", options.dataset_path,
                             trackerLogSessionOptions(options.dataset_path));
  feedRows(dataset, layout, row_count, &session);
  CalibrationRequest request;
  request.model = config.model;
  request.models = config.models;
  request.interval_mode =
      options.keyframe_interval_s > 0.0 ? FitIntervalMode::kConfigured : FitIntervalMode::kChoose;
  request.fold_counts = options.interval_selection.fold_counts;
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
  return std::move(*outcome.fit);
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

/// Prints the run (and writes the result YAML when asked); the exit status: 3 not converged,
/// 4 converged with warnings, 0 otherwise.
int reportTricycleRun(const TricycleCliOptions& options, std::size_t dataset_samples,
                      std::size_t fitted_samples, std::size_t pair_count,
                      const TricycleValidation& validation, const TricycleCalibrationResult& result,
                      const TricycleEvaluation& evaluation, std::ostream& out)
{
  out << "dataset: " << options.dataset_path << " (" << dataset_samples << " samples";
  if (options.holdout_fraction > 0.0) {
    out << ", the first " << fitted_samples << " fitted";
  }
  out << ", " << pair_count << " keyframe pairs at T = " << validation.interval_s << " s)\n\n";
  out << formatTricycleValidation(validation) << "\n";
  out << formatTricycleReport(result, evaluation);
  if (!options.output_path.empty()) {
    writeFileAtomically(
        options.output_path,
        tricycleResultToYaml(result, evaluation, options.dataset_path, &validation));
    out << "\nresult written to " << options.output_path << "\n";
  }
  if (!result.converged)
    return 3;
  return result.warnings.empty() ? 0 : 4;
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

/// Calibrates on a loaded dataset of at least two samples through the calibration session
/// (its pairing, interval choice and fit), then scores the fit dead-reckoned on the fitted rows
/// (and on the held-out ones) and reports.
int calibrateDataset(const TricycleDataset& dataset, const TricycleCliOptions& options,
                     std::ostream& out)
{
  const auto [layout, nominal] = readHeader(dataset, options.dataset_path);
  const std::vector<EncoderSample> all_samples = decodeTricycleEncoders(dataset, layout);
  const std::vector<Pose2> all_reference = tricycleTrackerPoses(dataset);
  // The fit sees the first rows only; the held-out ones score it.
  const std::size_t training_end = options.holdout_fraction > 0.0
                                       ? holdoutStart(all_samples.size(), options.holdout_fraction)
                                       : all_samples.size();
  const SessionFit fit = fitTrackerLog(dataset, layout, nominal, training_end, options);
  const TricycleCalibrationResult result = tricycleResult(fit);
  TricycleValidation validation = intervalValidation(fit, options);
  const std::vector<EncoderSample> samples = head(all_samples, training_end);
  const TricycleEvaluation evaluation =
      evaluateTricycle(result, layout, samples, head(all_reference, training_end),
                       keyframeIndices(samples, validation.interval_s));
  if (options.holdout_fraction > 0.0) {
    const std::vector<EncoderSample> test_samples = tail(all_samples, training_end);
    validation.holdout_fraction = options.holdout_fraction;
    validation.training_samples = samples.size();
    validation.held_out_samples = test_samples.size();
    validation.held_out =
        evaluateTricycle(result, layout, test_samples, tail(all_reference, training_end),
                         keyframeIndices(test_samples, validation.interval_s));
  }
  return reportTricycleRun(options, dataset.rows.size(), samples.size(), fit.job.pairs.size(),
                           validation, result, evaluation, out);
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
