#include "odometry_calibration/session/wheel_signals.h"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <utility>

namespace odometry_calibration {
namespace {

/// The unwrapper of each joint: its counter_bits (an absolute joint's reading is used as it is).
std::vector<TickUnwrapper> unwrappers(const CalibrationConfig& config)
{
  std::vector<TickUnwrapper> result;
  for (std::size_t j = 0; j < config.joints.size(); ++j) {
    const JointConfig& joint = config.joints[j];
    const std::string topic =
        j < config.wheels.topics.size() ? " on '" + config.wheels.topics[j] + "'" : "";
    const int bits = joint.kind == EncoderKind::kIncremental ? joint.counter_bits : 0;
    result.emplace_back(bits, "joints[" + std::to_string(j) + "].counter_bits",
                        "'" + joint.name + "'" + topic);
  }
  return result;
}

}  // namespace

WheelSignals::WheelSignals(const CalibrationConfig& config)
    : signs_(Eigen::VectorXd::Ones(static_cast<Eigen::Index>(config.joints.size()))),
      unwrappers_(unwrappers(config)),
      aligner_(std::max<std::size_t>(1, config.joints.size()), config.wheels.max_gap_s),
      integrator_(std::max<std::size_t>(1, config.joints.size()), config.wheels.max_gap_s,
                  "wheels.max_gap_s"),
      last_stamp_s_(config.joints.size(), -std::numeric_limits<double>::infinity())
{
  for (std::size_t j = 0; j < config.joints.size(); ++j)
    signs_(static_cast<Eigen::Index>(j)) = config.joints[j].sign;
}

std::vector<EncoderSample> WheelSignals::signed_(std::vector<EncoderSample> samples) const
{
  for (EncoderSample& sample : samples)
    sample.values = sample.values.cwiseProduct(signs_);
  return samples;
}

WheelSignalOutput WheelSignals::addTick(std::size_t wheel, double stamp_s, double raw)
{
  WheelSignalOutput output;
  if (wheel >= unwrappers_.size()) {
    output.problem =
        "a tick of wheel " + std::to_string(wheel) + " of " + std::to_string(unwrappers_.size());
    return output;
  }
  double& last_s = last_stamp_s_[wheel];
  if (stamp_s == last_s)
    return output;  // the same instant again
  if (stamp_s < last_s) {
    output.problem = "the ticks of wheel " + std::to_string(wheel) + " went back in time by " +
                     std::to_string(last_s - stamp_s) +
                     " s (a looped bag, a clock reset): unwrapping and alignment restart";
    for (TickUnwrapper& unwrapper : unwrappers_)
      unwrapper.restart();
    aligner_.restart();
    last_stamp_s_.assign(last_stamp_s_.size(), -std::numeric_limits<double>::infinity());
    return output;
  }
  try {
    const double count = unwrappers_[wheel].unwrap(stamp_s, raw);
    last_s = stamp_s;
    output.samples = signed_(aligner_.add(wheel, stamp_s, count));
  } catch (const std::invalid_argument& error) {
    output.problem = error.what();
  }
  return output;
}

WheelSignalOutput WheelSignals::addVelocities(double stamp_s, const Eigen::VectorXd& velocity)
{
  WheelSignalOutput output;
  try {
    std::string note;
    const Eigen::VectorXd position = integrator_.add(stamp_s, velocity, &note);
    output.samples = signed_({{stamp_s, position}});
    output.problem = note;
  } catch (const std::invalid_argument& error) {
    output.problem = error.what();
  }
  return output;
}

WheelSignalOutput WheelSignals::addBaseOdometry(double stamp_s, const Pose2& T_odom_base)
{
  WheelSignalOutput output;
  try {
    const std::optional<Eigen::Vector3d> path =
        base_path_.add(stamp_s, T_odom_base, &output.problem);
    if (path && static_cast<Eigen::Index>(signs_.size()) == path->size())
      output.samples = signed_({{stamp_s, *path}});
    else if (path)
      output.problem = "a base odometry message for " + std::to_string(signs_.size()) +
                       " joints: set wheels.source odometry (its own three joints)";
  } catch (const std::invalid_argument& error) {
    output.problem = error.what();
  }
  return output;
}

}  // namespace odometry_calibration
