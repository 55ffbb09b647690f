// The simulator's base odometry output (encoders.output odometry): the base's own odometry as a
// controller reports it, with its scale errors, from the true motion. At each encoder instant
// the true motion since the last one, T_prev^-1 T_now = (dx, dy, dtheta), is reported as
// ((1 + e_t) dx, (1 + e_t) dy, (1 + e_r) dtheta) and composed onto the reported pose; the twist
// is the realised one with the same factors (e_t = encoders.odometry_translation_error, e_r =
// encoders.odometry_rotation_error).
#pragma once

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace sim {

class BaseOdometryOutput
{
public:
  /// `encoders`' output (a sample only with `odometry`) and scale errors; the robot starts at
  /// `T_world_start`.
  BaseOdometryOutput(const EncoderOptions& encoders, const Pose2& T_world_start);

  /// At the encoder instant stamped `stamp_s` [s] (encoder clock), the robot now at
  /// `T_world_base` moving with `realised`: its sample to `sink` (with encoders.output odometry).
  void publish(double stamp_s, const Pose2& T_world_base, const Twist2& realised,
               SimulationSink& sink);

private:
  bool enabled_;
  double translation_error_, rotation_error_;
  Pose2 previous_T_world_base_;  ///< the truth at the last encoder instant
  Pose2 T_odom_base_;            ///< the reported pose
};

}  // namespace sim
}  // namespace odometry_calibration
