#include "odometry_calibration/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <map>
#include <memory>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

#include "odometry_calibration/sim/base_odometry_output.h"
#include "odometry_calibration/sim/drive_plan.h"
#include "odometry_calibration/sim/imu_output.h"
#include "odometry_calibration/sim/laser_model.h"

namespace odometry_calibration {
namespace sim {

double encoderReading(const JointEncoderSpec& spec, const EncoderOptions& options,
                      double shaft_angle_rad)
{
  const double turns = shaft_angle_rad / (2.0 * M_PI);
  const double tick_rad = 2.0 * M_PI / spec.ticks_per_rev;
  if (spec.kind == EncoderKind::kAbsolute) {
    double ticks = std::fmod(std::round(turns * spec.ticks_per_rev), spec.ticks_per_rev);
    if (ticks < 0.0)
      ticks += spec.ticks_per_rev;
    if (options.output_ticks)
      return ticks;
    return (ticks > 0.5 * spec.ticks_per_rev ? ticks - spec.ticks_per_rev : ticks) * tick_rad;
  }
  double ticks = std::floor(turns * spec.ticks_per_rev) + options.initial_ticks;
  if (options.counter_bits > 0) {
    const double period = std::ldexp(1.0, options.counter_bits);
    ticks = std::fmod(ticks, period);
    if (ticks < 0.0)
      ticks += period;
  }
  return options.output_ticks ? ticks : ticks * tick_rad;
}

std::vector<std::string> publishedJointNames(const Scenario& scenario, const Robot& robot)
{
  const auto specs = robot.joints();
  if (scenario.encoders.joint_names.empty()) {
    std::vector<std::string> names;
    for (const auto& spec : specs)
      names.push_back(spec.name);
    return names;
  }
  if (scenario.encoders.joint_names.size() != specs.size()) {
    throw std::invalid_argument("encoders.joint_names lists " +
                                std::to_string(scenario.encoders.joint_names.size()) +
                                " names, the " + scenario.robot.type + " robot has " +
                                std::to_string(specs.size()) + " joints");
  }
  return scenario.encoders.joint_names;
}

namespace {

constexpr std::int64_t kNanoseconds = 1000000000;
constexpr std::int64_t kMaxSubstepNs = 2000000;       // integration step: 2 ms
constexpr std::int64_t kControlPeriodNs = 100000000;  // planner: 10 Hz

std::int64_t periodNs(double rate_hz)
{
  return std::llround(1e9 / rate_hz);
}

/// The robot's poses at the integration steps of the last sweep, to place each firing.
struct PoseHistory
{
  std::deque<std::pair<std::int64_t, Pose2>> poses;  ///< (time [ns], T_world_base)

  void add(std::int64_t t_ns, const Pose2& pose, std::int64_t keep_ns)
  {
    poses.emplace_back(t_ns, pose);
    while (poses.size() > 2 && poses.front().first < t_ns - keep_ns)
      poses.pop_front();
  }

  /// The pose at t_ns, interpolated on SE(2) between the neighbouring steps.
  Pose2 at(double t_ns) const
  {
    auto after = std::lower_bound(
        poses.begin(), poses.end(), t_ns,
        [](const std::pair<std::int64_t, Pose2>& p, double t) { return p.first < t; });
    if (after == poses.begin())
      return poses.front().second;
    if (after == poses.end())
      return poses.back().second;
    const auto before = std::prev(after);
    const double alpha = (t_ns - before->first) / static_cast<double>(after->first - before->first);
    return before->second * se2Exp(alpha * se2Log(between(before->second, after->second)));
  }
};

/// One sweep of the multi-beam lidar over [end - period, end], from the poses of `history`, the
/// lidar mounted at T_base_laser (its pose now: scenario changes move it).
CloudSample castSweep(const LaserOptions& laser, const Pose2& T_base_laser, const World& world,
                      const PoseHistory& history, std::int64_t end_ns, std::int64_t period_ns,
                      std::mt19937_64& rng, std::normal_distribution<double>& range_noise,
                      std::uniform_real_distribution<double>& unit)
{
  CloudSample cloud;
  const std::int64_t start_ns = end_ns - period_ns;
  cloud.stamp_s = static_cast<double>(start_ns) / 1e9;
  const int columns = static_cast<int>(std::lround(2.0 * M_PI / laser.horizontal_step_rad));
  // The mounting tilt: directions in the laser frame to the level frame (R_y(pitch) R_x(roll),
  // the convention of ego_motion.cloud).
  const Eigen::Matrix3d R_level_laser =
      (Eigen::AngleAxisd(laser.pitch_rad, Eigen::Vector3d::UnitY()) *
       Eigen::AngleAxisd(laser.roll_rad, Eigen::Vector3d::UnitX()))
          .toRotationMatrix();
  std::vector<Eigen::Vector3d> ring_directions(static_cast<std::size_t>(laser.rings));
  for (int c = 0; c < columns; ++c) {
    const double tau_s = static_cast<double>(period_ns) * c / columns / 1e9;
    const Pose2 T_world_laser =
        history.at(static_cast<double>(start_ns) + tau_s * 1e9) * T_base_laser;
    const Eigen::Vector2d origin(T_world_laser.x(), T_world_laser.y());
    const double azimuth = -M_PI + 2.0 * M_PI * c / columns;
    for (int r = 0; r < laser.rings; ++r) {
      const double elevation =
          laser.rings == 1
              ? laser.elevation_min_rad
              : laser.elevation_min_rad +
                    (laser.elevation_max_rad - laser.elevation_min_rad) * r / (laser.rings - 1);
      const Eigen::Vector3d direction(std::cos(elevation) * std::cos(azimuth),
                                      std::cos(elevation) * std::sin(azimuth), std::sin(elevation));
      const Eigen::Vector3d level = R_level_laser * direction;
      double range = world.castRay3d(
          origin, laser.height_m, T_world_laser.theta() + std::atan2(level.y(), level.x()),
          std::asin(std::clamp(level.z(), -1.0, 1.0)), laser.max_range_m);
      if (std::isfinite(range) && laser.range_noise_m > 0.0)
        range += range_noise(rng);
      const bool dropped = laser.dropout_probability > 0.0 && unit(rng) < laser.dropout_probability;
      if (dropped || !(range >= laser.min_range_m && range <= laser.max_range_m))
        continue;
      const Eigen::Vector3d point = range * direction;
      cloud.xyz.insert(cloud.xyz.end(),
                       {static_cast<float>(point.x()), static_cast<float>(point.y()),
                        static_cast<float>(point.z())});
      cloud.intensity.push_back(static_cast<float>(100.0 / (1.0 + range)));
      cloud.ring.push_back(static_cast<std::uint16_t>(r));
      cloud.time_s.push_back(static_cast<float>(tau_s));
    }
  }
  return cloud;
}

/// Refuses a start pose inside an obstacle, outside the walls or closer to a wall than the
/// robot's footprint [m].
void checkStartPose(const Scenario& scenario, const World& world, double footprint_m)
{
  const Eigen::Vector2d start(scenario.start_pose.x(), scenario.start_pose.y());
  if (!world.isFree(start)) {
    throw std::invalid_argument("start_pose (" + std::to_string(start.x()) + ", " +
                                std::to_string(start.y()) +
                                ") is inside an obstacle or outside the world's walls");
  }
  if (world.clearance(start) < footprint_m) {
    throw std::invalid_argument("start_pose is closer to a wall than the robot's footprint (" +
                                std::to_string(footprint_m) + " m)");
  }
}

/// The robots after each change of the scenario (cumulative parameters); a change may not
/// change the joints.
std::vector<std::unique_ptr<Robot>> changedRobots(const Scenario& scenario, std::size_t joint_count)
{
  std::vector<std::unique_ptr<Robot>> robots;
  RobotOptions changed_options = scenario.robot;
  for (const ParameterChange& change : scenario.changes) {
    for (const auto& [key, value] : change.robot_parameters)
      changed_options.parameters[key] = value;
    robots.push_back(makeRobot(changed_options));
    if (robots.back()->joints().size() != joint_count)
      throw std::invalid_argument("changes: a change may not change the robot's joints");
  }
  return robots;
}

/// Period of each incremental output in its units (0: never wraps), to count wrap-arounds.
std::vector<double> wrapPeriods(const EncoderOptions& encoders,
                                const std::vector<JointEncoderSpec>& specs)
{
  std::vector<double> wrap_period(specs.size(), 0.0);
  if (encoders.counter_bits > 0) {
    for (std::size_t j = 0; j < specs.size(); ++j) {
      wrap_period[j] = std::ldexp(1.0, encoders.counter_bits) *
                       (encoders.output_ticks ? 1.0 : 2.0 * M_PI / specs[j].ticks_per_rev);
    }
  }
  return wrap_period;
}

/// Ramps `command` towards `target` over dt [s] with the plan's bounded accelerations.
void rampCommand(const Twist2& target, const DrivePlanOptions& motion, double dt, Twist2& command)
{
  auto approach = [dt](double current, double goal, double rate) {
    if (rate <= 0.0)
      return goal;
    const double step = rate * dt;
    return current + std::clamp(goal - current, -step, step);
  };
  command.vx_mps = approach(command.vx_mps, target.vx_mps, motion.max_acceleration_mps2);
  command.vy_mps = approach(command.vy_mps, target.vy_mps, motion.max_acceleration_mps2);
  command.omega_radps =
      approach(command.omega_radps, target.omega_radps, motion.max_angular_acceleration_radps2);
}

/// One integration step of the motion over the last sweep of the planar laser: the pose and
/// the (constant) body velocity at its start.
struct MotionStep
{
  std::int64_t start_ns;
  Pose2 T_world_base;
  Twist2 twist;
};

/// The laser's world pose at `at_ns` [ns] within the sweep that ends now: the step the instant
/// falls in, its start pose moved by its velocity for the rest. Before the recorded steps, the
/// first one's start pose; at or after now, the pose now.
Pose2 laserPoseDuringSweep(const std::deque<MotionStep>& recent_steps, const Pose2& T_world_base,
                           const Pose2& T_base_laser, std::int64_t now_ns, double at_ns)
{
  if (at_ns >= static_cast<double>(now_ns))
    return T_world_base * T_base_laser;
  auto step = std::upper_bound(
      recent_steps.begin(), recent_steps.end(), at_ns,
      [](double t, const MotionStep& s) { return t < static_cast<double>(s.start_ns); });
  if (step == recent_steps.begin())
    return recent_steps.empty() ? T_world_base * T_base_laser
                                : recent_steps.front().T_world_base * T_base_laser;
  --step;
  const double into_s = (at_ns - static_cast<double>(step->start_ns)) / kNanoseconds;
  return step->T_world_base * integrateTwist(step->twist, into_s) * T_base_laser;
}

/// A laser after the first: its ray model on a random stream of its own, its scan
/// period and sweep, and when its next scan is due.
struct ExtraLaser
{
  ExtraLaser(const LaserOptions& laser_options, unsigned seed, std::size_t laser_index)
      : options(laser_options),
        model(laser_options, seed),
        period_ns(periodNs(laser_options.rate_hz)),
        sweep_ns(std::llround(model.sweepDuration() * 1e9)),
        index(laser_index),
        T_base_laser(laser_options.T_base_laser)
  {
  }

  const LaserOptions& options;
  LaserModel model;
  std::int64_t period_ns;
  std::int64_t sweep_ns;
  std::size_t index;
  Pose2 T_base_laser;  ///< its pose now (changes move and turn it)
  std::int64_t next_ns = 0;
};

/// The extra lasers of a scenario, each seeded apart from the first laser's streams.
std::vector<ExtraLaser> extraLasers(const Scenario& scenario)
{
  std::vector<ExtraLaser> lasers;
  for (std::size_t k = 0; k < scenario.extra_lasers.size(); ++k) {
    const unsigned seed = scenario.seed ^ static_cast<unsigned>(0x9e3779b9u * (k + 1));
    lasers.emplace_back(scenario.extra_lasers[k], seed, k + 1);
  }
  return lasers;
}

/// The longest sweep [ns] of the planar lasers among `first_sweep_ns` and the extra lasers'.
std::int64_t longestSweep(std::int64_t first_sweep_ns, const std::vector<ExtraLaser>& extra)
{
  std::int64_t longest = first_sweep_ns;
  for (const ExtraLaser& laser : extra)
    longest = std::max(longest, laser.sweep_ns);
  return longest;
}

/// One run of the simulator: the robot driven by the planner in integration steps, the events
/// (control, encoders with the truth and the tracker, scans or sweeps) at their instants.
class SimulationRun
{
public:
  SimulationRun(const Scenario& scenario, const World& world, const Robot& robot,
                SimulationSink& sink, double footprint_m)
      : scenario_(scenario),
        laser_(scenario.laser),
        world_(world),
        sink_(sink),
        specs_(robot.joints()),
        planner_(scenario.motion, robot, world, footprint_m, scenario.seed),
        rng_(scenario.seed ^ 0x5eed5eedULL),
        range_noise_(0.0, laser_.range_noise_m),
        tracker_rng_(scenario.seed ^ 0x7ac4e7ULL),
        encoder_clock_rng_(scenario.seed ^ 0xc10c4ULL),
        laser_model_(laser_, scenario.seed),
        end_ns_(std::llround(scenario.duration_s * 1e9)),
        encoder_period_(periodNs(scenario.encoders.rate_hz)),
        scan_period_(periodNs(laser_.rate_hz)),
        T_world_base_(scenario.start_pose),
        joints_(robot.initialJoints()),
        changed_robots_(changedRobots(scenario, specs_.size())),
        current_robot_(&robot),
        T_base_laser_(laser_.T_base_laser),
        encoder_time_offset_s_(scenario.encoders.time_offset_s),
        previous_reading_(specs_.size(), std::numeric_limits<double>::quiet_NaN()),
        wrap_period_(wrapPeriods(scenario.encoders, specs_)),
        multibeam_(laser_.type == "multibeam"),
        sweep_ns_(multibeam_ ? 0 : std::llround(laser_model_.sweepDuration() * 1e9)),
        extra_lasers_(extraLasers(scenario)),
        longest_sweep_ns_(longestSweep(sweep_ns_, extra_lasers_)),
        ticks_(scenario.encoders.output == "ticks"),
        tick_stagger_ns_(std::llround(scenario.encoders.tick_stagger_s * 1e9)),
        velocities_(scenario.encoders.output == "joint_velocity"),
        base_odometry_(scenario.encoders, scenario.start_pose),
        shaft_rate_(Eigen::VectorXd::Zero(static_cast<Eigen::Index>(specs_.size()))),
        imu_(scenario.imu, scenario.seed)
  {
    if (multibeam_)
      history_.add(0, T_world_base_, 2 * scan_period_);
  }

  SimulationSummary run()
  {
    while (true) {
      const std::int64_t next_event = std::min(
          {next_encoder_, next_scan_, next_control_, nextExtraScan(), nextTick(), imu_.next()});
      if (next_event > end_ns_)
        break;
      integrateTo(next_event);
      applyChanges();
      const double t = static_cast<double>(now_) / kNanoseconds;
      if (now_ == next_control_) {
        target_ = planner_.command(t, T_world_base_);
        next_control_ += kControlPeriodNs;
      }
      if (now_ == next_encoder_) {
        publishEncoderInstant(t);
        next_encoder_ += nextEncoderSpacing();
      }
      publishDueTicks(t);
      imu_.publishDue(now_, t, realised_.omega_radps, sink_);
      if (now_ == next_scan_ && multibeam_) {
        if (now_ >= scan_period_) {  // a sweep that began at the start or later
          CloudSample cloud = castSweep(laser_, T_base_laser_, world_, history_, now_, scan_period_,
                                        rng_, range_noise_, unit_);
          cloud.stamp_s += laser_.time_offset_s;
          sink_.onCloud(cloud);
          ++summary_.scans;
        }
        next_scan_ += scan_period_;
      } else if (now_ == next_scan_) {
        publishScan(laser_model_, T_base_laser_, sweep_ns_, laser_.time_offset_s, 0);
        next_scan_ += scan_period_;
      }
      publishExtraScans();
    }
    return summary_;
  }

private:
  /// The spacing to the next encoder reading: the period, jittered by rate_jitter_s [ns].
  std::int64_t nextEncoderSpacing()
  {
    const double jitter_s = scenario_.encoders.rate_jitter_s;
    if (jitter_s <= 0.0)
      return encoder_period_;
    std::uniform_real_distribution<double> draw(-jitter_s, jitter_s);
    return encoder_period_ + std::llround(draw(encoder_clock_rng_) * 1e9);
  }

  /// When the next joint's tick reading is due [ns] (never but with encoders.output ticks).
  std::int64_t nextTick() const
  {
    return pending_ticks_.empty() ? std::numeric_limits<std::int64_t>::max()
                                  : pending_ticks_.begin()->first;
  }

  /// The tick readings due now: each joint's counter on its own topic, at time t [s].
  void publishDueTicks(double t)
  {
    while (!pending_ticks_.empty() && pending_ticks_.begin()->first == now_) {
      const std::size_t j = pending_ticks_.begin()->second;
      pending_ticks_.erase(pending_ticks_.begin());
      const Eigen::VectorXd shaft = current_robot_->encoderAngles(joints_);
      sink_.onWheelTick(
          {t + encoder_time_offset_s_, j, encoderReading(specs_[j], scenario_.encoders, shaft(j))});
    }
  }

  /// When the next scan of an extra laser is due [ns] (never without one).
  std::int64_t nextExtraScan() const
  {
    std::int64_t next = std::numeric_limits<std::int64_t>::max();
    for (const ExtraLaser& laser : extra_lasers_)
      next = std::min(next, laser.next_ns);
    return next;
  }

  /// The scans of the extra lasers due now, in the lasers' order.
  void publishExtraScans()
  {
    for (ExtraLaser& laser : extra_lasers_) {
      if (now_ != laser.next_ns)
        continue;
      publishScan(laser.model, laser.T_base_laser, laser.sweep_ns, laser.options.time_offset_s,
                  laser.index);
      laser.next_ns += laser.period_ns;
    }
  }

  /// The changes due by now: the robot after them, the laser (the change's) moved and turned
  /// by them, the encoders' clock shifted by them.
  void applyChanges()
  {
    while (next_change_ < scenario_.changes.size() &&
           now_ >= std::llround(scenario_.changes[next_change_].at_s * 1e9)) {
      const ParameterChange& change = scenario_.changes[next_change_];
      current_robot_ = changed_robots_[next_change_].get();
      Pose2& T_base_laser = change.laser_index == 0
                                ? T_base_laser_
                                : extra_lasers_.at(change.laser_index - 1).T_base_laser;
      T_base_laser = Pose2(T_base_laser.x() + change.laser_x_change_m,
                           T_base_laser.y() + change.laser_y_change_m,
                           normalizeAngle(T_base_laser.theta() + change.laser_yaw_change_rad));
      encoder_time_offset_s_ += change.time_offset_change_s;
      ++next_change_;
    }
  }

  /// Integrates up to the event in short steps (wheel-angle-dependent deformations).
  void integrateTo(std::int64_t next_event)
  {
    while (now_ < next_event) {
      const std::int64_t step = std::min(kMaxSubstepNs, next_event - now_);
      const double dt = static_cast<double>(step) / kNanoseconds;
      applyChanges();
      rampCommand(target_, scenario_.motion, dt, command_);
      const Eigen::VectorXd shaft_before =
          velocities_ ? current_robot_->encoderAngles(joints_) : Eigen::VectorXd();
      realised_ = current_robot_->step(command_, dt, &joints_);
      if (velocities_)
        shaft_rate_ = (current_robot_->encoderAngles(joints_) - shaft_before) / dt;
      if (longest_sweep_ns_ > 0) {
        recent_steps_.push_back({now_, T_world_base_, realised_});
        while (recent_steps_.size() > 1 && recent_steps_[1].start_ns <= now_ - longest_sweep_ns_)
          recent_steps_.pop_front();
      }
      const Pose2 motion = integrateTwist(realised_, dt);
      summary_.distance_m += std::hypot(motion.x(), motion.y());
      summary_.rotation_rad += std::abs(motion.theta());
      T_world_base_ = T_world_base_ * motion;
      now_ += step;
      if (multibeam_)
        history_.add(now_, T_world_base_, 2 * scan_period_);
    }
  }

  /// The encoders' joint state (counting the counters' wrap-arounds), the truth and, if
  /// enabled, the tracker's noisy laser pose at time t [s].
  void publishEncoderInstant(double t)
  {
    JointStateSample sample;
    sample.stamp_s = t + encoder_time_offset_s_;
    const Eigen::VectorXd shaft = current_robot_->encoderAngles(joints_);
    for (std::size_t j = 0; j < specs_.size(); ++j) {
      const double reading = encoderReading(specs_[j], scenario_.encoders, shaft(j));
      if (specs_[j].kind == EncoderKind::kIncremental && wrap_period_[j] > 0.0 &&
          std::abs(reading - previous_reading_[j]) > 0.5 * wrap_period_[j]) {
        ++summary_.counter_wraps;
      }
      previous_reading_[j] = reading;
      sample.positions.push_back(reading);
      if (velocities_) {
        const double per_rad =
            scenario_.encoders.output_ticks ? specs_[j].ticks_per_rev / (2.0 * M_PI) : 1.0;
        sample.velocities.push_back(shaft_rate_(static_cast<Eigen::Index>(j)) * per_rad);
      }
      if (ticks_) {
        pending_ticks_.emplace(now_ + static_cast<std::int64_t>(j) * tick_stagger_ns_, j);
      }
    }
    sink_.onJointState(sample);
    ++summary_.joint_states;
    base_odometry_.publish(sample.stamp_s, T_world_base_, realised_, sink_);
    sink_.onTruth({t, T_world_base_, realised_, T_base_laser_});
    ++summary_.truth_samples;
    if (scenario_.tracker.enabled) {
      const double noise_x = scenario_.tracker.translation_noise_m * unit_normal_(tracker_rng_);
      const double noise_y = scenario_.tracker.translation_noise_m * unit_normal_(tracker_rng_);
      const double noise_theta = scenario_.tracker.rotation_noise_rad * unit_normal_(tracker_rng_);
      const Pose2 noise(noise_x, noise_y, noise_theta);
      sink_.onTracker({t, T_world_base_ * T_base_laser_ * noise});
    }
  }

  /// A planar laser's scan (laser `index`, mounted at T_base_laser, its sweep `sweep_ns` long),
  /// complete now: its first ray was taken one sweep ago (a driver stamps the first ray; the
  /// stamp is on the laser's clock, time_offset_s [s] ahead of the true time). Before t = 0
  /// the robot stood at its start pose; the first scan whose sweep would begin before then is
  /// not taken.
  void publishScan(LaserModel& model, const Pose2& T_base_laser, std::int64_t sweep_ns,
                   double time_offset_s, std::size_t index)
  {
    const std::int64_t first_ray_ns = now_ - sweep_ns;
    if (first_ray_ns < 0)
      return;
    auto T_world_laser_at = [&](double tau_s) {
      if (sweep_ns == 0)
        return T_world_base_ * T_base_laser;
      return laserPoseDuringSweep(recent_steps_, T_world_base_, T_base_laser, now_,
                                  static_cast<double>(first_ray_ns) + tau_s * 1e9);
    };
    ScanSample scan = model.measure(
        world_, static_cast<double>(first_ray_ns) / kNanoseconds + time_offset_s, T_world_laser_at);
    scan.laser_index = index;
    sink_.onScan(scan);
    ++summary_.scans;
  }

  const Scenario& scenario_;
  const LaserOptions& laser_;
  const World& world_;
  SimulationSink& sink_;
  const std::vector<JointEncoderSpec> specs_;
  DrivePlanner planner_;
  std::mt19937_64 rng_;
  std::normal_distribution<double> range_noise_;
  std::uniform_real_distribution<double> unit_{0.0, 1.0};
  // A stream of its own, so that enabling the tracker leaves the scans unchanged.
  std::mt19937_64 tracker_rng_;
  std::mt19937_64 encoder_clock_rng_;  ///< the encoder spacing's jitter (rate_jitter_s)
  std::normal_distribution<double> unit_normal_{0.0, 1.0};
  // The planar laser's rays (and its realism effects, sim/laser_model.h); the multi-beam
  // lidar draws from rng_ above.
  LaserModel laser_model_;
  const std::int64_t end_ns_;
  const std::int64_t encoder_period_;
  const std::int64_t scan_period_;
  std::int64_t next_encoder_ = 0, next_scan_ = 0, next_control_ = 0;
  std::int64_t now_ = 0;
  Pose2 T_world_base_;
  Eigen::VectorXd joints_;
  std::vector<std::unique_ptr<Robot>> changed_robots_;
  std::size_t next_change_ = 0;
  const Robot* current_robot_;
  Pose2 T_base_laser_;            // the laser's pose now (changes move and turn it)
  double encoder_time_offset_s_;  // the encoders' stamp offset now (changes shift it) [s]
  Twist2 target_, command_, realised_;
  SimulationSummary summary_;
  std::vector<double> previous_reading_;
  std::vector<double> wrap_period_;
  const bool multibeam_;
  PoseHistory history_;
  std::deque<MotionStep> recent_steps_;
  const std::int64_t sweep_ns_;
  std::vector<ExtraLaser> extra_lasers_;
  const std::int64_t longest_sweep_ns_;  // of every planar laser: the motion steps kept
  const bool ticks_;                     // encoders.output ticks: each joint on its own topic
  const std::int64_t tick_stagger_ns_;   // joint j read j * this after the instant
  std::multimap<std::int64_t, std::size_t> pending_ticks_;  // due time [ns] -> joint
  const bool velocities_;                                   // encoders.output joint_velocity
  BaseOdometryOutput base_odometry_;  // encoders.output odometry: the base's reported odometry
  Eigen::VectorXd shaft_rate_;        // over the last integration step [rad/s]
  ImuOutput imu_;                     // the IMU's gyro (its own random stream)
};

}  // namespace

SimulationSummary simulate(const Scenario& scenario, const World& world, const Robot& robot,
                           SimulationSink& sink)
{
  validate(scenario);
  publishedJointNames(scenario, robot);  // checks the count
  double footprint = robot.footprintRadius();
  for (const LaserOptions& laser : allLasers(scenario))
    footprint =
        std::max(footprint, std::hypot(laser.T_base_laser.x(), laser.T_base_laser.y()) + 0.1);
  checkStartPose(scenario, world, footprint);
  return SimulationRun(scenario, world, robot, sink, footprint).run();
}

bool droveTooLittle(const Scenario& scenario, const SimulationSummary& summary)
{
  return summary.distance_m < 0.05 * scenario.motion.max_speed_mps * scenario.duration_s;
}
}  // namespace sim
}  // namespace odometry_calibration
