#include "odometry_calibration/data/velocity_integrator.h"

#include <cmath>
#include <stdexcept>
#include <utility>

namespace odometry_calibration {

VelocityIntegrator::VelocityIntegrator(std::size_t joints, double max_gap_s, std::string gap_key)
    : joints_(joints),
      max_gap_s_(max_gap_s),
      gap_key_(std::move(gap_key)),
      position_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints)))
{
  if (joints == 0)
    throw std::invalid_argument("velocity integration of no joint");
  if (!(max_gap_s > 0.0) || !std::isfinite(max_gap_s))
    throw std::invalid_argument(gap_key_ + " must be a positive number of seconds");
}

Eigen::VectorXd VelocityIntegrator::add(double stamp_s, const Eigen::VectorXd& velocity,
                                        std::string* note)
{
  if (note)
    note->clear();
  if (static_cast<std::size_t>(velocity.size()) != joints_) {
    throw std::invalid_argument(std::to_string(velocity.size()) + " velocities for " +
                                std::to_string(joints_) + " joints");
  }
  if (!std::isfinite(stamp_s) || !velocity.allFinite())
    throw std::invalid_argument("a joint velocity or its stamp is not a finite number");
  if (has_previous_ && stamp_s == previous_stamp_s_)
    return position_;
  const double dt = stamp_s - previous_stamp_s_;
  if (has_previous_ && dt > 0.0 && dt <= max_gap_s_) {
    const Eigen::VectorXd position = position_ + 0.5 * (previous_velocity_ + velocity) * dt;
    if (!position.allFinite()) {
      throw std::invalid_argument(
          "joint velocities of up to " + std::to_string(velocity.cwiseAbs().maxCoeff()) +
          " units/s integrate to positions beyond a double's range: not a wheel's speed");
    }
    position_ = position;
  } else if (has_previous_ && note) {
    *note = dt < 0.0 ? "the joint velocities' time went back by " + std::to_string(-dt) +
                           " s (a looped bag, a clock reset): integration restarted"
                     : "no joint velocity for " + std::to_string(dt) + " s (more than " + gap_key_ +
                           " " + std::to_string(max_gap_s_) +
                           " s): the motion in between is unknown, integration restarted";
  }
  has_previous_ = true;
  previous_stamp_s_ = stamp_s;
  previous_velocity_ = velocity;
  return position_;
}

}  // namespace odometry_calibration
