#include "odometry_calibration/data/base_odometry_path.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// Positions farther from the odom origin are refused: summed into the path, increments of
/// that size would leave it no precision for the real ones (a double keeps 1e-9 m at 1e7 m).
constexpr double kMaxPosition_m = 1e7;

}  // namespace

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
  if (std::abs(T_odom_base.x()) > kMaxPosition_m || std::abs(T_odom_base.y()) > kMaxPosition_m) {
    std::ostringstream text;
    text << "a base odometry message at " << stamp_s << " s with position (" << T_odom_base.x()
         << ", " << T_odom_base.y() << ") m: beyond " << kMaxPosition_m
         << " m from the odom origin, not a pose; not used";
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
    path_ += (previous_pose_.inverse() * T_odom_base).vector();
  }
  has_previous_ = true;
  previous_stamp_s_ = stamp_s;
  previous_pose_ = T_odom_base;
  return path_;
}

}  // namespace odometry_calibration
