// A base's own odometry (nav_msgs/Odometry poses T_odom_base) made three cumulative joint
// positions, the input of the base_odometry model (models/base_odometry_model.h), the linear
// model and the GP: message by message the increment in base_link at the previous message,
//   (ds, dl, dtheta) = T_{k-1}^-1 T_k,
// is summed into the forward path s [m], the lateral path l [m] and the heading theta [rad]
// (theta unwrapped). Between two consecutive messages the joints' increments are thus exactly
// the base's pose increment; over several messages their composition is.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

class BaseOdometryPath
{
public:
  /// The cumulative (s, l, theta) [m, m, rad] after the base's pose `T_odom_base` at `stamp_s`
  /// [s], or nothing for a stamp equal to the last one. The first message starts at (0, 0, 0).
  /// Time going backwards (a looped bag, a restarted clock) restarts the increments at this
  /// message (the path is held) and sets `note` (when given) to why; otherwise `note` is
  /// cleared. Throws std::invalid_argument for a stamp or pose that is not finite, or a position
  /// more than 1e7 m from the odom origin (1e308: increments that size would leave the path no
  /// precision), naming the values: the message is not used, the next is taken from the last
  /// one used.
  std::optional<Eigen::Vector3d> add(double stamp_s, const Pose2& T_odom_base,
                                     std::string* note = nullptr);

private:
  bool has_previous_ = false;
  double previous_stamp_s_ = 0.0;
  Pose2 previous_pose_;
  Eigen::Vector3d path_ = Eigen::Vector3d::Zero();
};

}  // namespace odometry_calibration
