#include "odometry_calibration/sim/simulator.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <deque>
#include <limits>
#include <random>
#include <stdexcept>

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
  LaserModel laser_model(laser, scenario.seed);
  // A stream of its own, so that enabling the tracker leaves the scans unchanged.
  std::mt19937_64 tracker_rng(scenario.seed ^ 0x7ac4e7ULL);
  std::normal_distribution<double> unit_normal(0.0, 1.0);

  const std::int64_t end_ns = std::llround(scenario.duration_s * 1e9);
  const std::int64_t encoder_period = periodNs(scenario.encoders.rate_hz);
  const std::int64_t scan_period = periodNs(laser.rate_hz);
  std::int64_t next_encoder = 0, next_scan = 0, next_control = 0;
  std::int64_t now = 0;

  Pose2 T_world_base = scenario.start_pose;
  // The motion over the last sweep, for the rays taken while the robot moves (laser.sweep):
  // the pose and the (constant) body velocity at the start of each integration step.
  struct Step
  {
    std::int64_t start_ns;
    Pose2 T_world_base;
    Twist2 twist;
  };
  std::deque<Step> recent_steps;
  const std::int64_t sweep_ns = std::llround(laser_model.sweepDuration() * 1e9);
  Eigen::VectorXd joints = robot.initialJoints();
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

  while (true) {
    const std::int64_t next_event = std::min({next_encoder, next_scan, next_control});
    if (next_event > end_ns)
      break;
    // Integrate up to the event in short steps (wheel-angle-dependent deformations).
    while (now < next_event) {
      const std::int64_t step = std::min(kMaxSubstepNs, next_event - now);
      const double dt = static_cast<double>(step) / kNanoseconds;
      ramp(dt);
      realised = robot.step(command, dt, &joints);
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
    }
    const double t = static_cast<double>(now) / kNanoseconds;
    if (now == next_control) {
      target = planner.command(t, T_world_base);
      next_control += kControlPeriodNs;
    }
    if (now == next_encoder) {
      JointStateSample sample;
      sample.stamp_s = t + scenario.encoders.time_offset_s;
      const Eigen::VectorXd shaft = robot.encoderAngles(joints);
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
      sink.onTruth({t, T_world_base, realised});
      ++summary.truth_samples;
      if (scenario.tracker.enabled) {
        const double noise_x = scenario.tracker.translation_noise_m * unit_normal(tracker_rng);
        const double noise_y = scenario.tracker.translation_noise_m * unit_normal(tracker_rng);
        const double noise_theta = scenario.tracker.rotation_noise_rad * unit_normal(tracker_rng);
        const Pose2 noise(noise_x, noise_y, noise_theta);
        sink.onTracker({t, T_world_base * laser.T_base_laser * noise});
      }
      next_encoder += encoder_period;
    }
    if (now == next_scan) {
      // The scan is complete now: its first ray was taken one sweep ago (a driver stamps the
      // first ray). Before t = 0 the robot stood at its start pose; the first scan whose sweep
      // would begin before then is not taken.
      const std::int64_t first_ray_ns = now - sweep_ns;
      auto T_world_laser_at = [&](double tau_s) {
        if (sweep_ns == 0)
          return T_world_base * laser.T_base_laser;
        const double at_ns = static_cast<double>(first_ray_ns) + tau_s * 1e9;
        if (at_ns >= static_cast<double>(now))
          return T_world_base * laser.T_base_laser;
        // The step the instant falls in: its start pose moved by its velocity for the rest.
        auto step = std::upper_bound(
            recent_steps.begin(), recent_steps.end(), at_ns,
            [](double t, const Step& s) { return t < static_cast<double>(s.start_ns); });
        if (step == recent_steps.begin())
          return recent_steps.empty() ? T_world_base * laser.T_base_laser
                                      : recent_steps.front().T_world_base * laser.T_base_laser;
        --step;
        const double into_s = (at_ns - static_cast<double>(step->start_ns)) / kNanoseconds;
        return step->T_world_base * integrateTwist(step->twist, into_s) * laser.T_base_laser;
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
