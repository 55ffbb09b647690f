#include "odometry_calibration/bag_writers/sim_bag_writer.h"

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <rosbag/bag.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <tf2_msgs/TFMessage.h>

#include "odometry_calibration/bag_writers/rosbag2_mcap_writer.h"
#include "odometry_calibration/bag_writers/rosbag2_sqlite_writer.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/staged_directory.h"
#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/ros/wheel_tick_messages.h"
#include "odometry_calibration/sim/tricycle_log_sink.h"
#include "odometry_calibration/sim/world.h"

namespace odometry_calibration {
namespace {

/// A counter reading [0, 2^bits) as a message field of type T: a value beyond a signed type's
/// maximum is sent as the same bits (value - 2^digits), as a driver's wrapping counter would.
template <typename T>
T wheelTickValue(double value)
{
  if constexpr (std::is_integral_v<T>) {
    const double max = static_cast<double>(std::numeric_limits<T>::max());
    const double span = max - static_cast<double>(std::numeric_limits<T>::min()) + 1.0;
    if (value > max)
      value -= span;
    return static_cast<T>(std::llround(value));
  } else {
    return static_cast<T>(value);
  }
}

/// The tick topics of `scenario`'s joints: encoders.tick_topics, or "/<joint name>_ticks".
std::vector<std::string> tickTopics(const sim::Scenario& scenario,
                                    const std::vector<std::string>& joint_names)
{
  if (scenario.encoders.output != "ticks")
    return {};
  if (scenario.encoders.tick_topics.empty()) {
    std::vector<std::string> topics;
    for (const std::string& name : joint_names)
      topics.push_back("/" + name + "_ticks");
    return topics;
  }
  if (scenario.encoders.tick_topics.size() != joint_names.size()) {
    throw std::invalid_argument("encoders.tick_topics lists " +
                                std::to_string(scenario.encoders.tick_topics.size()) +
                                " topics for " + std::to_string(joint_names.size()) + " joints");
  }
  visitWheelTickType(scenario.encoders.tick_type, [](auto) { return 0; });  // a known type
  return scenario.encoders.tick_topics;
}

ros::Time rosTime(double start_time_s, double stamp_s)
{
  // Integer nanoseconds: the same stamp for the same inputs on every machine.
  const std::int64_t start_ns = std::llround(start_time_s * 1e9);
  const std::int64_t ns = start_ns + std::llround(stamp_s * 1e9);
  ros::Time time;
  time.fromNSec(static_cast<std::uint64_t>(ns));
  return time;
}

}  // namespace

BagFormat bagFormatFromName(const std::string& name, const std::string& chunk_compression)
{
  if (chunk_compression != "zstd" && chunk_compression != "lz4" && chunk_compression != "none") {
    throw std::invalid_argument("unknown chunk compression '" + chunk_compression +
                                "' (zstd, lz4 or none)");
  }
  if (name == "bag")
    return BagFormat::kRos1;
  if (name == "db3")
    return BagFormat::kDb3;
  if (name == "db3.zstd")
    return BagFormat::kDb3Zstd;
  if (name == "mcap") {
    return chunk_compression == "zstd"  ? BagFormat::kMcapZstd
           : chunk_compression == "lz4" ? BagFormat::kMcapLz4
                                        : BagFormat::kMcap;
  }
  throw std::invalid_argument("unknown bag format '" + name + "' (bag, db3, db3.zstd or mcap)");
}

SimBagWriter::SimBagWriter(const std::string& bag_path, const sim::Scenario& scenario,
                           std::vector<std::string> joint_names, BagFormat format,
                           const std::string& bag_name)
    : scenario_(scenario),
      lasers_(sim::allLasers(scenario)),
      scan_seqs_(lasers_.size(), 0),
      joint_names_(std::move(joint_names)),
      tick_topics_(tickTopics(scenario, joint_names_))
{
  if (format == BagFormat::kMcapZstd || format == BagFormat::kMcapLz4 ||
      format == BagFormat::kMcap) {
    const char* compression = format == BagFormat::kMcapZstd  ? "zstd"
                              : format == BagFormat::kMcapLz4 ? "lz4"
                                                              : "none";
    mcap_ = std::make_unique<Rosbag2McapWriter>(bag_path, bag_name, compression);
    return;
  }
  if (format != BagFormat::kRos1) {
    rosbag2_ =
        std::make_unique<Rosbag2SqliteWriter>(bag_path, bag_name, format == BagFormat::kDb3Zstd);
    return;
  }
  bag_ = std::make_unique<rosbag::Bag>();
  try {
    bag_->open(bag_path, rosbag::bagmode::Write);
  } catch (const std::exception& error) {
    throw std::runtime_error("cannot write bag '" + bag_path + "': " + error.what());
  }
  bag_->setCompression(rosbag::compression::Uncompressed);
}

SimBagWriter::~SimBagWriter() = default;

template <typename M>
void SimBagWriter::record(const std::string& topic, const ros::Time& time, const M& message)
{
  if (rosbag2_)
    rosbag2_->write(topic, time, message);
  else if (mcap_)
    mcap_->write(topic, time, message);
  else
    bag_->write(topic, time, message);
}

void SimBagWriter::onJointState(const sim::JointStateSample& sample)
{
  if (scenario_.encoders.output == "ticks")
    return;  // each joint on its own topic (onWheelTick)
  sensor_msgs::JointState message;
  message.header.seq = joint_seq_++;
  message.header.stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  message.name = joint_names_;
  if (scenario_.encoders.output == "joint_velocity")
    message.velocity = sample.velocities;
  else
    message.position = sample.positions;
  record(scenario_.encoders.topic, message.header.stamp, message);
}

void SimBagWriter::onWheelTick(const sim::WheelTickSample& sample)
{
  if (sample.joint >= tick_topics_.size())
    throw std::invalid_argument("a tick of joint " + std::to_string(sample.joint) + ", " +
                                std::to_string(tick_topics_.size()) + " tick topics");
  // No stamp in the message: its record time is the reading's time.
  const ros::Time time = rosTime(scenario_.start_time_s, sample.stamp_s);
  visitWheelTickType(scenario_.encoders.tick_type, [&](auto message) {
    message.data = wheelTickValue<decltype(message.data)>(sample.value);
    record(tick_topics_[sample.joint], time, message);
    return 0;
  });
}

void SimBagWriter::onScan(const sim::ScanSample& sample)
{
  if (sample.laser_index >= lasers_.size())
    throw std::invalid_argument("a scan of laser " + std::to_string(sample.laser_index) +
                                ", the scenario has " + std::to_string(lasers_.size()));
  const sim::LaserOptions& laser = lasers_[sample.laser_index];
  sensor_msgs::LaserScan message;
  message.header.seq = sample.laser_index == 0 ? scan_seq_++ : scan_seqs_[sample.laser_index]++;
  message.header.stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  message.header.frame_id = laser.frame_id;
  message.angle_min = sample.angle_min_rad;
  message.angle_max = sample.angle_min_rad +
                      sample.angle_increment_rad * static_cast<float>(sample.ranges.size() - 1);
  message.angle_increment = sample.angle_increment_rad;
  // As a driver publishes it: stamped at the first ray, ray i taken i * time_increment later
  // (0: the whole scan at its stamp), recorded when the sweep is over.
  message.time_increment = static_cast<float>(sample.time_increment_s);
  message.scan_time = static_cast<float>(1.0 / laser.rate_hz);
  message.range_min = sample.range_min_m;
  message.range_max = sample.range_max_m;
  message.ranges = sample.ranges;
  const double sweep_s = sample.time_increment_s * static_cast<double>(sample.ranges.size() - 1);
  record(laser.topic, rosTime(scenario_.start_time_s, sample.stamp_s + sweep_s), message);
}

void SimBagWriter::onCloud(const sim::CloudSample& sample)
{
  // The layout lidar drivers write (e.g. velodyne_pointcloud's): x, y, z, intensity, ring, time
  // (FLOAT32 seconds after the stamp), packed; with `point_times: absolute` the last field is
  // Hesai's `timestamp` (FLOAT64 seconds since the epoch) instead.
  const bool absolute = scenario_.laser.point_times == "absolute";
  sensor_msgs::PointCloud2 message;
  message.header.seq = scan_seq_++;
  message.header.stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  message.header.frame_id = scenario_.laser.frame_id;
  auto field = [&](const char* name, std::uint32_t offset, std::uint8_t datatype) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = offset;
    f.datatype = datatype;
    f.count = 1;
    message.fields.push_back(f);
  };
  field("x", 0, sensor_msgs::PointField::FLOAT32);
  field("y", 4, sensor_msgs::PointField::FLOAT32);
  field("z", 8, sensor_msgs::PointField::FLOAT32);
  field("intensity", 12, sensor_msgs::PointField::FLOAT32);
  field("ring", 16, sensor_msgs::PointField::UINT16);
  if (absolute)
    field("timestamp", 18, sensor_msgs::PointField::FLOAT64);
  else
    field("time", 18, sensor_msgs::PointField::FLOAT32);
  const std::size_t n = sample.size();
  message.height = 1;
  message.width = static_cast<std::uint32_t>(n);
  message.is_bigendian = false;
  message.point_step = absolute ? 26 : 22;
  message.row_step = message.point_step * message.width;
  message.is_dense = true;
  message.data.resize(message.row_step);
  const double stamp_s = message.header.stamp.toSec();
  std::uint8_t* out = message.data.data();
  for (std::size_t i = 0; i < n; ++i, out += message.point_step) {
    std::memcpy(out, &sample.xyz[3 * i], 12);
    std::memcpy(out + 12, &sample.intensity[i], 4);
    std::memcpy(out + 16, &sample.ring[i], 2);
    if (absolute) {
      const double time_s = stamp_s + static_cast<double>(sample.time_s[i]);
      std::memcpy(out + 18, &time_s, 8);
    } else {
      std::memcpy(out + 18, &sample.time_s[i], 4);
    }
  }
  // Bag time: when the sweep is complete and the driver publishes it.
  const ros::Time published =
      rosTime(scenario_.start_time_s, sample.stamp_s + 1.0 / scenario_.laser.rate_hz);
  record(scenario_.laser.topic, published, message);
}

void SimBagWriter::onTruth(const sim::TruthSample& sample)
{
  const ros::Time stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  const std::string world = scenario_.ground_truth_frame;
  const std::string base = "sim_base_link";
  if (!wrote_static_tf_) {
    tf2_msgs::TFMessage tf_static;
    for (const sim::LaserOptions& options : lasers_) {  // every laser's true mounting
      geometry_msgs::TransformStamped laser;
      laser.header.stamp = stamp;
      laser.header.frame_id = base;
      laser.child_frame_id = "sim_" + options.frame_id;
      laser.transform = ros_conversions::toTransformMsg(options.T_base_laser);
      tf_static.transforms.push_back(laser);
    }
    record("/tf_static", stamp, tf_static);
    wrote_static_tf_ = true;
  }
  nav_msgs::Odometry odometry;
  odometry.header.seq = truth_seq_++;
  odometry.header.stamp = stamp;
  odometry.header.frame_id = world;
  odometry.child_frame_id = base;
  odometry.pose.pose = ros_conversions::toPoseMsg(sample.T_world_base);
  odometry.twist.twist.linear.x = sample.twist.vx_mps;
  odometry.twist.twist.linear.y = sample.twist.vy_mps;
  odometry.twist.twist.angular.z = sample.twist.omega_radps;
  record(scenario_.ground_truth_topic, stamp, odometry);

  tf2_msgs::TFMessage tf;
  geometry_msgs::TransformStamped transform;
  transform.header.stamp = stamp;
  transform.header.frame_id = world;
  transform.child_frame_id = base;
  transform.transform = ros_conversions::toTransformMsg(sample.T_world_base);
  tf.transforms.push_back(transform);
  record("/tf", stamp, tf);
}

void SimBagWriter::onBaseOdometry(const sim::BaseOdometrySample& sample)
{
  // As a base's driver publishes it: odom -> base_link, stamped in the encoders' clock; no tf
  // (the calibration node's odometry owns that tree in a replay).
  nav_msgs::Odometry odometry;
  odometry.header.seq = base_odometry_seq_++;
  odometry.header.stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  odometry.header.frame_id = "odom";
  odometry.child_frame_id = "base_link";
  odometry.pose.pose = ros_conversions::toPoseMsg(sample.T_odom_base);
  odometry.twist.twist.linear.x = sample.twist.vx_mps;
  odometry.twist.twist.linear.y = sample.twist.vy_mps;
  odometry.twist.twist.angular.z = sample.twist.omega_radps;
  record(scenario_.encoders.odometry_topic, odometry.header.stamp, odometry);
}

void SimBagWriter::onTracker(const sim::TrackerSample& sample)
{
  geometry_msgs::PoseStamped pose;
  pose.header.seq = tracker_seq_++;
  pose.header.stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  pose.header.frame_id = scenario_.tracker.frame_id;
  pose.pose = ros_conversions::toPoseMsg(sample.T_world_sensor);
  record(scenario_.tracker.topic, pose.header.stamp, pose);
}

void SimBagWriter::onImu(const sim::ImuSample& sample)
{
  sensor_msgs::Imu imu;
  imu.header.seq = imu_seq_++;
  imu.header.stamp = rosTime(scenario_.start_time_s, sample.stamp_s);
  imu.header.frame_id = scenario_.imu.frame_id;
  imu.orientation_covariance[0] = -1.0;
  imu.linear_acceleration_covariance[0] = -1.0;
  imu.angular_velocity.x = sample.angular_velocity.x();
  imu.angular_velocity.y = sample.angular_velocity.y();
  imu.angular_velocity.z = sample.angular_velocity.z();
  const double variance = scenario_.imu.noise_rad_s * scenario_.imu.noise_rad_s;
  for (int axis = 0; axis < 3; ++axis)
    imu.angular_velocity_covariance[4 * axis] = variance;
  record(scenario_.imu.topic, imu.header.stamp, imu);
}

void SimBagWriter::close()
{
  if (rosbag2_)
    rosbag2_->close();
  else if (mcap_)
    mcap_->close();
  else
    bag_->close();
}

std::string defaultSimulationBagPath(const sim::Scenario& scenario, BagFormat format)
{
  return format == BagFormat::kRos1 ? scenario.name + ".bag" : scenario.name;
}

std::string defaultTruthPath(const std::string& bag_path)
{
  const bool ends_in_bag =
      bag_path.size() > 4 && bag_path.compare(bag_path.size() - 4, 4, ".bag") == 0;
  return (ends_in_bag ? bag_path.substr(0, bag_path.size() - 4) : bag_path) + "_truth.yaml";
}

namespace {

/// The scenario run into `writer` (and `extra_sink`), closed when complete.
sim::SimulationSummary simulateInto(const sim::Scenario& scenario, const sim::World& world,
                                    const sim::Robot& robot, SimBagWriter& writer,
                                    sim::SimulationSink* extra_sink)
{
  std::vector<sim::SimulationSink*> sinks = {&writer};
  if (extra_sink)
    sinks.push_back(extra_sink);
  sim::TeeSink tee(sinks);
  const sim::SimulationSummary summary = sim::simulate(scenario, world, robot, tee);
  writer.close();
  return summary;
}

/// The scenario into the rosbag2 bag folder `folder`, staged and put in place when complete.
sim::SimulationSummary simulateToRosbag2(const sim::Scenario& scenario, const sim::World& world,
                                         const sim::Robot& robot, const std::string& folder,
                                         BagFormat format, sim::SimulationSink* extra_sink)
{
  std::filesystem::path final_path(folder);
  if (!final_path.has_filename())  // "bag/"
    final_path = final_path.parent_path();
  const std::string parent =
      final_path.has_parent_path() ? final_path.parent_path().string() : std::string(".");
  const std::string name = final_path.filename().string();
  StagedDirectory staged(parent, name);
  SimBagWriter writer(staged.path(), scenario, sim::publishedJointNames(scenario, robot), format,
                      name);
  const sim::SimulationSummary summary = simulateInto(scenario, world, robot, writer, extra_sink);
  staged.commit();
  return summary;
}

}  // namespace

sim::SimulationSummary simulateToBag(const sim::Scenario& scenario, const std::string& bag_path,
                                     const std::string& truth_path, sim::SimulationSink* extra_sink,
                                     BagFormat format)
{
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  sim::SimulationSummary summary;
  if (format != BagFormat::kRos1) {
    summary = simulateToRosbag2(scenario, world, *robot, bag_path, format, extra_sink);
  } else {
    const std::string temporary = bag_path + ".partial";
    try {
      SimBagWriter writer(temporary, scenario, sim::publishedJointNames(scenario, *robot));
      summary = simulateInto(scenario, world, *robot, writer, extra_sink);
    } catch (...) {
      std::remove(temporary.c_str());
      throw;
    }
    if (std::rename(temporary.c_str(), bag_path.c_str()) != 0) {
      std::remove(temporary.c_str());
      throw std::runtime_error("cannot move the finished bag to '" + bag_path + "'");
    }
  }
  if (!truth_path.empty()) {
    writeFileAtomically(truth_path, sim::scenarioTruthYaml(scenario, *robot));
  }
  return summary;
}

int simulateToFiles(const sim::Scenario& scenario, SimulationFiles files, std::ostream& out,
                    std::ostream& err)
{
  if (files.bag_path.empty())
    files.bag_path = defaultSimulationBagPath(scenario, files.format);
  if (files.truth_path.empty())
    files.truth_path = defaultTruthPath(files.bag_path);
  std::unique_ptr<sim::TricycleLogSink> log_sink;
  if (!files.tricycle_log_path.empty()) {
    if (!sim::canWriteTricycleLog(scenario)) {
      err << "error: --tricycle-log needs a tricycle robot with 'tracker: {enabled: "
             "true}' in the scenario\n";
      return 2;
    }
    log_sink = sim::makeTricycleLogSink(scenario);
  }
  const sim::SimulationSummary summary =
      simulateToBag(scenario, files.bag_path, files.truth_path, log_sink.get(), files.format);
  if (log_sink) {
    writeFileAtomically(files.tricycle_log_path, log_sink->text());
  }
  out << "simulated " << scenario.duration_s << " s of '" << scenario.name << "' ("
      << scenario.robot.type << "): " << summary.joint_states << " joint states, " << summary.scans
      << " scans, " << summary.distance_m << " m driven, " << summary.rotation_rad
      << " rad turned, " << summary.counter_wraps << " counter wrap-arounds\n"
      << "bag:   " << files.bag_path << "\ntruth: " << files.truth_path << "\n";
  if (sim::droveTooLittle(scenario, summary)) {
    err << "warning: the robot drove only " << summary.distance_m
        << " m (a script that stands still, or a random planner boxed in near the start "
           "pose: move start_pose or lower motion.clearance_m); a calibration needs "
           "motion\n";
  }
  if (log_sink) {
    out << "tricycle log: " << files.tricycle_log_path << " (" << log_sink->rows() << " rows)\n";
  }
  return 0;
}

}  // namespace odometry_calibration
