// The session's pairing at the estimated time offset: its inputs recorded (input_record.h) and,
// when the offset estimated on the pairs is far from the one they were made at, paired again
// at the estimate with fresh collectors, as a session configured at it would have paired them
// (calibrate_bag's result and the node's are then the same).
#include <cmath>
#include <cstdio>

#include "odometry_calibration/calibration/candidate_collectors.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {

struct CalibrationSession::Repairing
{
  std::vector<MotionPair> pairs;  ///< made so far, in order
  std::unique_ptr<PairCollector> collector;
  std::vector<EncoderSample> history;  ///< the encoder history as the session keeps it
  bool history_broken = false;         ///< time went backwards (no history until a reset)
  std::unique_ptr<CandidateCollectors> candidates;
  std::unique_ptr<EncoderDecoder> decoder;  ///< the history's (made at the first reading)
};

void CalibrationSession::record(const std::function<void(InputRecord&)>& add)
{
  input_since_flush_ = true;
  if (!record_)
    return;
  try {
    add(*record_);
  } catch (const std::exception& error) {
    record_.reset();
    say(SessionLogLevel::kError,
        std::string("the input record failed (") + error.what() +
            "): the pairs cannot be made again at the estimated time offset until ~reset");
  }
}

std::pair<std::size_t, std::uint64_t> CalibrationSession::inputRecordBytes() const
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (!record_)
    return {0, 0};
  return {record_->memoryBytes(), record_->spilledBytes()};
}

void CalibrationSession::feed(const InputRecordView& inputs, Repairing* repairing) const
{
  Repairing& r = *repairing;
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

void CalibrationSession::install(std::size_t end, Repairing repairing, double offset_s)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (record_)  // what came while the inputs were paired again
    feed(record_->view(end), &repairing);
  collector_ = std::move(repairing.collector);
  candidates_ = std::move(repairing.candidates);
  store_->replace(repairing.pairs);
  history_decoder_ = std::move(repairing.decoder);
  encoder_history_ = std::move(repairing.history);
  history_broken_ = repairing.history_broken;
  config_.collector.time_offset_s = offset_s;
  if (odometry_)
    odometry_->restart();  // it integrates at the pairing's offset
}

void CalibrationSession::pairAtEstimatedOffset(const std::optional<InputRecordView>& record,
                                               std::size_t resumed, SessionFitRequest* request,
                                               OffsetPairing* pairing)
{
  pairing->configured_s = pairing->estimate_s = request->config.collector.time_offset_s;
  // Resumed pairs' inputs are not in the record: those pairs cannot be made again.
  if (!record || resumed > 0 || !request->config.estimate_time_offset || request->pairs.empty() ||
      request->encoder_history.empty())
    return;
  CalibrationJobOptions offset_only;
  offset_only.compare_trajectories = false;
  const CalibrationJobResult first =
      runCalibrationJob(request->config, request->pairs, request->encoder_history, offset_only);
  if (!first.time_offset || first.time_offset->flat)
    return;
  pairing->estimate_s = first.time_offset_s;
  char text[300];
  if (!(std::abs(pairing->estimate_s - pairing->configured_s) > kOffsetPairingToleranceS)) {
    std::snprintf(text, sizeof(text),
                  "paired at the configured time offset %.3f s (estimated %.3f s, within %.3f s)\n",
                  pairing->configured_s, pairing->estimate_s, kOffsetPairingToleranceS);
    pairing->text = text;
    request->offset_search = first.time_offset;  // the very pairs it was searched on
    return;
  }
  CollectorOptions options = request->config.collector;
  options.time_offset_s = pairing->estimate_s;
  Repairing repairing;
  buildCollectors(options, &repairing.collector, &repairing.candidates);
  feed(*record, &repairing);  // without the lock: the inputs go on meanwhile
  request->config.collector.time_offset_s = pairing->estimate_s;
  request->pairs = repairing.pairs;
  request->candidates =
      repairing.candidates ? repairing.candidates->pairs() : std::vector<IntervalPairs>();
  request->encoder_history =
      repairing.history_broken ? std::vector<EncoderSample>() : repairing.history;
  request->offset_search.reset();
  install(record->end(), std::move(repairing), pairing->estimate_s);
  pairing->paired_again = true;
  std::snprintf(text, sizeof(text),
                "paired again at the estimated time offset %.3f s (configured %.3f s: set "
                "keyframes.time_offset_s to it to pair once)\n",
                pairing->estimate_s, pairing->configured_s);
  pairing->text = text;
}

}  // namespace odometry_calibration
