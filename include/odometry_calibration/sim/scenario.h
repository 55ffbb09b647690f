// A simulation scenario: world, robot with its true parameters, laser, encoders, motion.
// Read from YAML (see config/sim/scenarios/*.yaml, which document every key).
#pragma once

#include <limits>
#include <map>
#include <string>
#include <vector>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/sim/drive_plan.h"
#include "odometry_calibration/sim/imu_model.h"
#include "odometry_calibration/sim/robot.h"

namespace odometry_calibration {
namespace sim {

/// The simulated laser: a planar 2D scanner (sensor_msgs/LaserScan), or a multi-beam 3D lidar
/// (`type: multibeam`, sensor_msgs/PointCloud2, e.g. 16 rings over +-15 deg like a VLP-16).
struct LaserOptions
{
  std::string type = "planar";         ///< planar | multibeam
  Pose2 T_base_laser{0.15, 0.0, 0.0};  ///< true mounting pose [m, m, rad]
  int rays = 720;                      ///< rays per scan
  double fov_rad = 4.71238898;         ///< field of view, centred on the laser's x axis [rad]
  double rate_hz = 10.0;               ///< scans per second
  double range_noise_m = 0.01;         ///< Gaussian range noise sigma [m]
  double min_range_m = 0.05;           ///< closer returns are reported as invalid (NaN)
  double max_range_m = 20.0;           ///< no return beyond: +inf (REP 117)
  double dropout_probability = 0.0;    ///< chance a ray returns nothing (NaN)
  // Sensor realism (sim/laser_model.h); every effect is off by default.
  /// Rays taken one after the other over the sweep while the robot moves: ray i at
  /// i * time_increment after the scan's stamp, time_increment = angle increment / (2 pi
  /// rate_hz) (a mirror turning once per scan period, as a Hokuyo URG or a SICK LMS).
  bool sweep = false;
  double range_noise_per_m = 0.0;  ///< noise sigma = range_noise_m + this * range [m/m]
  /// Correlation of the range noise between neighbouring rays, in [0, 0.95]: the noise follows
  /// an AR(1) chain along the scan, e_i = sigma_i u_i with u_i = rho u_(i-1) + sqrt(1 - rho^2)
  /// z_i, z_i standard normal, so each ray keeps its sigma; the chain moves on at rays without
  /// a return too (the real URG-04LX log reads 0.49 between neighbours and 0.21 two rays apart,
  /// rho and rho^2). 0 = off. Planar lasers only.
  double range_noise_correlation = 0.0;
  double range_resolution_m = 0.0;       ///< returns rounded to multiples of this; 0 = exact [m]
  double mixed_pixel_probability = 0.0;  ///< chance a beam across a depth step mixes its ranges
  /// Full angle of the beam [rad]: its footprint (at least one ray increment wide) is what can
  /// straddle a depth discontinuity and give a mixed pixel.
  double beam_divergence_rad = 0.0;
  /// Dark surfaces: chance of losing a return from max_range_m at normal incidence; it scales
  /// with (range / max_range_m)^2 / cos(incidence) (the echo's weakness), capped at 1.
  double dark_dropout_probability = 0.0;
  /// A range error fixed to the rays (moves with the sensor): ray i reads
  /// range_ripple_m * sin(2 pi i / range_ripple_period_rays) too long [m]; 0 = off.
  double range_ripple_m = 0.0;
  double range_ripple_period_rays = 40.0;  ///< rays per period of the ripple [rays], >= 2
  std::string frame_id = "laser";          ///< header frame of the scans
  std::string topic = "/scan";             ///< bag topic
  /// The laser's clock: its scans (sweeps) are stamped at the true time of their first ray
  /// (start) + this [s]; each laser of a robot has its own. 0 = the true time.
  double time_offset_s = 0.0;
  // Multi-beam only: the rings' elevations are equally spaced over [min, max]; each sweep
  // turns once counter-clockwise from -pi during the 1 / rate_hz before its cloud is
  // published, the cloud stamped at the sweep's start, each point with its `time` after it.
  int rings = 16;                           ///< beams
  double elevation_min_rad = -0.261799;     ///< lowest ring (-15 deg) [rad]
  double elevation_max_rad = 0.261799;      ///< highest ring (+15 deg) [rad]
  double horizontal_step_rad = 0.00698132;  ///< azimuth between firings (0.4 deg) [rad]
  double height_m = 0.5;                    ///< mounting height above the floor [m]
  double roll_rad = 0.0;                    ///< mounting roll (about the laser's x) [rad]
  double pitch_rad = 0.0;                   ///< mounting pitch (about its y; + nose down) [rad]
  /// The per-point time field: `relative`: `time`, FLOAT32 seconds after the stamp (Velodyne);
  /// `absolute`: `timestamp`, FLOAT64 seconds since the epoch (Hesai).
  std::string point_times = "relative";
};

/// The wheel / joint encoders, published together as one sensor_msgs/JointState.
struct EncoderOptions
{
  double rate_hz = 50.0;  ///< JointState messages per second
  /// Each reading's spacing from the previous one is 1 / rate_hz plus a uniform draw in
  /// [-rate_jitter_s, rate_jitter_s] (a slow, unsteady driver loop); 0 = evenly spaced [s].
  double rate_jitter_s = 0.0;
  std::string topic = "/joint_states";   ///< bag topic
  std::vector<std::string> joint_names;  ///< empty = the robot's default names
  bool output_ticks = true;              ///< position in raw ticks (true) or radians (false)
  int counter_bits = 32;                 ///< incremental counters wrap at 2^bits; 0 = never
  double initial_ticks = 0.0;            ///< incremental counters start here [ticks]
  /// JointState stamps = true sample time + offset [s]. Negative: the encoder values are
  /// stamped earlier than they were measured (they run ahead of the laser).
  double time_offset_s = 0.0;
  /// What the wheels publish: "joint_state" (JointState positions), "ticks" (one std_msgs
  /// topic per joint: tick_topics, tick_type; no stamp, recorded at the reading's time) or
  /// "joint_velocity" (JointState with velocities only, `position` empty) or "odometry" (the
  /// JointState positions and the base's own odometry, below).
  std::string output = "joint_state";
  std::vector<std::string> tick_topics;      ///< ticks: one per joint; empty: "/<joint>_ticks"
  std::string tick_type = "std_msgs/Int32";  ///< ticks: the std_msgs type
  /// ticks: joint j is read j * this after each encoder instant (the wheels' messages apart) [s].
  double tick_stagger_s = 0.0;
  /// odometry: besides the JointState, the base's own nav_msgs/Odometry on this topic at each
  /// encoder instant, integrated from the true motion between instants with its translation
  /// times (1 + odometry_translation_error) and its rotation times (1 + odometry_rotation_error).
  std::string odometry_topic = "/odom";
  double odometry_translation_error = 0.0;  ///< the base's translation scale error [-]
  double odometry_rotation_error = 0.0;     ///< the base's rotation scale error [-]
};

/// An external tracker (motion capture) measuring the laser's world pose at every encoder
/// sample, as in the tricycle dataset. Off unless enabled.
struct TrackerOptions
{
  bool enabled = false;
  double translation_noise_m = 0.003;   ///< Gaussian sigma of x and y [m]
  double rotation_noise_rad = 0.0005;   ///< Gaussian sigma of the heading [rad]
  std::string topic = "/tracker/pose";  ///< geometry_msgs/PoseStamped in the bag
  std::string frame_id = "tracker";     ///< header frame of the tracker poses
};

/// The true robot changing at a given time (a worn tyre, a new load, a knocked laser,
/// a shifted laser, an encoder clock that jumps): from `at_s` on, the robot has these
/// parameters, the laser's mounting pose in base_link these extra x, y and yaw, and the encoder
/// stamps this extra offset. The encoders and the drive carry on; only the physics, the laser's
/// pose and the encoders' clock change. Changes add up (each is relative to the pose and offset
/// before it). With several lasers the mounting change moves one of them,
/// `laser_index` (YAML `laser:`, its index in `lasers:` or its frame_id or topic).
struct ParameterChange
{
  double at_s = 0.0;                               ///< simulated time of the change [s]
  std::map<std::string, double> robot_parameters;  ///< new values of robot keys (makeRobot)
  /// The laser the x, y and yaw changes move: 0 the first (`laser`), k the k-th extra laser.
  std::size_t laser_index = 0;
  double laser_x_change_m = 0.0;      ///< added to the laser's mounting x [m]
  double laser_y_change_m = 0.0;      ///< added to the laser's mounting y [m]
  double laser_yaw_change_rad = 0.0;  ///< added to the laser's mounting yaw [rad]
  /// Added to encoders.time_offset_s [s]: a negative change makes the encoder stamps jump back,
  /// so it must be shorter than one encoder period.
  double time_offset_change_s = 0.0;
};

/// Everything one simulation run needs.
struct Scenario
{
  std::string name = "scenario";
  unsigned seed = 1;                   ///< random seed: same seed, byte-identical bag
  double duration_s = 60.0;            ///< simulated time [s]
  double start_time_s = 1700000000.0;  ///< ROS time of the first sample [s since epoch]
  std::string world_path;              ///< world YAML (resolved path)
  Pose2 start_pose;                    ///< T_world_base at t = 0
  RobotOptions robot;
  LaserOptions laser;  ///< the (first) laser; the only one unless extra_lasers are given
  /// The robot's further lasers (e.g. a rear safety scanner), planar each, with their
  /// own pose, rays, rate and time offset, their scans drawn from random streams of their own
  /// (so the first laser's scans do not change when one is added). YAML: `lasers:`, a list
  /// whose first entry is `laser` and the others these.
  std::vector<LaserOptions> extra_lasers;
  EncoderOptions encoders;
  DrivePlanOptions motion;
  TrackerOptions tracker;
  ImuOptions imu;                        ///< the IMU's gyro (sim/imu_model.h); off unless enabled
  std::vector<ParameterChange> changes;  ///< in time order; empty: the robot never changes
  std::string ground_truth_topic = "/ground_truth/odom";  ///< nav_msgs/Odometry of the truth
  std::string ground_truth_frame = "sim_world";           ///< truth tree root (separate)
};

/// Throws std::invalid_argument naming the first invalid field.
void validate(const Scenario& scenario);

/// Every laser of the scenario: `laser`, then the extra lasers (the ScanSample::laser_index
/// order).
std::vector<LaserOptions> allLasers(const Scenario& scenario);

/// Reads a scenario. `world:` is a shipped world name (office, corridor, hall: looked up in
/// `worlds_directory`) or a path relative to the scenario file. Unknown keys are rejected.
/// Throws std::runtime_error naming the file and the key.
Scenario loadScenarioYaml(const std::string& path, const std::string& worlds_directory);

/// What a command line may change in a scenario file.
struct ScenarioOverrides
{
  double seed = -1.0;            ///< >= 0: replaces the scenario's seed (as an unsigned)
  double duration_s = -1.0;      ///< > 0: replaces the scenario's duration [s]
  std::string wheel_output;      ///< non-empty: replaces encoders.output
  int counter_bits = -1;         ///< >= 0: replaces encoders.counter_bits
  std::string tick_type;         ///< non-empty: replaces encoders.tick_type
  double tick_stagger_s = -1.0;  ///< >= 0: replaces encoders.tick_stagger_s [s]
  /// Finite: replaces encoders.odometry_translation_error (odometry_rotation_error) [-].
  double odometry_translation_error = std::numeric_limits<double>::quiet_NaN();
  double odometry_rotation_error = std::numeric_limits<double>::quiet_NaN();
};

/// loadScenarioYaml, then the overrides (the result validated again).
Scenario loadScenarioYaml(const std::string& path, const std::string& worlds_directory,
                          const ScenarioOverrides& overrides);

/// The folder of the worlds shipped with the package (its config/sim/worlds), where a
/// scenario's bare world name is looked up.
std::string shippedWorldsDirectory();

/// YAML text of the scenario with the robot's true parameters after defaults (the truth file).
std::string scenarioTruthYaml(const Scenario& scenario, const Robot& robot);

}  // namespace sim
}  // namespace odometry_calibration
