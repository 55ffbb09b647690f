#include "odometry_calibration/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <memory>
#include <random>
#include <stdexcept>

#include <Eigen/Geometry>

#include "odometry_calibration/sim/drive_plan.h"
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

/// One sweep of the multi-beam lidar over [end - period, end], from the poses of `history`.
CloudSample castSweep(const LaserOptions& laser, const World& world, const PoseHistory& history,
                      std::int64_t end_ns, std::int64_t period_ns, std::mt19937_64& rng,
                      std::normal_distribution<double>& range_noise,
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
        history.at(static_cast<double>(start_ns) + tau_s * 1e9) * laser.T_base_laser;
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

}  // namespace

SimulationSummary simulate(const Scenario& scenario, const World& world, const Robot& robot,
                           SimulationSink& sink)
{
  validate(scenario);
  publishedJointNames(scenario, robot);  // checks the count
  const LaserOptions& laser = scenario.laser;
  const double footprint = std::max(
      robot.footprintRadius(), std::hypot(laser.T_base_laser.x(), laser.T_base_laser.y()) + 0.1);
  const Eigen::Vector2d start(scenario.start_pose.x(), scenario.start_pose.y());
  if (!world.isFree(start)) {
    throw std::invalid_argument("start_pose (" + std::to_string(start.x()) + ", " +
                                std::to_string(start.y()) +
                                ") is inside an obstacle or outside the world's walls");
  }
  if (world.clearance(start) < footprint) {
    throw std::invalid_argument("start_pose is closer to a wall than the robot's footprint (" +
                                std::to_string(footprint) + " m)");
  }

  const auto specs = robot.joints();
  DrivePlanner planner(scenario.motion, robot, world, footprint, scenario.seed);
  std::mt19937_64 rng(scenario.seed ^ 0x5eed5eedULL);
  std::normal_distribution<double> range_noise(0.0, laser.range_noise_m);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // A stream of its own, so that enabling the tracker leaves the scans unchanged.
  std::mt19937_64 tracker_rng(scenario.seed ^ 0x7ac4e7ULL);
  std::normal_distribution<double> unit_normal(0.0, 1.0);
  // The planar laser's rays (and its realism effects, sim/laser_model.h); the multi-beam
  // lidar draws from rng above.
  LaserModel laser_model(laser, scenario.seed);

  const std::int64_t end_ns = std::llround(scenario.duration_s * 1e9);
  const std::int64_t encoder_period = periodNs(scenario.encoders.rate_hz);
  const std::int64_t scan_period = periodNs(laser.rate_hz);
  std::int64_t next_encoder = 0, next_scan = 0, next_control = 0;
  std::int64_t now = 0;

  Pose2 T_world_base = scenario.start_pose;
  Eigen::VectorXd joints = robot.initialJoints();
  // The robots after each change (cumulative parameters) and the laser's pose now.
  std::vector<std::unique_ptr<Robot>> changed_robots;
  RobotOptions changed_options = scenario.robot;
  for (const ParameterChange& change : scenario.changes) {
    for (const auto& [key, value] : change.robot_parameters)
      changed_options.parameters[key] = value;
    changed_robots.push_back(makeRobot(changed_options));
    if (changed_robots.back()->joints().size() != specs.size())
      throw std::invalid_argument("changes: a change may not change the robot's joints");
  }
  std::size_t next_change = 0;
  const Robot* current_robot = &robot;
  Pose2 T_base_laser = laser.T_base_laser;
  auto applyChanges = [&]() {
    while (next_change < scenario.changes.size() &&
           now >= std::llround(scenario.changes[next_change].at_s * 1e9)) {
      current_robot = changed_robots[next_change].get();
      T_base_laser = Pose2(T_base_laser.x(), T_base_laser.y(),
                           normalizeAngle(T_base_laser.theta() +
                                          scenario.changes[next_change].laser_yaw_change_rad));
      ++next_change;
    }
  };
  Twist2 target, command, realised;
  // Ramp the command towards the planner's target with bounded accelerations.
  auto ramp = [&](double dt) {
    auto approach = [dt](double current, double goal, double rate) {
      if (rate <= 0.0)
        return goal;
      const double step = rate * dt;
      return current + std::clamp(goal - current, -step, step);
    };
    command.vx_mps = approach(command.vx_mps, target.vx_mps, scenario.motion.max_acceleration_mps2);
    command.vy_mps = approach(command.vy_mps, target.vy_mps, scenario.motion.max_acceleration_mps2);
    command.omega_radps = approach(command.omega_radps, target.omega_radps,
                                   scenario.motion.max_angular_acceleration_radps2);
  };
  SimulationSummary summary;
  std::vector<double> previous_reading(specs.size(), std::numeric_limits<double>::quiet_NaN());
  // Period of each incremental output in its units (0: never wraps), to count wrap-arounds.
  std::vector<double> wrap_period(specs.size(), 0.0);
  if (scenario.encoders.counter_bits > 0) {
    for (std::size_t j = 0; j < specs.size(); ++j) {
      wrap_period[j] = std::ldexp(1.0, scenario.encoders.counter_bits) *
                       (scenario.encoders.output_ticks ? 1.0 : 2.0 * M_PI / specs[j].ticks_per_rev);
    }
  }

  const bool multibeam = laser.type == "multibeam";
  PoseHistory history;
  if (multibeam)
    history.add(0, T_world_base, 2 * scan_period);
  // The motion over the last sweep of the planar laser, for the rays taken while the robot
  // moves (laser.sweep): the pose and the (constant) body velocity at the start of each step.
  struct Step
  {
    std::int64_t start_ns;
    Pose2 T_world_base;
    Twist2 twist;
  };
  std::deque<Step> recent_steps;
  const std::int64_t sweep_ns = multibeam ? 0 : std::llround(laser_model.sweepDuration() * 1e9);

  while (true) {
    const std::int64_t next_event = std::min({next_encoder, next_scan, next_control});
    if (next_event > end_ns)
      break;
    // Integrate up to the event in short steps (wheel-angle-dependent deformations).
    while (now < next_event) {
      const std::int64_t step = std::min(kMaxSubstepNs, next_event - now);
      const double dt = static_cast<double>(step) / kNanoseconds;
      applyChanges();
      ramp(dt);
      realised = current_robot->step(command, dt, &joints);
      if (sweep_ns > 0) {
        recent_steps.push_back({now, T_world_base, realised});
        while (recent_steps.size() > 1 && recent_steps[1].start_ns <= now - sweep_ns)
          recent_steps.pop_front();
      }
      const Pose2 motion = integrateTwist(realised, dt);
      summary.distance_m += std::hypot(motion.x(), motion.y());
      summary.rotation_rad += std::abs(motion.theta());
      T_world_base = T_world_base * motion;
      now += step;
      if (multibeam)
        history.add(now, T_world_base, 2 * scan_period);
    }
    applyChanges();
    const double t = static_cast<double>(now) / kNanoseconds;
    if (now == next_control) {
      target = planner.command(t, T_world_base);
      next_control += kControlPeriodNs;
    }
    if (now == next_encoder) {
      JointStateSample sample;
      sample.stamp_s = t + scenario.encoders.time_offset_s;
      const Eigen::VectorXd shaft = current_robot->encoderAngles(joints);
      for (std::size_t j = 0; j < specs.size(); ++j) {
        const double reading = encoderReading(specs[j], scenario.encoders, shaft(j));
        if (specs[j].kind == EncoderKind::kIncremental && wrap_period[j] > 0.0 &&
            std::abs(reading - previous_reading[j]) > 0.5 * wrap_period[j]) {
          ++summary.counter_wraps;
        }
        previous_reading[j] = reading;
        sample.positions.push_back(reading);
      }
      sink.onJointState(sample);
      ++summary.joint_states;
      sink.onTruth({t, T_world_base, realised, T_base_laser});
      ++summary.truth_samples;
      if (scenario.tracker.enabled) {
        const double noise_x = scenario.tracker.translation_noise_m * unit_normal(tracker_rng);
        const double noise_y = scenario.tracker.translation_noise_m * unit_normal(tracker_rng);
        const double noise_theta = scenario.tracker.rotation_noise_rad * unit_normal(tracker_rng);
        const Pose2 noise(noise_x, noise_y, noise_theta);
        sink.onTracker({t, T_world_base * T_base_laser * noise});
      }
      next_encoder += encoder_period;
    }
    if (now == next_scan && multibeam) {
      if (now >= scan_period) {  // a sweep that began at the start or later
        sink.onCloud(castSweep(laser, world, history, now, scan_period, rng, range_noise, unit));
        ++summary.scans;
      }
      next_scan += scan_period;
    } else if (now == next_scan) {
      // The scan is complete now: its first ray was taken one sweep ago (a driver stamps the
      // first ray). Before t = 0 the robot stood at its start pose; the first scan whose sweep
      // would begin before then is not taken.
      const std::int64_t first_ray_ns = now - sweep_ns;
      auto T_world_laser_at = [&](double tau_s) {
        if (sweep_ns == 0)
          return T_world_base * T_base_laser;
        const double at_ns = static_cast<double>(first_ray_ns) + tau_s * 1e9;
        if (at_ns >= static_cast<double>(now))
          return T_world_base * T_base_laser;
        // The step the instant falls in: its start pose moved by its velocity for the rest.
        auto step = std::upper_bound(
            recent_steps.begin(), recent_steps.end(), at_ns,
            [](double t, const Step& s) { return t < static_cast<double>(s.start_ns); });
        if (step == recent_steps.begin())
          return recent_steps.empty() ? T_world_base * T_base_laser
                                      : recent_steps.front().T_world_base * T_base_laser;
        --step;
        const double into_s = (at_ns - static_cast<double>(step->start_ns)) / kNanoseconds;
        return step->T_world_base * integrateTwist(step->twist, into_s) * T_base_laser;
      };
      if (first_ray_ns >= 0) {
        const ScanSample scan = laser_model.measure(
            world, static_cast<double>(first_ray_ns) / kNanoseconds, T_world_laser_at);
        sink.onScan(scan);
        ++summary.scans;
      }
      next_scan += scan_period;
    }
  }
  return summary;
}

bool droveTooLittle(const Scenario& scenario, const SimulationSummary& summary)
{
  return summary.distance_m < 0.05 * scenario.motion.max_speed_mps * scenario.duration_s;
}
}  // namespace sim
}  // namespace odometry_calibration
