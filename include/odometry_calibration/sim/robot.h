// True kinematics of the simulated robots, including deformations that break the parametric
// models (non-circular wheel, misaligned wheel axis, speed-dependent slip), as in the GP paper's
// experiments.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {
namespace sim {

/// Body velocity in base_link: forward [m/s], left [m/s], counter-clockwise [rad/s].
struct Twist2
{
  double vx_mps = 0.0;
  double vy_mps = 0.0;
  double omega_radps = 0.0;
};

/// Exact SE(2) exponential: the motion after `dt_s` at a constant body twist (an arc).
Pose2 integrateTwist(const Twist2& twist, double dt_s);

/// How one joint is seen by its encoder.
struct JointEncoderSpec
{
  std::string name;      ///< default joint name
  EncoderKind kind;      ///< incremental (wheel) or absolute (steering)
  double ticks_per_rev;  ///< encoder resolution [ticks per encoder turn]
};

/// Parameters of a robot: a type and named numbers. Each type documents its keys (see
/// makeRobot); unknown keys are rejected so typos do not go unnoticed.
struct RobotOptions
{
  std::string type = "diff_drive";           ///< diff_drive | tricycle | mecanum | skid_steer
  std::map<std::string, double> parameters;  ///< overrides of the type's defaults
};

/// A simulated robot. Joint angles are the physical angles [rad] (wheel rotation, steering
/// angle); encoderAngles() maps them to what the encoder shafts see.
class Robot
{
public:
  virtual ~Robot() = default;

  /// Number of joints and their encoders, in joint order.
  virtual std::vector<JointEncoderSpec> joints() const = 0;

  /// Advances the joints by `dt_s` under the commanded twist (the robot's controller knows
  /// only the ideal geometry) and returns the body twist the true, possibly deformed, robot
  /// realises over that step.
  virtual Twist2 step(const Twist2& command, double dt_s, Eigen::VectorXd* joint_rad) const = 0;

  /// Encoder shaft angles [rad] of the joints (steering scale/offset, traction gearing).
  virtual Eigen::VectorXd encoderAngles(const Eigen::VectorXd& joint_rad) const
  {
    return joint_rad;
  }

  /// Whether the robot can rotate without translating, and drive sideways.
  virtual bool canTurnInPlace() const = 0;
  virtual bool canDriveSideways() const { return false; }

  /// Radius of a circle around base_link covering the robot [m], for collision avoidance.
  virtual double footprintRadius() const = 0;

  /// The true parameters, after defaults, for the truth file.
  virtual std::map<std::string, double> trueParameters() const = 0;

  /// Joint angles at the start [rad].
  virtual Eigen::VectorXd initialJoints() const
  {
    return Eigen::VectorXd::Zero(static_cast<Eigen::Index>(joints().size()));
  }
};

/// Builds a robot. Keys by type (defaults in brackets; lengths in m, angles in rad):
///  diff_drive: wheel_radius_left_m [0.077], wheel_radius_right_m [0.077],
///    wheel_separation_m [0.33], encoder_ticks_per_rev [2000], separation_growth [0] (a tracked
///    or skid base: the separation it turns with is b (1 + g nu), nu = |v_r - v_l| / (|v_r| +
///    |v_l|), 0 straight, 1 on the spot; 0.2: 20 % wider on the spot than straight)
///  tricycle: steering_scale [0.56], traction_scale_m_per_turn [0.0106], axis_length_m [1.54],
///    steering_offset_rad [-0.06], max_steering_rad [1.2], steering_rate_radps [1.5],
///    steering_ticks_per_rev [8192], traction_ticks_per_rev [5000]
///  mecanum: wheel_radius_m [0.05] (or wheel_radius_fl_m/_fr_m/_rl_m/_rr_m), half_length_m
///    [0.15], half_width_m [0.2], encoder_ticks_per_rev [1000]; the GP paper's deformations of
///    wheel deformed_wheel [0] (0 front left, 1 front right, 2 rear left, 3 rear right):
///    axis_yaw_deg [0] (T1: the wheel's axis and rollers yawed by this angle [deg]) and
///    wheel_tilt_deg [0] (T2: the wheel tilted by this angle [deg]: effective radius
///    r cos(tilt), rollers seen from above at atan(cos(tilt)) instead of 45 deg); the robot
///    realises the least-squares twist of the four wheels' roller constraints
///  skid_steer (joints front_left, rear_left, front_right, rear_right): wheel_radius_m [0.1] (or
///    wheel_radius_left_m/_right_m), wheel_separation_m [0.5] (geometric track width),
///    effective_separation_factor [1.45] (turns as a diff drive of that times the track width),
///    encoder_ticks_per_rev [2000]
/// Deformations, any type: slip_per_speed [0] (effective radius shrinks by this fraction per
/// m/s of wheel speed), non_circular_amplitude [0] and non_circular_phase_rad [0] (the first
/// wheel's radius varies as r (1 + A cos(angle + phase))), axis_misalignment_rad [0] (the
/// first wheel rolls in a direction turned by this angle; diff_drive; mecanum: axis_yaw_deg),
/// turn_slip_per_radps [0] (wheel slip in turns: the base turns at omega (1 - k |omega|) of the
/// wheels' yaw rate omega, k in s/rad, in [0, 1]; the encoders see the wheels' turn).
/// Throws std::invalid_argument naming an unknown type, unknown key or invalid value.
std::unique_ptr<Robot> makeRobot(const RobotOptions& options);

}  // namespace sim
}  // namespace odometry_calibration
