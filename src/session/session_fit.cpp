#include "odometry_calibration/session/session_fit.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "odometry_calibration/data/stream_spacing.h"
#include "odometry_calibration/models/model_checks.h"

namespace odometry_calibration {
namespace {

/// The secant step below is taken only while g's slope over the last two pairings lies in
/// [kSecantSlopeMin, kSecantSlopeMax]: the estimate leaning toward the pairing offset by at
/// most 3/4 (slope -0.25) or away from it by at most 1 (slope -2) [-].
constexpr double kSecantSlopeMin = -2.0;
constexpr double kSecantSlopeMax = -0.25;

/// A fit whose parameters are no physical values (a radius of 77 m or below zero, a value that
/// is not finite) is marked not converged, so that it never becomes the active model and
/// calibrate_bag reports it NOT converged.
void refuseUnphysicalFit(ModelReport* report)
{
  std::vector<std::string> names;
  std::vector<double> values;
  for (const ParameterEstimate& parameter : report->parameters) {
    names.push_back(parameter.name);
    values.push_back(parameter.value);
  }
  const std::string problem = physicalBoundsProblem(names, values);
  if (problem.empty() || !report->converged)
    return;
  report->converged = false;
  report->termination = problem;
  report->warnings.push_back(problem);
}

/// The pairs of one interval: the evaluation pairs at keyframes.interval_s, else a candidate's.
std::vector<MotionPair> pairsAt(const SessionFitRequest& request, double interval_s)
{
  if (std::abs(interval_s - request.config.collector.keyframe_interval_s) < 1e-9)
    return pairsEndingBy(request.pairs, request.fit_until_stamp_s);
  for (const IntervalPairs& candidate : request.candidates) {
    if (std::abs(candidate.interval_s - interval_s) < 1e-9)
      return pairsEndingBy(candidate.pairs, request.fit_until_stamp_s);
  }
  throw std::invalid_argument("no pairs were collected at the fit interval " +
                              std::to_string(interval_s) + " s");
}

/// Every candidate interval with its pairs (the evaluation interval among them), shortest first.
std::vector<IntervalPairs> allCandidates(const SessionFitRequest& request)
{
  std::vector<IntervalPairs> all{{request.config.collector.keyframe_interval_s,
                                  pairsEndingBy(request.pairs, request.fit_until_stamp_s)}};
  for (const IntervalPairs& candidate : request.candidates) {
    if (std::abs(candidate.interval_s - all.front().interval_s) > 1e-9)
      all.push_back({candidate.interval_s, pairsAt(request, candidate.interval_s)});
  }
  std::stable_sort(all.begin(), all.end(), [](const IntervalPairs& a, const IntervalPairs& b) {
    return a.interval_s < b.interval_s;
  });
  return all;
}

/// Candidate intervals shorter than this many encoder spacings hold too few readings of their
/// own to be told apart by the readings' timing: left out of the choice.
constexpr double kMinSpacingsPerCandidate = 2.0;

/// Removes from `candidates` those shorter than kMinSpacingsPerCandidate spacings of the
/// readings in `history` (never `keep_s`, the evaluation interval), and says which ("" when none).
std::string dropCandidatesBelowEncoderRate(const std::vector<EncoderSample>& history, double keep_s,
                                           std::vector<IntervalPairs>* candidates)
{
  StreamSpacing spacing(history.size());
  for (const EncoderSample& sample : history)
    spacing.add(sample.stamp_s);
  const double shortest_s = kMinSpacingsPerCandidate * spacing.median_s();
  if (!std::isfinite(shortest_s))
    return "";
  std::string dropped;
  for (auto it = candidates->begin(); it != candidates->end();) {
    if (it->interval_s < shortest_s && std::abs(it->interval_s - keep_s) > 1e-9) {
      char value[32];
      std::snprintf(value, sizeof(value), "%s%.2f", dropped.empty() ? "" : ", ", it->interval_s);
      dropped += value;
      it = candidates->erase(it);
    } else {
      ++it;
    }
  }
  if (dropped.empty())
    return "";
  char text[320];  // up to 20 candidates (keyframes.fit_intervals_s)
  std::snprintf(text, sizeof(text),
                "; left out T = %s s: shorter than %.0f encoder spacings (readings every %.3g s)",
                dropped.c_str(), kMinSpacingsPerCandidate, spacing.median_s());
  return text;
}

/// Cross-validates the candidates. The time offset belongs to the robot, not to T: found once
/// on the evaluation pairs, then every candidate is cut at it, so the comparison is of intervals
/// only. The chosen interval's pairs are returned as collected (the job re-cuts them).
void chooseInterval(const SessionFitRequest& request, bool with_offset, SessionFit* fit,
                    std::vector<MotionPair>* fit_pairs)
{
  const std::vector<IntervalPairs> collected = allCandidates(request);
  std::vector<IntervalPairs> candidates = collected;
  const std::string left_out = dropCandidatesBelowEncoderRate(
      request.encoder_history, request.config.collector.keyframe_interval_s, &candidates);
  std::vector<MotionPair> evaluation = pairsEndingBy(request.pairs, request.fit_until_stamp_s);
  if (with_offset) {
    CalibrationJobOptions offset_only;
    offset_only.compare_trajectories = false;
    const CalibrationJobResult offset_job =
        runCalibrationJob(request.config, evaluation, request.encoder_history, offset_only);
    evaluation = offset_job.pairs;
    for (IntervalPairs& candidate : candidates) {
      candidate.pairs =
          rewindowPairs(candidate.pairs, request.encoder_history, offset_job.time_offset_s);
    }
  }
  FitIntervalOptions cross_validation;
  if (!request.fold_counts.empty())
    cross_validation.fold_counts = request.fold_counts;
  fit->choice =
      chooseFitInterval(request.config, candidates, evaluation,
                        fitIntervalCriterion(request.config.ego_motion), cross_validation);
  const auto scored = std::count_if(
      fit->choice->curve.begin(), fit->choice->curve.end(),
      [](const FitIntervalScore& score) { return std::isfinite(score.validation_error_m); });
  if (scored < 2 && candidates.size() > 1) {
    throw std::invalid_argument(
        "only " + std::to_string(scored) +
        " candidate interval could be cross-validated (too few pairs outside the time blocks for "
        "the others); record a longer drive or fix the interval");
  }
  for (const IntervalPairs& candidate : collected) {
    if (candidate.interval_s == fit->choice->interval_s) {
      fit->fit_interval_s = candidate.interval_s;
      *fit_pairs = candidate.pairs;
    }
  }
  fit->interval_text =
      formatFitIntervalChoice(*fit->choice, request.config.collector.keyframe_interval_s);
  if (!left_out.empty()) {
    const bool newline = !fit->interval_text.empty() && fit->interval_text.back() == '\n';
    if (newline)
      fit->interval_text.pop_back();
    fit->interval_text += left_out + (newline ? "\n" : "");
  }
}

}  // namespace

SessionFit fitSessionPairs(const SessionFitRequest& request)
{
  const CalibrationConfig& config = request.config;
  SessionFit fit;
  fit.fit_interval_s = config.collector.keyframe_interval_s;
  fit.offset_estimated = config.estimate_time_offset && !request.encoder_history.empty();
  std::vector<MotionPair> fit_pairs = pairsEndingBy(request.pairs, request.fit_until_stamp_s);
  std::string interval_warning;
  if (request.interval_mode == FitIntervalMode::kFixed) {
    fit.fit_interval_s = request.fixed_interval_s;
    fit_pairs = pairsAt(request, request.fixed_interval_s);
    char text[160];
    std::snprintf(text, sizeof(text), "fit interval T = %.2f s (--interval): %zu pairs",
                  fit.fit_interval_s, fit_pairs.size());
    fit.interval_text = text;
  } else if (request.interval_mode == FitIntervalMode::kChoose) {
    try {
      chooseInterval(request, fit.offset_estimated, &fit, &fit_pairs);
    } catch (const std::exception& error) {
      fit.choice.reset();
      fit.interval_text.clear();
      fit_pairs = pairsEndingBy(request.pairs, request.fit_until_stamp_s);
      fit.interval_problem = error.what();
      interval_warning = "the fit interval could not be chosen by cross-validation (" +
                         fit.interval_problem + "): fitted at keyframes.interval_s";
    }
  }
  if (!fit.interval_text.empty() && fit.interval_text.back() == '\n')
    fit.interval_text.pop_back();
  CalibrationJobOptions job_options;
  job_options.allow_time_offset = fit.offset_estimated;
  job_options.keep_offset_within_s = kOffsetPairingToleranceS;
  job_options.compare_trajectories = request.compare_trajectories;
  const bool same_pairs = request.interval_mode == FitIntervalMode::kConfigured &&
                          fit_pairs.size() == request.pairs.size();
  if (same_pairs)
    job_options.time_offset_search = request.offset_search;
  fit.job = runCalibrationJob(config, fit_pairs, request.encoder_history, job_options);
  refuseUnphysicalFit(&fit.job.report);
  if (!interval_warning.empty())
    fit.job.report.warnings.push_back(interval_warning);
  if (config.estimate_time_offset && !fit.offset_estimated) {
    fit.job.report.warnings.push_back(
        "the time offset was not estimated: it needs one continuous encoder stream (time went "
        "backwards in the data); kept the configured " +
        std::to_string(fit.job.time_offset_s) + " s");
    ++fit.job.time_offset_warnings;
  }
  return fit;
}

std::string timeOffsetSentence(const CalibrationConfig& config, const SessionFit& fit)
{
  if (!config.estimate_time_offset)
    return "";
  char text[200];
  const CalibrationJobResult& job = fit.job;
  if (!fit.offset_estimated) {
    std::snprintf(text, sizeof(text),
                  " Time offset: not estimated (no continuous encoder history since the start or "
                  "the last ~reset), kept %.4f s.",
                  job.time_offset_s);
  } else if (!job.time_offset || job.time_offset->flat) {
    std::snprintf(text, sizeof(text),
                  " Time offset: not observable from this drive (flat cost), kept %.4f s.",
                  job.time_offset_s);
  } else if (job.time_offset->offset_s != job.time_offset_s) {
    std::snprintf(text, sizeof(text),
                  " Time offset: tau = %.4f +- %.4f s (encoder values at scan time + tau), within "
                  "%.3f s of the %.4f s the pairs were made at: kept.",
                  job.time_offset->offset_s, job.time_offset->sigma_s, kOffsetPairingToleranceS,
                  job.time_offset_s);
  } else {
    std::snprintf(text, sizeof(text),
                  " Time offset: tau = %.4f +- %.4f s (encoder values at scan time + tau), used "
                  "for new pairs.",
                  job.time_offset_s, job.time_offset->sigma_s);
  }
  return text;
}

double nextPairingOffset_s(const OffsetRound& before, const OffsetRound& last)
{
  // The estimate f(t) on pairs made at offset t leans toward t (each scan's sweep is undone
  // with the encoders at t), so the offset sought is the fixed point f(t) = t, the root of
  // g(t) = f(t) - t. The secant through the last two pairings (t0, g0), (t1, g1) finds it
  // where f leans linearly: t1 - g1 (t1 - t0) / (g1 - g0); outside the slopes the rule trusts,
  // the last estimate f(t1) itself (the plain iteration).
  const double g0 = before.estimate_s - before.paired_at_s;
  const double g1 = last.estimate_s - last.paired_at_s;
  const double dt = last.paired_at_s - before.paired_at_s;
  const double slope = dt != 0.0 ? (g1 - g0) / dt : NAN;
  if (!(slope >= kSecantSlopeMin && slope <= kSecantSlopeMax))
    return last.estimate_s;
  return last.paired_at_s - g1 / slope;
}

}  // namespace odometry_calibration
