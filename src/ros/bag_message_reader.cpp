#include "odometry_calibration/ros/bag_message_reader.h"

#include <signal.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <utility>

#include <geometry_msgs/PoseStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>

#include "odometry_calibration/ros/conversions.h"
#include "odometry_calibration/ros/point_cloud_conversion.h"
#include "odometry_calibration/ros/wire_length_check.h"
#include "odometry_calibration/scan/cloud_to_scan.h"
#include "odometry_calibration/session/calibration_session.h"

namespace odometry_calibration {
namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kBatchSize = 64;   // messages per hand-over
constexpr std::size_t kMaxBatches = 16;  // read ahead at most this many batches

double seconds(Clock::duration duration)
{
  return std::chrono::duration<double>(duration).count();
}

// The fault handler may only touch these: a flag of the faulting thread and a fixed buffer.
thread_local volatile std::sig_atomic_t t_reading_bag = 0;
char g_bag_names[2048] = "a bag";

void write2(const char* text)
{
  ssize_t ignored = ::write(STDERR_FILENO, text, std::strlen(text));
  (void)ignored;
}

void onBagReadFault(int signal)
{
  if (t_reading_bag) {
    write2("error: ");
    write2(g_bag_names);
    write2(signal == SIGBUS ? " is corrupted: rosbag read outside the bag's data (SIGBUS)"
                            : " is corrupted: rosbag read outside the bag's data (SIGSEGV)");
    write2("; check it with 'rosbag check' (a bag whose index is lost: 'rosbag reindex')\n");
    ::_exit(1);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

/// The message deserialised as T, or nullptr when it is of another type. Its bytes are copied
/// out of the chunk first (checkBagRecords vouched that they lie inside it) and their lengths
/// are checked before deserialising: a corrupted array count would otherwise make roscpp
/// allocate up to 4 G elements before it notices the bytes are missing.
template <typename T>
boost::shared_ptr<T> deserialiseChecked(const rosbag::MessageInstance& message,
                                        ros_conversions::WireMessage type,
                                        std::vector<std::uint8_t>& bytes)
{
  const std::string md5 = message.getMD5Sum();
  if (message.getDataType() != ros::message_traits::datatype<T>() ||
      (md5 != "*" && md5 != ros::message_traits::md5sum<T>()))
    return nullptr;
  bytes.resize(message.size());
  ros::serialization::OStream out(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  message.write(out);
  if (!ros_conversions::wireLengthsFit(type, bytes.data(), bytes.size())) {
    throw ros::Exception("a " + message.getDataType() + " message on '" + message.getTopic() +
                         "' at " + std::to_string(message.getTime().toSec()) +
                         " s claims strings or arrays longer than its " +
                         std::to_string(bytes.size()) + " bytes");
  }
  auto deserialised = boost::make_shared<T>();
  ros::serialization::IStream in(bytes.data(), static_cast<std::uint32_t>(bytes.size()));
  ros::serialization::deserialize(in, *deserialised);
  return deserialised;
}

/// Where the reading thread's time goes: reading and deserialising, converting, filtering
/// clouds. `start` is when the current stretch of reading began.
struct ReadTimers
{
  Clock::duration reading{}, converting{}, filtering{};
  Clock::time_point start = Clock::now();

  /// Ends the stretch of reading now; returns now.
  Clock::time_point endReading()
  {
    const auto now = Clock::now();
    reading += now - start;
    return now;
  }
  /// Ends a conversion begun at `from`; the next stretch of reading starts now.
  void endConverting(Clock::time_point from)
  {
    start = Clock::now();
    converting += start - from;
  }
};

/// A JointState into `input` (raw positions with the configured signs, or the reason they are
/// unusable); false when the message is not one.
bool readJointState(const rosbag::MessageInstance& message, const CalibrationConfig& config,
                    const std::vector<EncoderChannelOptions>& channels,
                    std::vector<std::uint8_t>& bytes, ReadTimers& timers, BagInput& input)
{
  const auto joints = deserialiseChecked<sensor_msgs::JointState>(
      message, ros_conversions::WireMessage::kJointState, bytes);
  if (!joints)
    return false;
  const auto converted = timers.endReading();
  input.stamp_s = joints->header.stamp.toSec();
  try {
    input.raw = applySigns(config, ros_conversions::rawJointPositions(*joints, channels));
  } catch (const std::invalid_argument& error) {
    input.kind = BagInput::Kind::kBadJoints;
    input.problem = error.what();
  }
  timers.endConverting(converted);
  return true;
}

/// A LaserScan into `input`; false when the message is not one.
bool readLaserScan(const rosbag::MessageInstance& message, long long max_rays,
                   std::vector<std::uint8_t>& bytes, ReadTimers& timers, BagInput& input)
{
  const auto scan = deserialiseChecked<sensor_msgs::LaserScan>(
      message, ros_conversions::WireMessage::kLaserScan, bytes);
  if (!scan)
    return false;
  const auto converted = timers.endReading();
  input.stamp_s = scan->header.stamp.toSec();
  input.frame = scan->header.frame_id;
  try {  // an impossible geometry or too many rays: skipped and counted, as the live node does
    if (const std::string problem = scanRaysProblem(scan->ranges.size(), max_rays);
        !problem.empty())
      throw std::invalid_argument(problem);
    input.scan = ros_conversions::fromLaserScanMsg(*scan);
    input.kind = BagInput::Kind::kScan;
  } catch (const std::invalid_argument& error) {
    input.kind = BagInput::Kind::kBadScan;
    input.problem = error.what();
  }
  timers.endConverting(converted);
  return true;
}

/// Why a cloud in `frame_id` is not the sensor's: no frame, or another than the first cloud's
/// (`sensor_frame`, empty before the first); empty when it is.
std::string cloudFrameProblem(const std::string& frame_id, const std::string& sensor_frame)
{
  if (frame_id.empty())
    return "PointCloud2 names no frame (header.frame_id is empty)";
  if (!sensor_frame.empty() && frame_id != sensor_frame) {
    return "PointCloud2 in frame '" + frame_id + "', not the sensor's frame '" + sensor_frame +
           "' (the first cloud's)";
  }
  return "";
}

/// A PointCloud2 into `input`: converted and cut into a planar scan, or a bad scan with the
/// reason; false when the message is not one. The first cloud's frame becomes the sensor's.
bool readCloud(const rosbag::MessageInstance& message, const CalibrationConfig& config,
               std::vector<std::uint8_t>& bytes, std::string& sensor_frame, ReadTimers& timers,
               BagInput& input)
{
  const auto cloud = deserialiseChecked<sensor_msgs::PointCloud2>(
      message, ros_conversions::WireMessage::kPointCloud2, bytes);
  if (!cloud)
    return false;
  const auto converted = timers.endReading();
  input.stamp_s = cloud->header.stamp.toSec();
  input.kind = BagInput::Kind::kBadScan;
  input.problem = cloudFrameProblem(cloud->header.frame_id, sensor_frame);
  if (!input.problem.empty()) {
    timers.endConverting(converted);
    return true;
  }
  sensor_frame = cloud->header.frame_id;
  input.frame = sensor_frame;
  try {
    const auto lidar = ros_conversions::fromPointCloud2Msg(*cloud, config.cloud.point_times);
    const auto filtered = Clock::now();
    timers.converting += filtered - converted;
    try {
      input.scan = cloudToScan(lidar.cloud, lidar.has_times, config.cloud);
      input.kind = BagInput::Kind::kScan;
      input.problem = lidar.time_problem;
    } catch (const std::invalid_argument& error) {
      input.problem = "PointCloud2 skipped: " + std::string(error.what());
    }
    timers.start = Clock::now();
    timers.filtering += timers.start - filtered;
  } catch (const std::invalid_argument& error) {
    input.problem = "PointCloud2 skipped: " + std::string(error.what());
    timers.endConverting(converted);
  }
  return true;
}

/// An Odometry's or a PoseStamped's pose into `input`; false when the message is neither.
bool readPose(const rosbag::MessageInstance& message, std::vector<std::uint8_t>& bytes,
              BagInput& input)
{
  input.kind = BagInput::Kind::kPose;
  if (const auto odometry = deserialiseChecked<nav_msgs::Odometry>(
          message, ros_conversions::WireMessage::kOdometry, bytes)) {
    input.stamp_s = odometry->header.stamp.toSec();
    input.pose = ros_conversions::fromPoseMsg(odometry->pose.pose);
    input.frame = odometry->child_frame_id;
    return true;
  }
  if (const auto stamped = deserialiseChecked<geometry_msgs::PoseStamped>(
          message, ros_conversions::WireMessage::kPoseStamped, bytes)) {
    input.stamp_s = stamped->header.stamp.toSec();
    input.pose = ros_conversions::fromPoseMsg(stamped->pose);
    return true;
  }
  return false;
}

}  // namespace

void containBagReadFaults()
{
  struct sigaction action = {};
  action.sa_handler = onBagReadFault;
  sigemptyset(&action.sa_mask);
  ::sigaction(SIGSEGV, &action, nullptr);
  ::sigaction(SIGBUS, &action, nullptr);
}

BagReadScope::BagReadScope(const std::string& bags)
{
  std::snprintf(g_bag_names, sizeof(g_bag_names), "%s", bags.c_str());
  t_reading_bag = 1;
}

BagReadScope::~BagReadScope()
{
  t_reading_bag = 0;
}

BagMessageReader::BagMessageReader(rosbag::View& view, const CalibrationConfig& config,
                                   const std::string& bags)
{
  thread_ = std::thread([this, &view, config, bags] {
    const BagReadScope reading(bags);
    try {
      read(view, config);
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex_);
      error_ = std::current_exception();
    }
    std::lock_guard<std::mutex> lock(mutex_);
    finished_ = true;
    changed_.notify_all();
  });
}

BagMessageReader::~BagMessageReader()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
  }
  changed_.notify_all();
  thread_.join();
}

void BagMessageReader::push(std::vector<BagInput> batch)
{
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return stopping_ || batches_.size() < kMaxBatches; });
  batches_.push_back(std::move(batch));
  changed_.notify_all();
}

std::vector<BagInput> BagMessageReader::next()
{
  std::unique_lock<std::mutex> lock(mutex_);
  changed_.wait(lock, [this] { return finished_ || !batches_.empty(); });
  if (batches_.empty()) {
    if (error_)
      std::rethrow_exception(error_);
    return {};
  }
  std::vector<BagInput> batch = std::move(batches_.front());
  batches_.pop_front();
  changed_.notify_all();
  return batch;
}

void BagMessageReader::read(rosbag::View& view, const CalibrationConfig& config)
{
  const std::vector<EncoderChannelOptions> channels = encoderChannels(config);
  const std::vector<EgoMotionSourceConfig> sources = egoMotionSources(config);
  cloud_frames_.assign(sources.size(), "");
  const double begin_s = view.getBeginTime().toSec();
  const double span_s = std::max(1e-9, (view.getEndTime() - view.getBeginTime()).toSec());
  ReadTimers timers;
  std::vector<BagInput> batch;
  for (const rosbag::MessageInstance& message : view) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_)
        return;
    }
    BagInput input;
    input.fraction = (message.getTime().toSec() - begin_s) / span_s;
    input.publisher = message.getCallerId();
    const std::string& topic = message.getTopic();
    while (input.source + 1 < sources.size() && sources[input.source].topic != topic)
      ++input.source;
    const EgoMotionSource type = sources[input.source].type;
    const bool read_one =
        topic == config.joint_state_topic
            ? readJointState(message, config, channels, message_bytes_, timers, input)
        : type == EgoMotionSource::kScan
            ? readLaserScan(message, config.max_scan_rays, message_bytes_, timers, input)
        : type == EgoMotionSource::kCloud
            ? readCloud(message, config, message_bytes_, cloud_frames_[input.source], timers, input)
            : readPose(message, message_bytes_, input);
    if (!read_one)
      continue;  // another message type on the topic
    batch.push_back(std::move(input));
    if (batch.size() == kBatchSize) {
      timers.reading += Clock::now() - timers.start;
      push(std::move(batch));
      batch.clear();
      timers.start = Clock::now();
    }
  }
  timers.reading += Clock::now() - timers.start;
  if (!batch.empty())
    push(std::move(batch));
  read_time_s_ = seconds(timers.reading);
  conversion_time_s_ = seconds(timers.converting);
  filtering_time_s_ = seconds(timers.filtering);
}

}  // namespace odometry_calibration
