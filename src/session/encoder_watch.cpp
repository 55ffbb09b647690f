#include "odometry_calibration/session/encoder_watch.h"

#include <utility>

namespace odometry_calibration {

EncoderWatch::EncoderWatch(std::vector<EncoderChannelOptions> channels, std::size_t stuck_readings)
    : channels_(std::move(channels)), stuck_readings_(stuck_readings), joints_(channels_.size())
{
}

void EncoderWatch::add(const Eigen::VectorXd& raw)
{
  if (static_cast<std::size_t>(raw.size()) != joints_.size())
    return;
  std::vector<bool> changed(joints_.size(), false);
  std::size_t incremental_changed = 0;
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    changed[i] = has_reading_ && raw(static_cast<Eigen::Index>(i)) != joints_[i].last;
    if (changed[i] && channels_[i].kind == EncoderKind::kIncremental)
      ++incremental_changed;
  }
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    Joint& joint = joints_[i];
    if (changed[i] || !has_reading_)
      joint.unchanged = 0;
    else if (channels_[i].kind == EncoderKind::kIncremental && incremental_changed > 0)
      ++joint.unchanged;  // still while another wheel turns
    joint.last = raw(static_cast<Eigen::Index>(i));
  }
  has_reading_ = true;
}

std::vector<std::string> EncoderWatch::problems(const std::map<std::string, std::size_t>& glitches)
{
  std::vector<std::string> found;
  for (std::size_t i = 0; i < joints_.size(); ++i) {
    Joint& joint = joints_[i];
    const std::string& name = channels_[i].name;
    if (joint.unchanged >= stuck_readings_) {
      found.push_back("encoder of joint '" + name + "' stuck: the same reading " +
                      std::to_string(joint.unchanged) +
                      " times in a row while the other wheels turn (or a turn about that wheel)");
    }
    const auto count = glitches.find(name);
    const std::size_t total = count == glitches.end() ? 0 : count->second;
    if (total > joint.glitches_seen) {
      found.push_back("encoder of joint '" + name +
                      "' glitching: " + std::to_string(total - joint.glitches_seen) +
                      " readings skipped as glitches since the last status (" +
                      std::to_string(total) + " in all; a stuck or corrupted reading?)");
    }
    joint.glitches_seen = total;
  }
  return found;
}

}  // namespace odometry_calibration
