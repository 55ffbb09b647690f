// The pair collector's results folded in submission order: the consecutive matches into the
// chain, the keyframe matches into pairs or rejections checked against it, and every event in
// the order a one-threaded run makes them (pair_collector.h).
#include <cmath>
#include <utility>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/pairing/pair_collector.h"

namespace odometry_calibration {
namespace {

/// Chains shorter than this stay out of the scale check: their direction is noise [m].
constexpr double kScaleCheckMinChain_m = 0.01;

}  // namespace

const CollectorStatistics& PairCollector::statistics() const
{
  fold(Fold::kAll);
  statistics_.encoder_spacing_median_s = encoder_spacing_.median_s();
  statistics_.encoder_spacings = encoder_spacing_.count();
  statistics_.max_encoder_gap_s = encoderGapLimit_s();
  return statistics_;
}

void PairCollector::fold(Fold how) const
{
  std::size_t count = unfolded_.size();
  if (how == Fold::kThroughLastEvent) {
    while (count > 0 && unfolded_[count - 1].consecutive)
      --count;
  }
  for (; count > 0; --count) {
    const Unfolded& front = unfolded_.front();
    const std::shared_ptr<MatchJob>& job = front.consecutive ? front.consecutive : front.keyframe;
    if (how == Fold::kDone && job && !matches_->done(job))
      return;
    foldFront();
  }
}

void PairCollector::foldFront() const
{
  Unfolded front = std::move(unfolded_.front());
  unfolded_.pop_front();
  if (const std::shared_ptr<MatchJob>& job =
          front.consecutive ? front.consecutive : front.keyframe) {
    const PlicpResult result = matches_ ? matches_->wait(job) : job->result;
    statistics_.preparation_time_s += job->preparation_time_s;
    statistics_.matching_time_s += job->matching_time_s;
    if (front.keyframe)
      front.event = concludeKeyframeMatch(result, front.event.pair);
    // A one-threaded run matches only while the chain is valid: later matches after a failure
    // were submitted speculatively and are dropped uncounted.
    if (front.consecutive && chain_valid_) {
      ++statistics_.consecutive_matches;
      statistics_.consecutive_rematched_all_rays += job->fine_rematched ? 1 : 0;
      if (result.valid()) {
        chain_ = chain_ * result.T_ref_new;
      } else {
        ++statistics_.consecutive_failures;
        chain_valid_ = false;
      }
    }
  }
  if (!front.consecutive && front.event.type != CollectorEvent::Type::kNothing)
    ready_.push_back(std::move(front.event));
  if (front.ends_chain) {
    chain_ = Pose2();
    chain_valid_ = true;
  }
}

std::vector<CollectorEvent> PairCollector::takeEvents()
{
  if (options_.defer_keyframe_matches) {
    if (matches_)
      matches_->runWhileQueuedAbove(kMaxQueuedMatches);
    fold(Fold::kDone);
  } else {
    fold(Fold::kThroughLastEvent);
  }
  return std::exchange(ready_, {});
}

void PairCollector::queueEvent(const CollectorEvent& event, bool ends_chain)
{
  Unfolded entry;
  entry.event = event;
  entry.ends_chain = ends_chain;
  unfolded_.push_back(std::move(entry));
}

bool PairCollector::consistentWithChain(const PlicpResult& match) const
{
  const Pose2 difference = between(chain_, match.T_ref_new);
  if (std::hypot(difference.x(), difference.y()) > options_.consistency_translation_m ||
      std::abs(difference.theta()) > options_.consistency_rotation_rad) {
    return false;
  }
  const Eigen::Vector2d chain_m(chain_.x(), chain_.y());
  if (chain_m.norm() >= kScaleCheckMinChain_m) {
    const double keyframe_m =
        Eigen::Vector2d(match.T_ref_new.x(), match.T_ref_new.y()).dot(chain_m) / chain_m.norm();
    ++statistics_.scale_check_pairs;
    statistics_.chained_m += chain_m.norm();
    statistics_.keyframe_along_chain_m += keyframe_m;
    statistics_.chained_m2 += chain_m.squaredNorm();
    statistics_.keyframe_along_chain_m2 += keyframe_m * keyframe_m;
    statistics_.chained_times_keyframe_m2 += keyframe_m * chain_m.norm();
  }
  return true;
}

CollectorEvent PairCollector::concludeKeyframeMatch(const PlicpResult& match,
                                                    const MotionPair& interval) const
{
  if (!match.valid())
    return reject(std::string("scan match ") + toString(match.status));
  if (options_.pair_motion_from_chain && !chain_valid_)
    return reject("a consecutive match failed (pair motion from the chain)");
  if (options_.check_consistency && !chain_valid_) {
    ++statistics_.unverified_pairs;  // a consecutive match failed: nothing to compare with
  } else if (options_.check_consistency && !consistentWithChain(match)) {
    return reject("keyframe match disagrees with consecutive matches");
  }
  return pairEvent(interval, options_.pair_motion_from_chain ? chain_ : match.T_ref_new,
                   match.covariance);
}

CollectorEvent PairCollector::pairEvent(MotionPair interval, const Pose2& sensor_motion,
                                        const Eigen::Matrix3d& covariance) const
{
  CollectorEvent event;
  event.type = CollectorEvent::Type::kPair;
  event.pair = std::move(interval);
  event.pair.sensor_motion = sensor_motion;
  event.pair.covariance = covariance;
  event.pair.covariance.diagonal() += options_.covariance_floor;
  ++statistics_.pairs;
  return event;
}

CollectorEvent PairCollector::reject(const std::string& reason) const
{
  ++statistics_.rejected[reason];
  CollectorEvent event;
  event.type = CollectorEvent::Type::kRejected;
  event.reason = reason;
  return event;
}

}  // namespace odometry_calibration
