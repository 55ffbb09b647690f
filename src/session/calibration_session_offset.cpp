// The session's pairing at the estimated time offset: its inputs recorded (input_record.h) and,
// when the offset estimated on the pairs is far from the one they were made at, paired again
// at the estimate with fresh collectors, as a session configured at it would have paired them
// (calibrate_bag's result and the node's are then the same).
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <memory>

#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {

namespace {

/// While more inputs than this came since the record's view, the catch-up feeds them without
/// the lock (the inputs keep flowing); the rest is fed under it.
constexpr std::size_t kCatchUpUnderLock = 200;

}  // namespace

struct CalibrationSession::PairingAgain
{
  std::size_t end = 0;            ///< the record's inputs [0, end) are fed
  double offset_s = 0.0;          ///< the time offset the collectors pair at [s]
  std::vector<MotionPair> pairs;  ///< made so far, in order
  std::unique_ptr<PairCollector> collector;
  std::vector<EncoderSample> history;  ///< the encoder history as the session keeps it
  bool history_broken = false;         ///< time went backwards (no history until a reset)
  std::unique_ptr<CandidateCollectors> candidates;
  std::unique_ptr<EncoderDecoder> decoder;  ///< the history's (made at the first reading)
  /// The time-offset search run on exactly `pairs` at `offset_s` (when one was).
  std::optional<TimeOffsetResult> offset_search;
  /// The pairing before this one: its offset and the estimate on its pairs [s].
  OffsetRound before;
};

void CalibrationSession::record(const std::function<void(InputRecord&)>& add)
{
  input_since_flush_ = true;
  if (!record_)
    return;
  try {
    add(*record_);
  } catch (const std::exception& error) {
    dropRecord(error.what());
  }
}

void CalibrationSession::dropRecord(const std::string& error)
{
  record_.reset();
  say(SessionLogLevel::kError,
      "the input record failed (" + error +
          "): the pairs cannot be made again at the estimated time offset until ~reset");
}

std::optional<InputRecordView> CalibrationSession::recordSince(std::size_t first)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!record_)
    return std::nullopt;
  try {
    return record_->view(first);
  } catch (const std::exception& error) {
    dropRecord(error.what());
    return std::nullopt;
  }
}

std::pair<std::size_t, std::uint64_t> CalibrationSession::inputRecordBytes() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!record_)
    return {0, 0};
  return {record_->memoryBytes(), record_->spilledBytes()};
}

void CalibrationSession::feed(const InputRecordView& inputs, PairingAgain* again) const
{
  PairingAgain& r = *again;
  auto take = [&r](const std::vector<CollectorEvent>& events) {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair) {
        r.pairs.push_back(event.pair);
      } else if (event.type == CollectorEvent::Type::kRestarted) {
        r.history_broken = true;  // as restart() does
        r.history.clear();
      }
    }
  };
  RecordedInputVisitor visitor;
  visitor.encoders = [&](double stamp_s, const Eigen::VectorXd& raw) {
    Eigen::VectorXd accepted;
    try {
      take(r.collector->addEncoders(stamp_s, raw, &accepted));
      if (r.candidates)
        r.candidates->addEncoders(stamp_s, raw);
    } catch (const std::invalid_argument&) {
      return;  // refused by the session too
    }
    if (accepted.size() == 0 || !keep_history_ || r.history_broken)
      return;
    if (!r.decoder)
      r.decoder = std::make_unique<EncoderDecoder>(channels_);
    if (r.history.empty() || stamp_s > r.history.back().stamp_s)
      r.history.push_back({stamp_s, r.decoder->decode(accepted)});
  };
  visitor.scan = [&](double stamp_s, const Scan& scan) {
    try {
      take(r.collector->addScan(stamp_s, scan));
      if (r.candidates)
        r.candidates->addScan(stamp_s, scan);
    } catch (const std::invalid_argument&) {
    }
  };
  visitor.sensor_pose = [&](double stamp_s, const Pose2& T_world_sensor,
                            const Eigen::Matrix3d& covariance) {
    try {
      take(r.collector->addSensorPose(stamp_s, T_world_sensor, covariance));
      if (r.candidates)
        r.candidates->addSensorPose(stamp_s, T_world_sensor, covariance);
    } catch (const std::invalid_argument&) {
    }
  };
  visitor.flush = [&] {
    take(r.collector->flush());
    if (r.candidates)
      r.candidates->flush();
  };
  inputs.replay(visitor);
}

bool CalibrationSession::install(PairingAgain* again)
{
  // What came while the inputs were paired again: fed without the lock while much is new.
  for (int round = 0; round < 4; ++round) {
    const std::optional<InputRecordView> more = recordSince(again->end);
    if (!more)
      return false;
    if (more->size() < kCatchUpUnderLock)
      break;
    feed(*more, again);
    again->end = more->end();
  }
  std::lock_guard<std::mutex> lock(mutex_);
  if (!record_)
    return false;  // dropped meanwhile: the inputs since cannot be caught up
  try {
    feed(record_->view(again->end), again);
  } catch (const std::exception& error) {
    dropRecord(error.what());
    return false;
  }
  collector_ = std::move(again->collector);
  candidates_ = std::move(again->candidates);
  store_->replace(again->pairs);
  history_decoder_ = std::move(again->decoder);
  encoder_history_ = std::move(again->history);
  history_broken_ = again->history_broken;
  config_.collector.time_offset_s = again->offset_s;
  if (odometry_)
    odometry_->restart();  // it integrates at the pairing's offset
  return true;
}

std::unique_ptr<CalibrationSession::PairingAgain> CalibrationSession::pairRecord(
    const InputRecordView& record, CollectorOptions options, double offset_s, std::string* problem)
{
  options.time_offset_s = offset_s;
  auto again = std::make_unique<PairingAgain>();
  again->end = record.end();
  again->offset_s = offset_s;
  buildCollectors(options, &again->collector, &again->candidates);
  try {
    feed(record, again.get());  // without the lock: the inputs go on meanwhile
  } catch (const std::exception& error) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      dropRecord(error.what());
    }
    *problem =
        "not paired again at the estimated time offset: the input record could not be "
        "read back (" +
        std::string(error.what()) + ")\n";
    return nullptr;
  }
  return again;
}

std::unique_ptr<CalibrationSession::PairingAgain> CalibrationSession::pairUntilSettled(
    const InputRecordView& record, const CalibrationConfig& config,
    std::unique_ptr<PairingAgain> again, int* rounds)
{
  // Pairs made far from the true offset carry its trace (each scan's sweep undone with the
  // motion of another instant), so the estimate on them lands short of it: each round pairs
  // at the offset nextPairingOffset_s gives from the last two until the estimate on the
  // pairs is within the tolerance of the offset they were made at.
  CalibrationJobOptions offset_only;
  offset_only.compare_trajectories = false;
  while (*rounds < kMaxPairingRounds && !again->history_broken && !again->pairs.empty()) {
    CalibrationConfig at = config;
    at.collector.time_offset_s = again->offset_s;
    std::optional<CalibrationJobResult> job;
    try {
      job = runCalibrationJob(at, again->pairs, again->history, offset_only);
    } catch (const std::exception&) {
      break;  // the pairs of the previous round stand
    }
    if (!job->time_offset || job->time_offset->flat ||
        !(std::abs(job->time_offset_s - again->offset_s) > kOffsetPairingToleranceS)) {
      again->offset_search = job->time_offset;  // settled: the final fit reuses it
      break;
    }
    const OffsetRound last{again->offset_s, job->time_offset_s};
    const double next_offset_s =
        std::clamp(nextPairingOffset_s(again->before, last), config.time_offset_search_min_s,
                   config.time_offset_search_max_s);
    std::string problem;
    std::unique_ptr<PairingAgain> next =
        pairRecord(record, config.collector, next_offset_s, &problem);
    if (!next)
      break;
    next->before = last;
    again = std::move(next);
    ++*rounds;
  }
  return again;
}

std::unique_ptr<CalibrationSession::PairingAgain> CalibrationSession::pairAtEstimatedOffset(
    const std::optional<InputRecordView>& record, std::size_t resumed, SessionFitRequest* request,
    OffsetPairing* pairing)
{
  pairing->configured_s = pairing->estimate_s = request->config.collector.time_offset_s;
  if (!request->config.estimate_time_offset || request->pairs.empty() ||
      request->encoder_history.empty() || (!record && resumed == 0))
    return nullptr;
  CalibrationJobOptions offset_only;
  offset_only.compare_trajectories = false;
  const CalibrationJobResult first =
      runCalibrationJob(request->config, request->pairs, request->encoder_history, offset_only);
  if (!first.time_offset || first.time_offset->flat)
    return nullptr;
  pairing->estimate_s = first.time_offset_s;
  char text[400];
  if (!(std::abs(pairing->estimate_s - pairing->configured_s) > kOffsetPairingToleranceS)) {
    std::snprintf(text, sizeof(text),
                  "paired at the configured time offset %.3f s (estimated %.3f s, within %.3f s)\n",
                  pairing->configured_s, pairing->estimate_s, kOffsetPairingToleranceS);
    pairing->text = text;
    request->offset_search = first.time_offset;  // the very pairs it was searched on
    return nullptr;
  }
  if (resumed > 0 || !record) {  // resumed pairs' inputs are not in the record
    std::snprintf(text, sizeof(text),
                  "not paired again at the estimated time offset %.3f s (paired at %.3f s): %zu "
                  "pairs were resumed from the pairs file without their inputs; set "
                  "keyframes.time_offset_s to it, or ~reset and drive again\n",
                  pairing->estimate_s, pairing->configured_s, resumed);
    pairing->text = text;
    return nullptr;
  }
  const auto started = std::chrono::steady_clock::now();
  std::unique_ptr<PairingAgain> again =
      pairRecord(*record, request->config.collector, pairing->estimate_s, &pairing->text);
  if (!again)
    return nullptr;
  again->before = {pairing->configured_s, pairing->estimate_s};
  int rounds = 1;
  again = pairUntilSettled(*record, request->config, std::move(again), &rounds);
  pairing->estimate_s = again->offset_s;
  request->config.collector.time_offset_s = pairing->estimate_s;
  request->pairs = again->pairs;
  request->candidates =
      again->candidates ? again->candidates->pairs() : std::vector<IntervalPairs>();
  request->encoder_history = again->history_broken ? std::vector<EncoderSample>() : again->history;
  request->offset_search = again->offset_search;
  pairing->paired_again = true;
  std::snprintf(text, sizeof(text),
                "paired again at the estimated time offset %.3f s in %.1f s, %d round%s "
                "(configured %.3f s: set keyframes.time_offset_s to it to pair once)\n",
                pairing->estimate_s,
                std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count(),
                rounds, rounds == 1 ? "" : "s", pairing->configured_s);
  pairing->text = text;
  return again;
}

SessionFit CalibrationSession::fitPairs(const CalibrationRequest& request,
                                        const std::optional<InputRecordView>& record,
                                        std::size_t resumed, SessionFitRequest* fit_request)
{
  fit_request->fixed_interval_s = request.fixed_interval_s;
  fit_request->fold_counts = request.fold_counts;
  fit_request->fit_until_stamp_s = request.fit_until_stamp_s;
  fit_request->offset_search = request.offset_search;
  OffsetPairing pairing;
  const std::unique_ptr<PairingAgain> again =
      pairAtEstimatedOffset(record, resumed, fit_request, &pairing);
  if (request.holdout_fraction) {
    fit_request->fit_until_stamp_s =
        holdOutLastPairs(fit_request->pairs, *request.holdout_fraction).border_stamp_s;
    fit_request->offset_search.reset();
  }
  fit_request->interval_mode = request.interval_mode.value_or(
      fit_request->candidates.empty() ? FitIntervalMode::kConfigured : FitIntervalMode::kChoose);
  SessionFit fit = fitSessionPairs(*fit_request);
  // The pairs made again become the session's only with a fit that can be its result.
  if (again && (fit.job.report.converged || !options_.adopt_fits) && !install(again.get())) {
    pairing.text.pop_back();
    pairing.text += "; the session keeps its earlier pairs: its input record was dropped\n";
  }
  fit.offset_pairing = std::move(pairing);
  return fit;
}

}  // namespace odometry_calibration
