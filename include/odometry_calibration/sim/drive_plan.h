// What the simulated robot is told to do: a scripted list of motions, or a seeded random
// driver that excites every parameter (straight runs, turns both ways, turning on the spot
// where the robot can, reversing, sideways for mecanum) while keeping clear of the walls.
#pragma once

#include <random>
#include <string>
#include <vector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/world.h"

namespace odometry_calibration {
namespace sim {

/// One scripted motion: hold this body twist for a duration.
struct ScriptedMotion
{
  double duration_s = 1.0;
  Twist2 twist;
};

/// Options of the drive plan.
struct DrivePlanOptions
{
  std::string type = "random";       ///< "random" or "scripted"
  double max_speed_mps = 0.6;        ///< random: speed limit [m/s]
  double max_turn_rate_radps = 1.2;  ///< random: turn-rate limit [rad/s]
  double min_segment_s = 1.0;        ///< random: shortest motion [s]
  double max_segment_s = 4.0;        ///< random: longest motion [s]
  double clearance_m = 0.3;          ///< random: kept free around the footprint [m]
  double lookahead_s = 1.5;          ///< random: how far ahead a motion is checked [s]
  /// The robot follows a new command with at most these accelerations (real drives cannot
  /// change speed instantly); 0 = instantly.
  double max_acceleration_mps2 = 1.0;            ///< [m/s^2]
  double max_angular_acceleration_radps2 = 3.0;  ///< [rad/s^2]
  std::vector<ScriptedMotion> script;            ///< scripted: the motions, in order, then stop
  /// random: motions left out, to test what a drive without them determines. A left
  /// (right) turn is any motion turning counter-clockwise (clockwise), forward or reversing.
  bool left_turns = true;
  bool right_turns = true;
  bool turning_in_place = true;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const DrivePlanOptions& options);

/// Produces the commanded twist; called at the control rate with the robot's true pose.
class DrivePlanner
{
public:
  DrivePlanner(DrivePlanOptions options, const Robot& robot, const World& world,
               double footprint_radius_m, unsigned seed);

  /// Command at time `t_s` [s] for the robot at `T_world_base`.
  Twist2 command(double t_s, const Pose2& T_world_base);

private:
  bool isSafe(const Twist2& twist, const Pose2& T_world_base) const;
  Twist2 randomMotion();

  DrivePlanOptions options_;
  const Robot& robot_;
  const World& world_;
  double footprint_radius_m_;
  std::mt19937_64 rng_;
  Twist2 current_;
  double segment_end_s_ = -1.0;
};

}  // namespace sim
}  // namespace odometry_calibration
