#include "odometry_calibration/data/base_odometry_path.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {

std::optional<Eigen::Vector3d> BaseOdometryPath::add(double stamp_s, const Pose2& T_odom_base,
                                                     std::string* note)
{
  if (note != nullptr)
    note->clear();
  if (!std::isfinite(stamp_s) || !T_odom_base.vector().allFinite()) {
    std::ostringstream text;
    text << "a base odometry message at " << stamp_s << " s with pose (" << T_odom_base.x()
         << " m, " << T_odom_base.y() << " m, " << T_odom_base.theta()
         << " rad): not finite, not used";
    throw std::invalid_argument(text.str());
  }
  if (has_previous_ && stamp_s == previous_stamp_s_)
    return std::nullopt;
  if (has_previous_ && stamp_s < previous_stamp_s_) {
    if (note != nullptr) {
      std::ostringstream text;
      text << "the base odometry went back in time by " << previous_stamp_s_ - stamp_s
           << " s (a looped bag, a clock reset): its increments restart here";
      *note = text.str();
    }
    has_previous_ = false;
  }
  if (has_previous_) {
    const Pose2 step = previous_pose_.inverse() * T_odom_base;
    if (!step.vector().allFinite()) {
      std::ostringstream text;
      text << "a base odometry message at " << stamp_s << " s: the increment from ("
           << previous_pose_.x() << ", " << previous_pose_.y() << ") m to (" << T_odom_base.x()
           << ", " << T_odom_base.y() << ") m is not finite, not used";
      throw std::invalid_argument(text.str());
    }
    path_ += step.vector();
  }
  has_previous_ = true;
  previous_stamp_s_ = stamp_s;
  previous_pose_ = T_odom_base;
  return path_;
}

}  // namespace odometry_calibration
