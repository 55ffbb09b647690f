// The live node's input health: silent-topic warnings and /diagnostics.
#include <cmath>

#include <diagnostic_msgs/DiagnosticArray.h>

#include "odometry_calibration/ros/calibration_node.h"

namespace odometry_calibration {

// --- Health -------------------------------------------------------------------------------

void CalibrationNode::onTimer(const ros::WallTimerEvent& event)
{
  std::lock_guard<std::mutex> lock(state_mutex_);
  const double period_s = event.last_real.isZero() ? options_.diagnostics_period_s
                                                   : (event.current_real - event.last_real).toSec();
  warnSilentTopics();
  writePendingPairs();
  publishDiagnostics(period_s);
  publishPaths();
}

void CalibrationNode::writePendingPairs()
{
  if (pairs_unwritten_ == 0)
    return;
  const std::string pairs_path = options_.output_directory + "/pairs.csv";
  try {
    if (!appender_)  // a reset could not create the file
      appender_ = std::make_unique<PairsCsvAppender>(pairs_path, jointLayout(config_));
    for (; pairs_unwritten_ > 0; --pairs_unwritten_)
      appender_->append(pairs_[pairs_.size() - pairs_unwritten_]);
  } catch (const std::exception& error) {
    if (pairs_file_problem_.empty()) {
      ROS_ERROR(
          "%s: the pairs stay in memory (%zu not written yet) and are written when the disk "
          "takes them again (retried with every pair and every %.1f s)",
          error.what(), pairs_unwritten_, options_.diagnostics_period_s);
    }
    pairs_file_problem_ = error.what();
    return;
  }
  if (!pairs_file_problem_.empty()) {
    ROS_INFO("the pairs file %s is written again: no pair lost", pairs_path.c_str());
    pairs_file_problem_.clear();
  }
}

void CalibrationNode::warnSilentTopics()
{
  const ros::WallTime now = ros::WallTime::now();
  for (TopicHealth* health : {&joint_health_, &ego_health_}) {
    const ros::WallTime since = health->messages == 0 ? started_ : health->last_message;
    const double silent_s = (now - since).toSec();
    if (silent_s > options_.silent_topic_timeout_s &&
        (now - health->last_warning).toSec() > options_.silent_topic_timeout_s) {
      health->last_warning = now;
      if (health->messages == 0) {
        ROS_WARN("no message on '%s' after %.0f s: is the topic name right? (rostopic info %s)",
                 health->topic.c_str(), silent_s, health->topic.c_str());
      } else {
        ROS_WARN("'%s' has been silent for %.0f s", health->topic.c_str(), silent_s);
      }
    }
  }
}

void CalibrationNode::publishDiagnostics(double period_s)
{
  diagnostic_msgs::DiagnosticArray array;
  array.header.stamp = ros::Time::now();
  diagnostic_msgs::DiagnosticStatus status;
  status.name = ros::this_node::getName() + ": calibration";
  status.hardware_id = sensorFrame();
  auto add = [&status](const std::string& key, const std::string& value) {
    diagnostic_msgs::KeyValue entry;
    entry.key = key;
    entry.value = value;
    status.values.push_back(entry);
  };
  const ros::WallTime now = ros::WallTime::now();
  std::vector<std::string> problems;
  for (TopicHealth* health : {&joint_health_, &ego_health_}) {
    const double rate = (health->messages - health->messages_at_last_tick) / period_s;
    health->messages_at_last_tick = health->messages;
    add(health->topic + " rate [Hz]", std::to_string(rate));
    const ros::WallTime since = health->messages == 0 ? started_ : health->last_message;
    if ((now - since).toSec() > options_.silent_topic_timeout_s)
      problems.push_back("no input on " + health->topic);
  }
  const CollectorStatistics& s = collector_->statistics();
  const double icp_success =
      s.consecutive_matches > 0
          ? 1.0 - static_cast<double>(s.consecutive_failures) / s.consecutive_matches
          : std::nan("");
  std::size_t rejected = 0;
  for (const auto& [reason, count] : s.rejected)
    rejected += count;
  add("scan matching success ratio", std::to_string(icp_success));
  add("pairs collected", std::to_string(pairs_.size()));
  add("pairs resumed from file", std::to_string(pairs_resumed_));
  add("pairs not yet in the pairs file", std::to_string(pairs_unwritten_));
  if (!pairs_file_problem_.empty())
    problems.push_back("cannot write the pairs file (pairs kept in memory): " +
                       pairs_file_problem_);
  add("keyframe intervals rejected", std::to_string(rejected));
  for (const auto& [reason, count] : s.rejected)
    add("rejected: " + reason, std::to_string(count));
  add("JointStates skipped", std::to_string(bad_joint_states_));
  for (const auto& channel : channels_) {
    const auto found = s.glitches.find(channel.name);
    add("encoder glitches: " + channel.name,
        std::to_string(found == s.glitches.end() ? 0 : found->second));
  }
  add("scans skipped", std::to_string(bad_scans_));
  if (config_.ego_motion == EgoMotionSource::kCloud)
    add("clouds without per-point times", std::to_string(clouds_without_times_));
  add("restarts (time went backwards)", std::to_string(s.restarts));
  add("model", active_model_ ? active_model_->name() + " (" + active_model_origin_ + ")"
                             : std::string("none"));
  add("time offset [s]", std::to_string(config_.collector.time_offset_s));
  if (!last_problem_.empty())
    add("last problem", last_problem_);
  if (!problems.empty()) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    status.message = problems.front();
  } else if (s.consecutive_matches > 10 && icp_success < 0.9) {
    status.level = diagnostic_msgs::DiagnosticStatus::WARN;
    status.message = "scan matching fails often";
  } else {
    status.level = diagnostic_msgs::DiagnosticStatus::OK;
    status.message = std::to_string(pairs_.size()) + " pairs";
  }
  array.status.push_back(status);
  publishAssistant(array.status);
  diagnostics_publisher_.publish(array);
}

}  // namespace odometry_calibration
