// Writes the simulator's streams into a rosbag: sensor_msgs/JointState (positions, or velocities
// only with encoders.output joint_velocity; with encoders.output ticks instead one std_msgs
// number topic per joint, recorded at each reading's time; with encoders.output odometry also
// the base's own nav_msgs/Odometry), sensor_msgs/LaserScan
// (each laser of the scenario on its own topic and frame)
// (or sensor_msgs/PointCloud2 of the multi-beam lidar: x, y, z, intensity, ring, time),
// and the ground truth as nav_msgs/Odometry plus its own tf tree (sim_world -> sim_base_link
// -> sim_<laser frame>), kept apart from the frames a calibration uses (odom, base_link,
// laser) so that it never leaks into calibration inputs. The same messages at the same record
// times go into a ROS 1 bag or a rosbag2 bag folder (SQLite storage, CDR, optionally zstd; or
// MCAP storage, its chunks compressed with zstd, lz4 or not at all).
#pragma once

#include <memory>
#include <ostream>
#include <string>
#include <vector>

#include <ros/time.h>

#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"

namespace rosbag {
class Bag;
}

namespace odometry_calibration {

class Rosbag2McapWriter;
class Rosbag2SqliteWriter;

/// What a simulation writes: a ROS 1 bag, or a rosbag2 bag folder in SQLite storage (its
/// storage file as it is, or compressed with zstd) or in MCAP storage (its chunks compressed
/// with zstd, lz4, or not at all).
enum class BagFormat
{
  kRos1,
  kDb3,
  kDb3Zstd,
  kMcapZstd,
  kMcapLz4,
  kMcap,
};

/// "bag", "db3", "db3.zstd" or "mcap" (simulate's --format) as a BagFormat, MCAP's chunks
/// compressed with `chunk_compression` ("zstd", "lz4" or "none"; simulate's
/// --chunk-compression). Throws std::invalid_argument for another name.
BagFormat bagFormatFromName(const std::string& name, const std::string& chunk_compression = "zstd");

/// A SimulationSink that writes a bag. Messages are written with their header stamps as bag
/// times; the bag is uncompressed so a fixed seed gives a byte-identical file.
class SimBagWriter : public sim::SimulationSink
{
public:
  /// Opens `bag_path` for writing (truncates). Throws std::runtime_error if it cannot. A
  /// rosbag2 `format` writes into the existing folder `bag_path` the bag named `bag_name`
  /// (the folder's final name: its storage file is "<bag_name>_0.db3" or "<bag_name>_0.mcap").
  SimBagWriter(const std::string& bag_path, const sim::Scenario& scenario,
               std::vector<std::string> joint_names, BagFormat format = BagFormat::kRos1,
               const std::string& bag_name = "");
  ~SimBagWriter() override;
  SimBagWriter(const SimBagWriter&) = delete;
  SimBagWriter& operator=(const SimBagWriter&) = delete;

  void onJointState(const sim::JointStateSample& sample) override;
  void onScan(const sim::ScanSample& sample) override;
  void onTruth(const sim::TruthSample& sample) override;
  void onTracker(const sim::TrackerSample& sample) override;
  /// The IMU's reading as sensor_msgs/Imu on imu.topic (angular velocity only; orientation and
  /// linear acceleration marked unknown: their covariances' first element -1).
  void onImu(const sim::ImuSample& sample) override;
  void onCloud(const sim::CloudSample& sample) override;
  /// encoders.output ticks: the joint's reading on its tick topic as encoders.tick_type.
  void onWheelTick(const sim::WheelTickSample& sample) override;
  /// encoders.output odometry: the base's own nav_msgs/Odometry (odom -> base_link) on
  /// encoders.odometry_topic, besides the JointState.
  void onBaseOdometry(const sim::BaseOdometrySample& sample) override;

  /// Writes the index and closes the file.
  void close();

private:
  /// `message` on `topic` at record time `time`, into the bag of either format.
  template <typename M>
  void record(const std::string& topic, const ros::Time& time, const M& message);

  std::unique_ptr<rosbag::Bag> bag_;
  std::unique_ptr<Rosbag2SqliteWriter> rosbag2_;
  std::unique_ptr<Rosbag2McapWriter> mcap_;
  sim::Scenario scenario_;
  std::vector<sim::LaserOptions> lasers_;  ///< every laser, in ScanSample::laser_index order
  std::vector<std::uint32_t> scan_seqs_;   ///< the extra lasers' header seq (the first's below)
  std::vector<std::string> joint_names_;
  std::vector<std::string> tick_topics_;  ///< encoders.output ticks: each joint's topic
  std::uint32_t joint_seq_ = 0, scan_seq_ = 0, truth_seq_ = 0, tracker_seq_ = 0;
  std::uint32_t base_odometry_seq_ = 0, imu_seq_ = 0;
  bool wrote_static_tf_ = false;
};

/// The bag a simulation writes unless told otherwise: "<scenario name>.bag" (rosbag2: the
/// folder "<scenario name>").
std::string defaultSimulationBagPath(const sim::Scenario& scenario,
                                     BagFormat format = BagFormat::kRos1);

/// The truth file that goes with a bag unless told otherwise: the bag's path without ".bag",
/// plus "_truth.yaml".
std::string defaultTruthPath(const std::string& bag_path);

/// Runs the scenario into a bag written atomically (temporary file, renamed when complete; a
/// rosbag2 folder staged and renamed) and writes the truth YAML next to it atomically ("" skips
/// it). `extra_sink`, if given, receives every sample too. Returns the run's summary.
sim::SimulationSummary simulateToBag(const sim::Scenario& scenario, const std::string& bag_path,
                                     const std::string& truth_path,
                                     sim::SimulationSink* extra_sink = nullptr,
                                     BagFormat format = BagFormat::kRos1);

/// Where the simulate tool writes a run: the bag and the truth ("" = the defaults above), and
/// the tricycle dataset's text log ("" = none).
struct SimulationFiles
{
  std::string bag_path;
  std::string truth_path;
  std::string tricycle_log_path;
  BagFormat format = BagFormat::kRos1;
};

/// The simulate tool's run: the scenario into its bag, truth and (if asked) tricycle log, the
/// summary printed to `out`, a warning on `err` when the robot barely moved. Returns the exit
/// status: 0 written; 2 a tricycle log asked of a scenario that cannot give one (a tricycle
/// robot with the tracker enabled). Throws what loading or writing throws.
int simulateToFiles(const sim::Scenario& scenario, SimulationFiles files, std::ostream& out,
                    std::ostream& err);

}  // namespace odometry_calibration
