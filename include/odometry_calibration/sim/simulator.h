// The simulation loop: drives the robot through the world and emits encoder readings, laser
// scans and ground truth, in time order, to a sink (the bag writer, or a test).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/sim/imu_model.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/world.h"

namespace odometry_calibration {
namespace sim {

/// One JointState: positions in the configured units, stamped with the encoder clock.
struct JointStateSample
{
  double stamp_s = 0.0;           ///< true time + encoders.time_offset_s [s since start]
  std::vector<double> positions;  ///< ticks (or radians), in joint order
  /// The joints' shaft rates over the last integration step (at most 2 ms) [ticks/s, or rad/s],
  /// for encoders.output joint_velocity.
  std::vector<double> velocities;
};

/// One joint's reading on its own tick topic (encoders.output ticks): the counter as
/// encoderReading gives it, joint j read encoders.tick_stagger_s * j after the instant.
struct WheelTickSample
{
  double stamp_s = 0.0;  ///< true time + encoders.time_offset_s [s since start]
  std::size_t joint = 0;
  double value = 0.0;  ///< ticks (or radians)
};

/// The base's own odometry at an encoder instant (encoders.output odometry): the pose it
/// integrated, with its scale errors, from the true motion.
struct BaseOdometrySample
{
  double stamp_s = 0.0;  ///< true time + encoders.time_offset_s [s since start]
  Pose2 T_odom_base;     ///< the base's reported pose in its odom frame
  Twist2 twist;          ///< the reported body velocity (the true one, scaled)
};

/// One laser scan in the sensor's frame (angles counter-clockwise from its x axis).
struct ScanSample
{
  double stamp_s = 0.0;  ///< time of the scan's first ray [s since start]
  float angle_min_rad = 0.0f;
  float angle_increment_rad = 0.0f;
  float range_min_m = 0.0f;
  float range_max_m = 0.0f;
  /// Time between rays [s]: ray i measured i * time_increment_s after the stamp (laser.sweep);
  /// 0 = all rays at the stamp.
  double time_increment_s = 0.0;
  double scan_time_s = 0.0;  ///< time between scans [s] (sensor_msgs/LaserScan scan_time)
  /// Ranges [m]: +inf no return within range_max, -inf closer than range_min, NaN dropout.
  std::vector<float> ranges;
  /// Which laser took it: 0 the scenario's `laser`, k its extra_lasers[k - 1] (allLasers).
  std::size_t laser_index = 0;
};

/// One sweep of the multi-beam lidar: its points in the sensor's frame, in firing order
/// (azimuth column by column, rings bottom up within a column). Rays without a return within
/// range are left out (a dense cloud).
struct CloudSample
{
  double stamp_s = 0.0;             ///< start of the sweep [s since start]
  std::vector<float> xyz;           ///< x, y, z of each point [m], 3 per point
  std::vector<float> intensity;     ///< per point, falling with range (synthetic)
  std::vector<std::uint16_t> ring;  ///< per point: 0 = lowest beam
  std::vector<float> time_s;        ///< per point: time after stamp_s [s]

  std::size_t size() const { return ring.size(); }
};

/// The truth at one instant (never an input of the calibration).
struct TruthSample
{
  double stamp_s = 0.0;  ///< true time [s since start]
  Pose2 T_world_base;    ///< robot pose
  Twist2 twist;          ///< body velocity
  Pose2 T_base_laser;    ///< the laser's true mounting pose now (scenario.changes)
};

/// One pose of the external tracker: the laser's world pose with tracker noise.
struct TrackerSample
{
  double stamp_s = 0.0;  ///< time of the measurement [s since start]
  Pose2 T_world_sensor;  ///< measured sensor pose
};

/// Receives the simulated streams in time order. At an encoder instant the order is
/// onJointState, onBaseOdometry (encoders.output odometry), onTruth, then onTracker (if the
/// tracker is enabled). A multi-beam sweep comes
/// (onCloud) when it is complete, one sweep period after its stamp.
class SimulationSink
{
public:
  virtual ~SimulationSink() = default;
  virtual void onJointState(const JointStateSample& sample) = 0;
  virtual void onScan(const ScanSample& sample) = 0;
  virtual void onTruth(const TruthSample& sample) = 0;
  virtual void onTracker(const TrackerSample& /*sample*/) {}
  virtual void onCloud(const CloudSample& /*sample*/) {}
  virtual void onWheelTick(const WheelTickSample& /*sample*/) {}
  virtual void onBaseOdometry(const BaseOdometrySample& /*sample*/) {}
  virtual void onImu(const ImuSample& /*sample*/) {}
};

/// Forwards every sample to several sinks, in order.
class TeeSink : public SimulationSink
{
public:
  explicit TeeSink(std::vector<SimulationSink*> sinks) : sinks_(std::move(sinks)) {}
  void onJointState(const JointStateSample& s) override
  {
    forward(&SimulationSink::onJointState, s);
  }
  void onScan(const ScanSample& s) override { forward(&SimulationSink::onScan, s); }
  void onTruth(const TruthSample& s) override { forward(&SimulationSink::onTruth, s); }
  void onTracker(const TrackerSample& s) override { forward(&SimulationSink::onTracker, s); }
  void onCloud(const CloudSample& s) override { forward(&SimulationSink::onCloud, s); }
  void onWheelTick(const WheelTickSample& s) override { forward(&SimulationSink::onWheelTick, s); }
  void onBaseOdometry(const BaseOdometrySample& s) override
  {
    forward(&SimulationSink::onBaseOdometry, s);
  }
  void onImu(const ImuSample& s) override { forward(&SimulationSink::onImu, s); }

private:
  /// Calls `receive` (one of the SimulationSink callbacks) with `sample` on every sink, in order.
  template <typename Sample>
  void forward(void (SimulationSink::*receive)(const Sample&), const Sample& sample)
  {
    for (auto* sink : sinks_)
      (sink->*receive)(sample);
  }

  std::vector<SimulationSink*> sinks_;
};

/// Counts and motion statistics of a run.
struct SimulationSummary
{
  std::size_t joint_states = 0;
  std::size_t scans = 0;  ///< LaserScans or clouds
  std::size_t truth_samples = 0;
  double distance_m = 0.0;        ///< path length of base_link
  double rotation_rad = 0.0;      ///< summed |heading change|
  std::size_t counter_wraps = 0;  ///< times an incremental counter wrapped around
};

/// Raw encoder output of one joint for its shaft angle [rad]: incremental counters count
/// floor(angle * ticks_per_rev / 2 pi) + initial_ticks modulo 2^counter_bits; absolute
/// encoders report round(angle * ticks_per_rev / 2 pi) modulo ticks_per_rev, in [0, tpr).
/// In radians mode the tick value times 2 pi / ticks_per_rev (absolute: signed).
double encoderReading(const JointEncoderSpec& spec, const EncoderOptions& options,
                      double shaft_angle_rad);

/// Runs the scenario. Throws std::invalid_argument if the scenario does not fit the robot
/// (joint names count) or the start pose is inside a wall.
SimulationSummary simulate(const Scenario& scenario, const World& world, const Robot& robot,
                           SimulationSink& sink);

/// Names of the joints as published (scenario's names or the robot's defaults).
std::vector<std::string> publishedJointNames(const Scenario& scenario, const Robot& robot);

/// Whether a run drove too little for a calibration: less than 5 % of the distance at the
/// scenario's top speed over its duration (a script that stands still, or a random planner
/// boxed in near the start pose).
bool droveTooLittle(const Scenario& scenario, const SimulationSummary& summary);

}  // namespace sim
}  // namespace odometry_calibration
