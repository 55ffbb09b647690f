// Joint positions from joint velocities alone (a JointState whose `position` is empty and whose
// `velocity` is filled), integrated between stamps with the trapezoid rule:
//   p_k = p_{k-1} + (v_{k-1} + v_k) / 2 * (t_k - t_{k-1}),   p_0 = 0,
// exact for velocities linear in time between two messages. Across a gap longer than
// max_gap_s the velocity in between is unknown: the positions are held (not integrated) and the
// integration restarts at the new message, which says so; the joint stream's own gap then drops
// the pairs across it (keyframes.max_encoder_gap_s). Time going backwards restarts it the same
// way. Positions are in the velocities' units times seconds (rad for rad/s).
#pragma once

#include <cstddef>
#include <string>

#include <Eigen/Core>

namespace odometry_calibration {

/// Integrates the velocities of `joints` joints into positions.
class VelocityIntegrator
{
public:
  /// Throws std::invalid_argument for no joint or a max_gap_s that is not positive [s].
  VelocityIntegrator(std::size_t joints, double max_gap_s, std::string gap_key);

  /// The positions at `stamp_s` [s] after velocities `velocity` [units/s] (joints' order).
  /// `note` (when given) is set to why this message restarted the integration (a gap, time
  /// going backwards), else cleared. Throws std::invalid_argument for a size mismatch or a
  /// value that is not finite (the message is not used). A stamp equal to the last one is
  /// ignored (the positions as they are).
  Eigen::VectorXd add(double stamp_s, const Eigen::VectorXd& velocity, std::string* note = nullptr);

private:
  std::size_t joints_;
  double max_gap_s_;
  std::string gap_key_;
  bool has_previous_ = false;
  double previous_stamp_s_ = 0.0;
  Eigen::VectorXd previous_velocity_, position_;
};

}  // namespace odometry_calibration
