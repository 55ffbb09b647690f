// The session's statuses for /diagnostics: the collection ("calibration") and the assistant's.
#include <cmath>

#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {
namespace {

/// Scan matching's success ratio (nan before the first consecutive match).
double matchingSuccess(const CollectorStatistics& s)
{
  return s.consecutive_matches > 0
             ? 1.0 - static_cast<double>(s.consecutive_failures) / s.consecutive_matches
             : std::nan("");
}

}  // namespace

std::vector<std::string> CalibrationSession::collectionNotes() const
{
  const SessionCounts c = counts();
  const std::string ego_type = egoMessageType(config_.ego_motion);
  std::vector<std::string> notes;
  if (c.ignored_encoder_messages > 0) {
    notes.push_back("ignored " + std::to_string(c.ignored_encoder_messages) +
                    " JointState messages from " + publisherName(c.ignored_encoder_publisher) +
                    " (joint_state_publisher: " + publisherName(c.encoder_publisher) + ")");
  }
  if (c.ignored_ego_messages > 0) {
    notes.push_back("ignored " + std::to_string(c.ignored_ego_messages) + " " + ego_type +
                    " messages from " + publisherName(c.ignored_ego_publisher) + " (" +
                    config_.ego_motion_publisher_key + ": " + publisherName(c.ego_publisher) + ")");
  }
  if (c.bad_encoder_messages > 0) {
    notes.push_back("skipped " + std::to_string(c.bad_encoder_messages) +
                    (config_.wheels.source == WheelSource::kTicks      ? " wheel tick"
                     : config_.wheels.source == WheelSource::kOdometry ? " base odometry"
                                                                       : " JointState") +
                    " messages, first: " + c.first_bad_encoder_message);
  }
  if (c.clouds_without_times > 0) {
    notes.push_back(std::to_string(c.clouds_without_times) +
                    " PointCloud2 messages used without their per-point times, first: " +
                    c.first_cloud_time_problem);
  }
  if (c.bad_ego_messages > 0) {
    notes.push_back("skipped " + std::to_string(c.bad_ego_messages) + " " + ego_type +
                    " messages, first: " + c.first_bad_ego_message);
  }
  for (const auto& [joint, count] : c.statistics.glitches) {
    const auto wrap = c.statistics.glitch_wrap_bits.find(joint);
    const std::string cause =
        wrap == c.statistics.glitch_wrap_bits.end()
            ? "increments beyond its max_turns_per_s"
            : "steps of a whole 2^" + std::to_string(wrap->second) +
                  " counts: its counter wraps at " + std::to_string(wrap->second) +
                  " bits; set joints[].counter_bits: " + std::to_string(wrap->second) + " for '" +
                  joint + "'";
    notes.push_back("skipped " + std::to_string(count) + " encoder glitches on joint '" + joint +
                    "' (" + cause + ")");
  }
  for (const std::string& restart : c.restarts)
    notes.push_back("restart " + restart);
  return notes;
}

std::string CalibrationSession::collectionStatus(SessionStatusReport* status) const
{
  const CollectorStatistics& s = collector_->statistics();
  std::size_t rejected = 0;
  for (const auto& [reason, count] : s.rejected)
    rejected += count;
  status->add("scan matching success ratio", s.consecutive_matches > 0
                                                 ? std::to_string(matchingSuccess(s))
                                                 : std::string("no consecutive match yet"));
  status->add("pairs collected", std::to_string(store_->pairs().size()));
  status->add("pairs resumed from file", std::to_string(store_->resumed()));
  status->add("pairs not yet in the pairs file", std::to_string(store_->unwritten()));
  status->add("keyframe intervals rejected", std::to_string(rejected));
  for (const auto& [reason, count] : s.rejected)
    status->add("rejected: " + reason, std::to_string(count));
  status->add("JointStates skipped", std::to_string(counts_.bad_encoder_messages));
  for (const auto& channel : channels_) {
    const auto found = s.glitches.find(channel.name);
    status->add("encoder glitches: " + channel.name,
                std::to_string(found == s.glitches.end() ? 0 : found->second));
  }
  status->add("scans skipped", std::to_string(counts_.bad_ego_messages));
  if (config_.ego_motion == EgoMotionSource::kCloud)
    status->add("clouds without per-point times", std::to_string(counts_.clouds_without_times));
  status->add("restarts (time went backwards)", std::to_string(s.restarts));
  status->add("model", active_model_ ? active_model_->name() + " (" + active_model_origin_ + ")"
                                     : std::string("none"));
  status->add("time offset [s]", std::to_string(config_.collector.time_offset_s));
  if (last_fit_counts_) {  // as the fit's reply and report count them
    status->add("last fit: pairs used", std::to_string(last_fit_counts_->used));
    status->add("last fit: pairs rejected", std::to_string(last_fit_counts_->rejected));
    status->add("last fit: pairs down-weighted", std::to_string(last_fit_counts_->down_weighted));
  }
  if (!last_problem_.empty())
    status->add("last problem", last_problem_);
  if (!store_->problem().empty())
    return "cannot write the pairs file (pairs kept in memory): " + store_->problem();
  return "";
}

std::vector<SessionStatusReport> CalibrationSession::statusReports(double period_s)
{
  std::lock_guard<std::mutex> lock(mutex_);
  SessionStatusReport status;
  status.name = "calibration";
  std::vector<std::string> problems;
  inputs_->addRates(&status, &problems, now(), period_s);
  const std::string file_problem = collectionStatus(&status);
  if (!file_problem.empty())
    problems.push_back(file_problem);
  const CollectorStatistics& s = collector_->statistics();
  for (const std::string& problem : encoder_watch_->problems(s.glitches))
    problems.push_back(problem);
  status.add("encoder readings' spacing [s] (median)",
             std::isfinite(s.encoder_spacing_median_s) ? std::to_string(s.encoder_spacing_median_s)
                                                       : std::string("none yet"));
  status.add("max encoder gap in use [s]", std::to_string(s.max_encoder_gap_s));
  status.add("messages from other publishers ignored",
             std::to_string(publishers_->ignored(SessionInput::kEncoders) +
                            publishers_->ignored(SessionInput::kEgoMotion)));
  const std::string conflict =
      publishers_->conflict().empty() ? counts_.configuration_conflict : publishers_->conflict();
  if (!conflict.empty()) {
    status.level = SessionStatusReport::Level::kError;
    status.message = conflict;
  } else if (!problems.empty()) {
    status.level = SessionStatusReport::Level::kWarn;
    status.message = problems.front();
  } else if (s.consecutive_matches > 10 && matchingSuccess(s) < 0.9) {
    status.level = SessionStatusReport::Level::kWarn;
    status.message = "scan matching fails often";
  } else {
    status.message = std::to_string(store_->pairs().size()) + " pairs";
  }
  std::vector<SessionStatusReport> statuses{status};
  if (assistant_)
    assistant_->addStatuses(&statuses);
  return statuses;
}

}  // namespace odometry_calibration
