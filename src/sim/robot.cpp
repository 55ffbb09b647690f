#include <cmath>
#include <set>
#include <stdexcept>

#include <Eigen/Geometry>

#include "odometry_calibration/common/number_text.h"
#include "odometry_calibration/sim/robot.h"

namespace odometry_calibration {
namespace sim {

Pose2 integrateTwist(const Twist2& twist, double dt_s)
{
  // Exact arc: rotate by w dt while translating with the body-frame velocity (SE(2) exp).
  return se2Exp(
      Eigen::Vector3d(twist.vx_mps * dt_s, twist.vy_mps * dt_s, twist.omega_radps * dt_s));
}

namespace {

/// Reads the robot's keys with defaults; rejects unknown keys and non-finite values.
class Parameters
{
public:
  Parameters(const RobotOptions& options, std::map<std::string, double> defaults)
      : values_(std::move(defaults))
  {
    for (const char* key : {"slip_per_speed", "non_circular_amplitude", "non_circular_phase_rad",
                            "axis_misalignment_rad", "turn_slip_per_radps"}) {
      values_.emplace(key, 0.0);
    }
    for (const auto& [key, value] : options.parameters) {
      if (values_.count(key) == 0) {
        std::string known;
        for (const auto& entry : values_)
          known += " " + entry.first;
        throw std::invalid_argument("robot '" + options.type + "': unknown parameter '" + key +
                                    "' (known:" + known + ")");
      }
      if (!std::isfinite(value)) {
        throw std::invalid_argument("robot parameter '" + key + "' must be a finite number");
      }
      values_[key] = value;
    }
  }

  double positive(const std::string& key) const
  {
    const double value = values_.at(key);
    if (!(value > 0.0)) {
      throw std::invalid_argument("robot parameter '" + key + "' must be > 0");
    }
    return value;
  }
  double operator[](const std::string& key) const { return values_.at(key); }
  const std::map<std::string, double>& all() const { return values_; }

private:
  std::map<std::string, double> values_;
};

/// Deformations shared by all robot types.
struct Deformation
{
  double slip_per_speed = 0.0;
  double non_circular_amplitude = 0.0;
  double non_circular_phase_rad = 0.0;
  double axis_misalignment_rad = 0.0;
  double turn_slip_per_radps = 0.0;

  explicit Deformation(const Parameters& p)
      : slip_per_speed(p["slip_per_speed"]),
        non_circular_amplitude(p["non_circular_amplitude"]),
        non_circular_phase_rad(p["non_circular_phase_rad"]),
        axis_misalignment_rad(p["axis_misalignment_rad"]),
        turn_slip_per_radps(p["turn_slip_per_radps"])
  {
    if (slip_per_speed < 0.0 || std::abs(non_circular_amplitude) >= 0.5) {
      throw std::invalid_argument("slip_per_speed must be >= 0 and |non_circular_amplitude| < 0.5");
    }
    if (!(turn_slip_per_radps >= 0.0 && turn_slip_per_radps <= 1.0)) {
      throw std::invalid_argument(
          "robot parameter 'turn_slip_per_radps' must be in [0, 1] s/rad, got " +
          formatNumber(turn_slip_per_radps));
    }
  }

  /// Wheel slip in turns: the base turns less than its wheels' kinematics say, by a fraction
  /// growing with the turn rate, while the wheels (and so the encoders) turn as commanded:
  ///   omega_true = omega_wheels * max(0, 1 - k |omega_wheels|),  k = turn_slip_per_radps [s/rad];
  /// the translation is the wheels'.
  Twist2 slipInTurns(const Twist2& wheels) const
  {
    Twist2 realised = wheels;
    realised.omega_radps *= std::max(0.0, 1.0 - turn_slip_per_radps * std::abs(wheels.omega_radps));
    return realised;
  }

  /// Effective rolling radius of a wheel of nominal radius r turning at `rate` with angle
  /// `angle`; the first wheel (index 0) carries the non-circular deformation.
  double effectiveRadius(int wheel, double radius_m, double angle_rad, double rate_radps) const
  {
    double r = radius_m;
    if (wheel == 0) {
      r *= 1.0 + non_circular_amplitude * std::cos(angle_rad + non_circular_phase_rad);
    }
    return r * std::max(0.0, 1.0 - slip_per_speed * std::abs(radius_m * rate_radps));
  }
};

/// A differential drive's two sides commanded (v, omega) by a controller that knows the geometric
/// separation b: wheel rates (v -+ b omega / 2) / r [rad/s], and the ground speeds the (possibly
/// deformed) wheels realise at those rates [m/s]. `right_wheel` is the right side's wheel index
/// in the deformation (the left side's is 0, the one that can be out of round).
struct SideSpeeds
{
  double rate_left_radps = 0.0, rate_right_radps = 0.0;
  double speed_left_mps = 0.0, speed_right_mps = 0.0;
};

SideSpeeds differentialSideSpeeds(const Twist2& command, double separation_m, double r_left_m,
                                  double r_right_m, const Deformation& deformation,
                                  const Eigen::VectorXd& joint_rad, int right_wheel)
{
  SideSpeeds sides;
  sides.rate_left_radps = (command.vx_mps - 0.5 * separation_m * command.omega_radps) / r_left_m;
  sides.rate_right_radps = (command.vx_mps + 0.5 * separation_m * command.omega_radps) / r_right_m;
  sides.speed_left_mps =
      deformation.effectiveRadius(0, r_left_m, joint_rad(0), sides.rate_left_radps) *
      sides.rate_left_radps;
  sides.speed_right_mps =
      deformation.effectiveRadius(right_wheel, r_right_m, joint_rad(right_wheel),
                                  sides.rate_right_radps) *
      sides.rate_right_radps;
  return sides;
}

class DiffDrive : public Robot
{
public:
  explicit DiffDrive(const RobotOptions& options)
      : p_(options, {{"wheel_radius_left_m", 0.077},
                     {"wheel_radius_right_m", 0.077},
                     {"wheel_separation_m", 0.33},
                     {"encoder_ticks_per_rev", 2000},
                     {"separation_growth", 0.0}}),
        deformation_(p_),
        r_left_(p_.positive("wheel_radius_left_m")),
        r_right_(p_.positive("wheel_radius_right_m")),
        separation_(p_.positive("wheel_separation_m")),
        ticks_(p_.positive("encoder_ticks_per_rev")),
        growth_(p_["separation_growth"])
  {
    if (!(growth_ >= 0.0 && growth_ <= 10.0)) {
      throw std::invalid_argument("robot parameter 'separation_growth' must be in [0, 10], got " +
                                  std::to_string(growth_));
    }
  }

  std::vector<JointEncoderSpec> joints() const override
  {
    return {{"left_wheel", EncoderKind::kIncremental, ticks_},
            {"right_wheel", EncoderKind::kIncremental, ticks_}};
  }

  Twist2 step(const Twist2& command, double dt_s, Eigen::VectorXd* joint_rad) const override
  {
    const SideSpeeds sides = differentialSideSpeeds(command, separation_, r_left_, r_right_,
                                                    deformation_, *joint_rad, 1);
    const double rate_left = sides.rate_left_radps, rate_right = sides.rate_right_radps;
    const double speed_left = sides.speed_left_mps, speed_right = sides.speed_right_mps;
    // The left wheel may roll in a direction turned by the misalignment angle.
    const double misalignment = deformation_.axis_misalignment_rad;
    const double left_x = speed_left * std::cos(misalignment);
    const double left_y = speed_left * std::sin(misalignment);
    (*joint_rad)(0) += rate_left * dt_s;
    (*joint_rad)(1) += rate_right * dt_s;
    return deformation_.slipInTurns(
        {0.5 * (left_x + speed_right), 0.5 * left_y,
         (speed_right - left_x) / effectiveSeparation(left_x, speed_right)});
  }

  bool canTurnInPlace() const override { return true; }
  double footprintRadius() const override { return 0.5 * separation_ + 0.1; }
  std::map<std::string, double> trueParameters() const override { return p_.all(); }

private:
  /// A tracked or skid base's separation, growing with the turn's tightness: b (1 + g nu), nu =
  /// |v_r - v_l| / (|v_r| + |v_l|) (0 driving straight, 1 turning on the spot) [m].
  double effectiveSeparation(double speed_left_mps, double speed_right_mps) const
  {
    const double sum = std::abs(speed_left_mps) + std::abs(speed_right_mps);
    const double nu = sum > 0.0 ? std::abs(speed_right_mps - speed_left_mps) / sum : 0.0;
    return separation_ * (1.0 + growth_ * nu);
  }

  Parameters p_;
  Deformation deformation_;
  double r_left_, r_right_, separation_, ticks_, growth_;
};

class Tricycle : public Robot
{
public:
  explicit Tricycle(const RobotOptions& options)
      : p_(options, {{"steering_scale", 0.56},
                     {"traction_scale_m_per_turn", 0.0106},
                     {"axis_length_m", 1.54},
                     {"steering_offset_rad", -0.06},
                     {"max_steering_rad", 1.2},
                     {"steering_rate_radps", 1.5},
                     {"steering_ticks_per_rev", 8192},
                     {"traction_ticks_per_rev", 5000}}),
        deformation_(p_),
        steering_scale_(p_.positive("steering_scale")),
        traction_scale_(p_.positive("traction_scale_m_per_turn")),
        axis_length_(p_.positive("axis_length_m")),
        max_steering_(p_.positive("max_steering_rad")),
        steering_rate_(p_.positive("steering_rate_radps"))
  {
    if (max_steering_ >= 0.5 * M_PI) {
      throw std::invalid_argument("robot parameter 'max_steering_rad' must be < pi/2");
    }
    if (deformation_.axis_misalignment_rad != 0.0) {
      throw std::invalid_argument("axis_misalignment_rad is not modelled for the tricycle");
    }
  }

  std::vector<JointEncoderSpec> joints() const override
  {
    return {{"steering", EncoderKind::kAbsolute, p_["steering_ticks_per_rev"]},
            {"traction_wheel", EncoderKind::kIncremental, p_["traction_ticks_per_rev"]}};
  }

  Twist2 step(const Twist2& command, double dt_s, Eigen::VectorXd* joint_rad) const override
  {
    double& steering = (*joint_rad)(0);
    // Steering target that realises (v, w): tan(alpha) = w a / v; held when not moving.
    double target = steering;
    if (std::abs(command.vx_mps) > 1e-6) {
      target = std::atan(command.omega_radps * axis_length_ / command.vx_mps);
    }
    target = std::clamp(target, -max_steering_, max_steering_);
    const double max_change = steering_rate_ * dt_s;
    steering += std::clamp(target - steering, -max_change, max_change);
    // Front-wheel speed for the commanded forward speed of the rear axle.
    const double wheel_speed = command.vx_mps / std::cos(steering);
    const double rate = wheel_speed / traction_scale_ * 2.0 * M_PI;  // wheel [rad/s]
    const double radius = traction_scale_ / (2.0 * M_PI);
    const double travel_rate =
        deformation_.effectiveRadius(0, radius, (*joint_rad)(1), rate) * rate;  // [m/s]
    (*joint_rad)(1) += rate * dt_s;
    return deformation_.slipInTurns(
        {travel_rate * std::cos(steering), 0.0, travel_rate * std::sin(steering) / axis_length_});
  }

  Eigen::VectorXd encoderAngles(const Eigen::VectorXd& joint_rad) const override
  {
    // Seed, section 2: alpha = Ks * encoder_angle + offset.
    return Eigen::Vector2d((joint_rad(0) - p_["steering_offset_rad"]) / steering_scale_,
                           joint_rad(1));
  }

  bool canTurnInPlace() const override { return false; }
  double footprintRadius() const override { return axis_length_ + 0.3; }
  std::map<std::string, double> trueParameters() const override { return p_.all(); }

private:
  Parameters p_;
  Deformation deformation_;
  double steering_scale_, traction_scale_, axis_length_, max_steering_, steering_rate_;
};

/// The four-wheel mecanum robot in the X roller configuration (mecanum_kinematics.h), with the
/// GP paper's deformations of one wheel (Sec. IV, Fig. 1): T1, its axis yawed (the wheel and its
/// rollers turned about the vertical by `axis_yaw_deg`), and T2, the wheel tilted (cambered by
/// `wheel_tilt_deg` about its rolling direction: its effective radius becomes r cos(tilt) and
/// its rollers' axis, seen from above, turns from 45 deg to atan(cos(tilt))).
///
/// Each wheel i at p_i = (+-lx, +-ly), rolling along d_i, with rollers whose axis points along
/// n_i on the ground (scaled so that d_i . n_i = 1; nominal n = (1, -1) for front left and rear
/// right, (1, 1) for front right and rear left) allows only body twists t = (vx, vy, omega) with
///   n_i . (v + omega x p_i) = s_i,  s_i = r_eff,i * wheel rate_i   (rollers slide along the rest).
/// Four such rows overdetermine the three twist components; the robot realises their
/// least-squares solution (the wheels slip against each other in proportion). Undeformed, the
/// rows are those of the inverse kinematics and the solution is the forward kinematics of [16].
/// The controller commands wheel rates through the nominal inverse kinematics (it knows neither
/// deformation).
class Mecanum : public Robot
{
public:
  explicit Mecanum(const RobotOptions& options)
      : p_(options, {{"wheel_radius_m", 0.05},
                     {"wheel_radius_fl_m", 0.0},
                     {"wheel_radius_fr_m", 0.0},
                     {"wheel_radius_rl_m", 0.0},
                     {"wheel_radius_rr_m", 0.0},
                     {"half_length_m", 0.15},
                     {"half_width_m", 0.2},
                     {"encoder_ticks_per_rev", 1000},
                     {"deformed_wheel", 0},
                     {"axis_yaw_deg", 0.0},
                     {"wheel_tilt_deg", 0.0}}),
        deformation_(p_),
        lever_(p_.positive("half_length_m") + p_.positive("half_width_m"))
  {
    const char* keys[] = {"wheel_radius_fl_m", "wheel_radius_fr_m", "wheel_radius_rl_m",
                          "wheel_radius_rr_m"};
    for (int i = 0; i < 4; ++i) {
      radius_[i] = p_[keys[i]] > 0.0 ? p_[keys[i]] : p_.positive("wheel_radius_m");
    }
    if (deformation_.axis_misalignment_rad != 0.0) {
      throw std::invalid_argument(
          "axis_misalignment_rad is not modelled for mecanum: use axis_yaw_deg (deformation T1)");
    }
    const double wheel = p_["deformed_wheel"];
    if (wheel != 0.0 && wheel != 1.0 && wheel != 2.0 && wheel != 3.0) {
      throw std::invalid_argument(
          "robot parameter 'deformed_wheel' must be 0 (front left), 1 (front right), 2 (rear "
          "left) or 3 (rear right)");
    }
    const double yaw = p_["axis_yaw_deg"] * M_PI / 180.0;
    const double tilt = p_["wheel_tilt_deg"] * M_PI / 180.0;
    if (std::abs(yaw) >= M_PI / 4.0 || std::abs(tilt) >= M_PI / 3.0) {
      throw std::invalid_argument(
          "robot parameters 'axis_yaw_deg' must be within +-45 and 'wheel_tilt_deg' within +-60");
    }
    deformed_ = yaw != 0.0 || tilt != 0.0;
    const double lx = p_["half_length_m"], ly = p_["half_width_m"];
    const double x[4] = {lx, lx, -lx, -lx}, y[4] = {ly, -ly, ly, -ly};
    const double roller_y[4] = {-1.0, 1.0, 1.0, -1.0};
    const int k = static_cast<int>(wheel);
    for (int i = 0; i < 4; ++i) {
      Eigen::Vector2d n(1.0, roller_y[i]);
      radius_scale_[i] = 1.0;
      if (i == k) {
        n.y() *= std::cos(tilt);
        n = Eigen::Rotation2Dd(yaw) * n;
        radius_scale_[i] = std::cos(tilt);
      }
      rows_.row(i) << n.x(), n.y(), x[i] * n.y() - y[i] * n.x();
    }
    solver_ = (rows_.transpose() * rows_).inverse() * rows_.transpose();
  }

  std::vector<JointEncoderSpec> joints() const override
  {
    const double ticks = p_.positive("encoder_ticks_per_rev");
    return {{"front_left_wheel", EncoderKind::kIncremental, ticks},
            {"front_right_wheel", EncoderKind::kIncremental, ticks},
            {"rear_left_wheel", EncoderKind::kIncremental, ticks},
            {"rear_right_wheel", EncoderKind::kIncremental, ticks}};
  }

  Twist2 step(const Twist2& command, double dt_s, Eigen::VectorXd* joint_rad) const override
  {
    const double vx = command.vx_mps, vy = command.vy_mps, w = lever_ * command.omega_radps;
    const double surface[4] = {vx - vy - w, vx + vy + w, vx + vy - w, vx - vy + w};
    Eigen::Vector4d speed;
    for (int i = 0; i < 4; ++i) {
      const double rate = surface[i] / radius_[i];
      speed(i) =
          deformation_.effectiveRadius(i, radius_[i] * radius_scale_[i], (*joint_rad)(i), rate) *
          rate;
      (*joint_rad)(i) += rate * dt_s;
    }
    if (deformed_) {
      const Eigen::Vector3d twist = solver_ * speed;
      return deformation_.slipInTurns({twist(0), twist(1), twist(2)});
    }
    // The least-squares solution of the undeformed rows in closed form ([16]).
    return deformation_.slipInTurns({0.25 * (speed(0) + speed(1) + speed(2) + speed(3)),
                                     0.25 * (-speed(0) + speed(1) + speed(2) - speed(3)),
                                     0.25 * (-speed(0) + speed(1) - speed(2) + speed(3)) / lever_});
  }

  bool canTurnInPlace() const override { return true; }
  bool canDriveSideways() const override { return true; }
  double footprintRadius() const override
  {
    return std::hypot(p_["half_length_m"], p_["half_width_m"]) + 0.1;
  }
  std::map<std::string, double> trueParameters() const override { return p_.all(); }

private:
  Parameters p_;
  Deformation deformation_;
  double lever_;
  double radius_[4];
  double radius_scale_[4];              ///< r_eff / r: cos(tilt) for the tilted wheel (T2), else 1
  bool deformed_ = false;               ///< T1 or T2 set: solve the rows, else the closed form
  Eigen::Matrix<double, 4, 3> rows_;    ///< the constraints' rows (n_i, p_i x n_i)
  Eigen::Matrix<double, 3, 4> solver_;  ///< their least-squares pseudo-inverse
};

/// Four wheels, two per side turning together (chained), steered by the speed difference of the
/// sides. Turning drags the wheels sideways, so the robot turns as a differential drive whose
/// separation is the track width times `effective_separation_factor` (Mandow et al., IROS 2007:
/// the instantaneous centres of rotation of the two sides lie outside the wheels).
class SkidSteer : public Robot
{
public:
  explicit SkidSteer(const RobotOptions& options)
      : p_(options, {{"wheel_radius_m", 0.1},
                     {"wheel_radius_left_m", 0.0},
                     {"wheel_radius_right_m", 0.0},
                     {"wheel_separation_m", 0.5},
                     {"effective_separation_factor", 1.45},
                     {"encoder_ticks_per_rev", 2000}}),
        deformation_(p_),
        r_left_(p_["wheel_radius_left_m"] > 0.0 ? p_["wheel_radius_left_m"]
                                                : p_.positive("wheel_radius_m")),
        r_right_(p_["wheel_radius_right_m"] > 0.0 ? p_["wheel_radius_right_m"]
                                                  : p_.positive("wheel_radius_m")),
        separation_(p_.positive("wheel_separation_m")),
        factor_(p_.positive("effective_separation_factor"))
  {
    if (factor_ < 1.0) {
      throw std::invalid_argument("robot parameter 'effective_separation_factor' must be >= 1");
    }
    if (deformation_.axis_misalignment_rad != 0.0) {
      throw std::invalid_argument("axis_misalignment_rad is not modelled for skid_steer");
    }
  }

  std::vector<JointEncoderSpec> joints() const override
  {
    const double ticks = p_.positive("encoder_ticks_per_rev");
    return {{"front_left_wheel", EncoderKind::kIncremental, ticks},
            {"rear_left_wheel", EncoderKind::kIncremental, ticks},
            {"front_right_wheel", EncoderKind::kIncremental, ticks},
            {"rear_right_wheel", EncoderKind::kIncremental, ticks}};
  }

  Twist2 step(const Twist2& command, double dt_s, Eigen::VectorXd* joint_rad) const override
  {
    // The controller knows the geometric values only; the turn rate realised is smaller by the
    // slip factor.
    const SideSpeeds sides = differentialSideSpeeds(command, separation_, r_left_, r_right_,
                                                    deformation_, *joint_rad, 2);
    const double rate_left = sides.rate_left_radps, rate_right = sides.rate_right_radps;
    const double speed_left = sides.speed_left_mps, speed_right = sides.speed_right_mps;
    (*joint_rad)(0) += rate_left * dt_s;
    (*joint_rad)(1) += rate_left * dt_s;
    (*joint_rad)(2) += rate_right * dt_s;
    (*joint_rad)(3) += rate_right * dt_s;
    return deformation_.slipInTurns({0.5 * (speed_left + speed_right), 0.0,
                                     (speed_right - speed_left) / (factor_ * separation_)});
  }

  bool canTurnInPlace() const override { return true; }
  double footprintRadius() const override { return 0.5 * factor_ * separation_ + 0.2; }
  std::map<std::string, double> trueParameters() const override { return p_.all(); }

private:
  Parameters p_;
  Deformation deformation_;
  double r_left_, r_right_, separation_, factor_;
};

}  // namespace

std::unique_ptr<Robot> makeRobot(const RobotOptions& options)
{
  if (options.type == "diff_drive")
    return std::make_unique<DiffDrive>(options);
  if (options.type == "tricycle")
    return std::make_unique<Tricycle>(options);
  if (options.type == "mecanum")
    return std::make_unique<Mecanum>(options);
  if (options.type == "skid_steer")
    return std::make_unique<SkidSteer>(options);
  throw std::invalid_argument("unknown robot type '" + options.type +
                              "' (expected diff_drive, tricycle, mecanum or skid_steer)");
}

}  // namespace sim
}  // namespace odometry_calibration
