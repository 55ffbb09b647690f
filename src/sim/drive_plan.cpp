#include "odometry_calibration/sim/drive_plan.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {
namespace sim {

void validate(const DrivePlanOptions& options)
{
  auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value)) {
      throw std::invalid_argument(std::string("motion option '") + name + "' must be > 0");
    }
  };
  if (options.type != "random" && options.type != "scripted") {
    throw std::invalid_argument("motion option 'type' must be 'random' or 'scripted', got '" +
                                options.type + "'");
  }
  positive(options.max_speed_mps, "max_speed_mps");
  positive(options.max_turn_rate_radps, "max_turn_rate_radps");
  positive(options.min_segment_s, "min_segment_s");
  positive(options.lookahead_s, "lookahead_s");
  if (!(options.max_segment_s >= options.min_segment_s)) {
    throw std::invalid_argument("motion option 'max_segment_s' must be >= min_segment_s");
  }
  if (!(options.max_acceleration_mps2 >= 0.0) ||
      !(options.max_angular_acceleration_radps2 >= 0.0)) {
    throw std::invalid_argument("motion accelerations must be >= 0 (0 = instant)");
  }
  if (!(options.clearance_m >= 0.0)) {
    throw std::invalid_argument("motion option 'clearance_m' must be >= 0");
  }
  if (options.type == "scripted" && options.script.empty()) {
    throw std::invalid_argument("motion type 'scripted' needs a non-empty 'script'");
  }
  for (const ScriptedMotion& motion : options.script) {
    positive(motion.duration_s, "script[].duration_s");
  }
}

DrivePlanner::DrivePlanner(DrivePlanOptions options, const Robot& robot, const World& world,
                           double footprint_radius_m, unsigned seed)
    : options_(std::move(options)),
      robot_(robot),
      world_(world),
      footprint_radius_m_(footprint_radius_m),
      rng_(seed)
{
  validate(options_);
}

bool DrivePlanner::isSafe(const Twist2& twist, const Pose2& T_world_base) const
{
  const double step_s = 0.1;
  for (double t = step_s; t <= options_.lookahead_s + 1e-9; t += step_s) {
    const Pose2 ahead = T_world_base * integrateTwist(twist, t);
    if (world_.clearance(Eigen::Vector2d(ahead.x(), ahead.y())) <
        footprint_radius_m_ + options_.clearance_m) {
      return false;
    }
  }
  return true;
}

Twist2 DrivePlanner::randomMotion()
{
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  const double v_max = options_.max_speed_mps;
  const double w_max = options_.max_turn_rate_radps;
  double sign = unit(rng_) < 0.5 ? -1.0 : 1.0;
  if (!options_.left_turns)
    sign = -1.0;
  if (!options_.right_turns)
    sign = 1.0;
  const bool turns = options_.left_turns || options_.right_turns;
  const bool spot_turns = robot_.canTurnInPlace() && options_.turning_in_place && turns;
  Twist2 twist;
  auto arc = [&]() {
    twist.vx_mps = v_max * (0.2 + 0.8 * unit(rng_)) * (unit(rng_) < 0.8 ? 1.0 : -1.0);
    twist.omega_radps = turns ? sign * w_max * (0.2 + 0.8 * unit(rng_)) : 0.0;
  };
  // Weights: forward straight, reverse, arcs, turning on the spot, sideways (a motion the robot
  // cannot do or the options leave out becomes an arc).
  const double pick = unit(rng_);
  if (pick < 0.2) {
    twist.vx_mps = v_max * (0.3 + 0.7 * unit(rng_));
  } else if (pick < 0.35) {
    twist.vx_mps = -v_max * (0.2 + 0.5 * unit(rng_));
  } else if (pick < 0.75 || (pick < 0.9 && !spot_turns)) {
    arc();
  } else if (pick < 0.9 || (!robot_.canDriveSideways() && spot_turns)) {
    twist.omega_radps = sign * w_max * (0.3 + 0.7 * unit(rng_));
  } else if (robot_.canDriveSideways()) {
    twist.vy_mps = sign * v_max * (0.2 + 0.6 * unit(rng_));
    twist.vx_mps = v_max * 0.3 * (2.0 * unit(rng_) - 1.0);
  } else {
    arc();
  }
  return twist;
}

Twist2 DrivePlanner::command(double t_s, const Pose2& T_world_base)
{
  if (options_.type == "scripted") {
    double start_s = 0.0;
    for (const ScriptedMotion& motion : options_.script) {
      if (t_s < start_s + motion.duration_s) {
        return motion.twist;
      }
      start_s += motion.duration_s;
    }
    return Twist2();  // the script is over: stand still
  }
  const bool expired = t_s >= segment_end_s_;
  if (!expired && isSafe(current_, T_world_base)) {
    return current_;
  }
  std::uniform_real_distribution<double> duration(options_.min_segment_s, options_.max_segment_s);
  for (int attempt = 0; attempt < 30; ++attempt) {
    const Twist2 candidate = randomMotion();
    if (isSafe(candidate, T_world_base)) {
      current_ = candidate;
      segment_end_s_ = t_s + duration(rng_);
      return current_;
    }
  }
  // Boxed in: stand still and try again at the next control step.
  current_ = Twist2();
  segment_end_s_ = t_s;
  return current_;
}

}  // namespace sim
}  // namespace odometry_calibration
