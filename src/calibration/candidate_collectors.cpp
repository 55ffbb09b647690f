#include "odometry_calibration/calibration/candidate_collectors.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {

struct CandidateCollectors::Candidate
{
  double interval_s = 0.0;
  std::unique_ptr<PairCollector> collector;
  std::vector<MotionPair> pairs;
};

CandidateCollectors::CandidateCollectors(const std::vector<EncoderChannelOptions>& channels,
                                         const CollectorOptions& options,
                                         const MotionPredictor& predictor,
                                         const std::vector<double>& intervals_s)
    : channels_(channels), options_(options), predictor_(predictor)
{
  for (const double interval : intervals_s) {
    if (!(interval > 0.0) || !std::isfinite(interval)) {
      throw std::invalid_argument("candidate keyframe interval must be > 0 s, got " +
                                  std::to_string(interval));
    }
    auto candidate = std::make_unique<Candidate>();
    candidate->interval_s = interval;
    CollectorOptions at_interval = options_;
    at_interval.keyframe_interval_s = interval;
    candidate->collector = std::make_unique<PairCollector>(channels_, at_interval, predictor_);
    candidates_.push_back(std::move(candidate));
  }
}

CandidateCollectors::~CandidateCollectors() = default;

void CandidateCollectors::keep(Candidate& candidate, const std::vector<CollectorEvent>& events)
{
  for (const CollectorEvent& event : events) {
    if (event.type == CollectorEvent::Type::kPair)
      candidate.pairs.push_back(event.pair);
  }
}

void CandidateCollectors::addEncoders(double stamp_s, const Eigen::VectorXd& raw)
{
  for (auto& candidate : candidates_)
    keep(*candidate, candidate->collector->addEncoders(stamp_s, raw));
}

void CandidateCollectors::addScan(double stamp_s, const Scan& scan)
{
  for (auto& candidate : candidates_)
    keep(*candidate, candidate->collector->addScan(stamp_s, scan));
}

void CandidateCollectors::addSensorPose(double stamp_s, const Pose2& T_world_sensor,
                                        const Eigen::Matrix3d& covariance)
{
  for (auto& candidate : candidates_)
    keep(*candidate, candidate->collector->addSensorPose(stamp_s, T_world_sensor, covariance));
}

void CandidateCollectors::flush()
{
  for (auto& candidate : candidates_)
    keep(*candidate, candidate->collector->flush());
}

void CandidateCollectors::clear()
{
  for (auto& candidate : candidates_) {
    candidate->collector->reset();
    candidate->pairs.clear();
  }
}

std::vector<IntervalPairs> CandidateCollectors::pairs() const
{
  std::vector<IntervalPairs> all;
  for (const auto& candidate : candidates_)
    all.push_back({candidate->interval_s, candidate->pairs});
  return all;
}

}  // namespace odometry_calibration
