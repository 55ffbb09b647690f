#include "odometry_calibration/calibration/calibration_job.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/common/median.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {

namespace {

/// The fine search refits the model within this of the coarse estimate [s].
constexpr double kFineSearchHalfWidthS = 0.2;
/// Without a coarse estimate, the fine search's grid has at most this many steps over the range.
constexpr double kMaxFineSteps = 40.0;

/// Where the fine search refits: near the coarse estimate (the configured range searched by
/// heading correlation with the nominal robot, coarse_time_offset.h, recorded in `job`) when
/// the range is wider than the fine search's window and there is a nominal robot; else over
/// the configured range, on a grid of at most kMaxFineSteps steps.
TimeOffsetOptions fineSearch(const CalibrationConfig& config, const std::vector<MotionPair>& pairs,
                             const std::vector<EncoderSample>& encoder_history,
                             CalibrationJobResult* job)
{
  TimeOffsetOptions search;
  search.min_s = config.time_offset_search_min_s;
  search.max_s = config.time_offset_search_max_s;
  search.interpolation = config.collector.encoder_interpolation;
  const MotionPredictor predict = priorPredictor(config);
  if (predict && search.max_s - search.min_s > 2.0 * kFineSearchHalfWidthS) {
    CoarseTimeOffsetOptions coarse;
    coarse.min_s = search.min_s;
    coarse.max_s = search.max_s;
    coarse.interpolation = search.interpolation;
    job->coarse_time_offset = coarseTimeOffset(pairs, encoder_history, predict, coarse);
    if (job->coarse_time_offset->found) {
      search.min_s =
          std::max(search.min_s, job->coarse_time_offset->offset_s - kFineSearchHalfWidthS);
      search.max_s =
          std::min(search.max_s, job->coarse_time_offset->offset_s + kFineSearchHalfWidthS);
      return search;
    }
  }
  search.step_s = std::max(search.step_s, (search.max_s - search.min_s) / kMaxFineSteps);
  return search;
}

/// The fine search (models from `make_model`); once more around its result when that lies on
/// an edge of the window that is not an edge of the configured range (the coarse estimate was
/// off by more than the window).
TimeOffsetResult searchFinely(const CalibrationConfig& config, const std::vector<MotionPair>& pairs,
                              const std::vector<EncoderSample>& encoder_history,
                              const std::function<std::unique_ptr<MotionModel>()>& make_model,
                              TimeOffsetOptions search)
{
  TimeOffsetResult result = estimateTimeOffset(pairs, encoder_history, make_model, search);
  auto insideRange = [&](double tau_s) {
    return tau_s > config.time_offset_search_min_s + 1e-9 &&
           tau_s < config.time_offset_search_max_s - 1e-9;
  };
  if (result.at_boundary && !result.flat && insideRange(result.offset_s)) {
    const double centre_s = result.offset_s;
    search.min_s = std::max(config.time_offset_search_min_s, centre_s - kFineSearchHalfWidthS);
    search.max_s = std::min(config.time_offset_search_max_s, centre_s + kFineSearchHalfWidthS);
    result = estimateTimeOffset(pairs, encoder_history, make_model, search);
  }
  result.at_boundary = result.at_boundary && !insideRange(result.offset_s);
  return result;
}

/// The time-offset search (or the one given), its warnings, and the pairs re-cut at the offset.
void estimateJobTimeOffset(const CalibrationConfig& config, const std::vector<MotionPair>& pairs,
                           const std::vector<EncoderSample>& encoder_history,
                           const CalibrationJobOptions& options, CalibrationJobResult* job,
                           std::vector<std::string>* warnings)
{
  if (encoder_history.empty()) {
    throw std::runtime_error(
        "time offset estimation needs one continuous encoder stream "
        "(the bags went back in time)");
  }
  // The grid refits the model per offset from the configured start only: the global yaw
  // starts are for the final fit and would multiply the search's cost.
  ModelFactoryOptions search_models = config.models;
  search_models.diff_drive.yaw_starts = 1;
  search_models.tricycle.calibration.yaw_starts = 1;
  search_models.mecanum.yaw_starts = 1;
  job->time_offset = options.time_offset_search
                         ? *options.time_offset_search
                         : searchFinely(
                               config, pairs, encoder_history,
                               [&]() { return makeModel(config.model, search_models); },
                               fineSearch(config, pairs, encoder_history, job));
  const TimeOffsetResult& offset = *job->time_offset;
  if (offset.flat) {
    warnings->push_back(
        "the time offset is not observable from this drive (flat cost curve): kept the "
        "configured " +
        std::to_string(job->time_offset_s) + " s");
  } else {
    if (std::abs(offset.offset_s - job->time_offset_s) > options.keep_offset_within_s)
      job->time_offset_s = offset.offset_s;
    if (offset.at_boundary) {
      warnings->push_back("the time offset estimate " + std::to_string(offset.offset_s) +
                          " s lies at the edge of time_offset_search_s: widen it");
    }
  }
  // At the offset they were made at, the pairs stay as made; at another, a pair whose window
  // the history does not cover to the end (the last, a few ms short) stays as made too.
  if (job->time_offset_s != config.collector.time_offset_s)
    job->pairs = rewindowPairs(pairs, encoder_history, job->time_offset_s,
                               config.collector.encoder_interpolation, UncoveredPairs::kKeptAsMade);
}

/// The evidence: the calibrated model against the scan matches, and the nominal robot (the
/// prior's start values, no time offset) when there is one.
void compareJobTrajectories(const CalibrationConfig& config, const std::vector<MotionPair>& pairs,
                            const std::vector<EncoderSample>& encoder_history,
                            CalibrationJobResult* job)
{
  const std::shared_ptr<MotionModel> nominal = priorModel(config);
  std::vector<MotionPair> nominal_pairs;
  if (nominal) {
    job->nominal_at_zero_offset = !encoder_history.empty();
    nominal_pairs =
        job->nominal_at_zero_offset ? rewindowPairs(pairs, encoder_history, 0.0) : pairs;
    job->nominal_description =
        "the " + config.prior_model + " start values of the configuration at time offset 0";
  }
  job->trajectories = compareTrajectories(job->pairs, *job->model, nominal_pairs, nominal.get());
}

}  // namespace

CalibrationJobResult runCalibrationJob(const CalibrationConfig& config,
                                       const std::vector<MotionPair>& pairs,
                                       const std::vector<EncoderSample>& encoder_history,
                                       const CalibrationJobOptions& options)
{
  const auto start = std::chrono::steady_clock::now();
  CalibrationJobResult job;
  job.pairs = pairs;
  job.time_offset_s = config.collector.time_offset_s;
  std::vector<std::string> offset_warnings;
  if (options.allow_time_offset && config.estimate_time_offset)
    estimateJobTimeOffset(config, pairs, encoder_history, options, &job, &offset_warnings);
  job.model = makeModel(config.model, config.models);
  job.report = job.model->fit(job.pairs);
  job.report.warnings.insert(job.report.warnings.end(), offset_warnings.begin(),
                             offset_warnings.end());
  job.time_offset_warnings = offset_warnings.size();
  job.fit_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (options.compare_trajectories)
    compareJobTrajectories(config, pairs, encoder_history, &job);
  return job;
}

std::optional<ModelScore> scoreNominalRobot(const CalibrationConfig& config,
                                            const std::vector<MotionPair>& pairs,
                                            const std::vector<EncoderSample>& history,
                                            double pairs_offset_s)
{
  const std::shared_ptr<MotionModel> nominal = priorModel(config);
  if (!nominal)
    return std::nullopt;
  const bool recut = !history.empty() && pairs_offset_s != 0.0;
  const std::vector<MotionPair> nominal_pairs = recut ? rewindowPairs(pairs, history, 0.0) : pairs;
  if (nominal_pairs.size() < 2)
    return std::nullopt;
  ModelScore score = scoreNominal(*nominal, nominal_pairs);
  score.T_base_sensor = priorSensorPose(config);
  return score;
}

std::vector<ModelScore> scoreModelsOnTest(const CalibrationConfig& config,
                                          const CalibrationJobResult& job,
                                          const std::vector<MotionPair>& test_pairs,
                                          const std::vector<EncoderSample>& test_history)
{
  std::vector<ModelScore> scores;
  auto add = [&](const MotionModel& model, const ModelReport& fitted) {
    ModelScore score = withFitReport(scoreModel(model, test_pairs), fitted);
    score.warnings.clear();  // the test table never showed them; the report does
    scores.push_back(score);
  };
  add(*job.model, job.report);
  for (const std::string& name : config.compare_models) {
    if (name == config.model)
      continue;
    // A model this robot's joints cannot serve (linear or gp on wheels chained per side) is
    // skipped with the reason; the others are still compared.
    try {
      const std::unique_ptr<MotionModel> candidate = makeModel(name, config.models);
      const ModelReport fitted = candidate->fit(job.pairs);
      add(*candidate, fitted);
    } catch (const std::exception& error) {
      ModelScore skipped;
      skipped.model = name;
      skipped.fitted = false;
      skipped.skipped = error.what();
      scores.push_back(skipped);
    }
  }
  if (std::optional<ModelScore> nominal =
          scoreNominalRobot(config, test_pairs, test_history, job.time_offset_s))
    scores.push_back(std::move(*nominal));
  return scores;
}

std::vector<ModelScore> scoreHeldOut(const CalibrationConfig& config,
                                     const CalibrationJobResult& job,
                                     const std::vector<MotionPair>& test_pairs,
                                     const std::vector<EncoderSample>& encoder_history)
{
  const bool recut =
      !encoder_history.empty() && job.time_offset_s != config.collector.time_offset_s;
  return scoreModelsOnTest(
      config, job,
      recut ? rewindowPairs(test_pairs, encoder_history, job.time_offset_s) : test_pairs,
      encoder_history);
}

std::string formatTimeOffset(const TimeOffsetResult& offset)
{
  std::ostringstream out;
  out << "time offset (encoder values at scan time + tau): tau = " << offset.offset_s << " s +- "
      << offset.sigma_s << " s"
      << (offset.at_boundary ? "  WARNING: at the edge of the search range" : "")
      << "\ncost curve (tau [s], mean Huber loss of chi^2):";
  for (const auto& [tau, cost] : offset.curve)
    out << " " << tau << ":" << cost;
  return out.str() + "\n";
}

std::string formatNominalComparison(const CalibrationJobResult& job)
{
  if (job.nominal_description.empty() || !job.nominal_at_zero_offset)
    return "";
  char line[200];
  std::snprintf(line, sizeof(line),
                "median per-pair RPE vs the matched displacements: nominal (start values, "
                "no time offset) %.4f m -> calibrated %.4f m\n",
                median(translationErrors(job.trajectories.nominal_errors)),
                median(translationErrors(job.trajectories.calibrated_errors)));
  return line;
}

int calibrationExitStatus(const ModelReport& report)
{
  if (!report.converged)
    return 3;
  return report.warnings.empty() ? 0 : 4;
}

int calibrationExitStatus(const CalibrationJobResult& job)
{
  if (!job.report.converged)
    return 3;
  if (job.time_offset_warnings > 0)
    return 5;
  return job.report.warnings.empty() ? 0 : 4;
}

}  // namespace odometry_calibration
