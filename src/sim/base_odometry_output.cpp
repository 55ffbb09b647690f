#include "odometry_calibration/sim/base_odometry_output.h"

namespace odometry_calibration {
namespace sim {

BaseOdometryOutput::BaseOdometryOutput(const EncoderOptions& encoders, const Pose2& T_world_start)
    : enabled_(encoders.output == "odometry"),
      translation_error_(encoders.odometry_translation_error),
      rotation_error_(encoders.odometry_rotation_error),
      previous_T_world_base_(T_world_start)
{
}

void BaseOdometryOutput::publish(double stamp_s, const Pose2& T_world_base, const Twist2& realised,
                                 SimulationSink& sink)
{
  if (!enabled_)
    return;
  const double e_t = translation_error_, e_r = rotation_error_;
  const Pose2 step = previous_T_world_base_.inverse() * T_world_base;
  T_odom_base_ = T_odom_base_ *
                 Pose2((1.0 + e_t) * step.x(), (1.0 + e_t) * step.y(), (1.0 + e_r) * step.theta());
  previous_T_world_base_ = T_world_base;
  Twist2 twist = realised;
  twist.vx_mps *= 1.0 + e_t;
  twist.vy_mps *= 1.0 + e_t;
  twist.omega_radps *= 1.0 + e_r;
  sink.onBaseOdometry({stamp_s, T_odom_base_, twist});
}

}  // namespace sim
}  // namespace odometry_calibration
