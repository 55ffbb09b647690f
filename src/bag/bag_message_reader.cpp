#include "odometry_calibration/bag/bag_message_reader.h"

#include <signal.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <csignal>
#include <cstdio>
#include <cstring>
#include <type_traits>
#include <utility>

#include "odometry_calibration/ros/message_adapter.h"

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

/// What the messages on one of the read topics are: the joint states, joint `wheel`'s ticks of
/// std_msgs type `tick_type` (non-empty), or source `source`'s ego-motion messages of `type`.
struct Route
{
  std::string topic;
  bool joints = false;
  std::size_t source = 0;
  EgoMotionSource type = EgoMotionSource::kScan;
  std::string tick_type;
  std::size_t wheel = 0;
  bool gyro = false;  ///< gyro.topic's sensor_msgs/Imu
};

/// The wheels' routes (the joint states, or each joint's tick topic), then each ego-motion
/// source's.
std::vector<Route> routes(const CalibrationConfig& config)
{
  std::vector<Route> result;
  if (config.wheels.source == WheelSource::kTicks) {
    for (std::size_t j = 0; j < config.wheels.topics.size(); ++j) {
      result.push_back({config.wheels.topics[j], true, 0, EgoMotionSource::kScan,
                        config.wheels.message_type, j});
    }
  } else if (config.wheels.source == WheelSource::kOdometry) {
    // The base's own odometry: a wheel route of type odometry.
    result.push_back({config.wheels.topics[0], true, 0, EgoMotionSource::kOdometry, "", 0});
  } else {
    result.push_back({config.joint_state_topic, true, 0, EgoMotionSource::kScan, "", 0});
  }
  const std::vector<EgoMotionSourceConfig> sources = egoMotionSources(config);
  for (std::size_t k = 0; k < sources.size(); ++k)
    result.push_back({sources[k].topic, false, k, sources[k].type, "", 0});
  if (!config.gyro.topic.empty())
    result.push_back({config.gyro.topic, false, 0, EgoMotionSource::kScan, "", 0, true});
  return result;
}

/// The messages the reading thread deserialises into, reused from one message to the next.
struct MessageBuffers
{
  sensor_msgs::JointState joints;
  sensor_msgs::LaserScan scan;
  sensor_msgs::PointCloud2 cloud;
  nav_msgs::Odometry odometry;
  geometry_msgs::PoseStamped pose;
  sensor_msgs::Imu imu;
};

/// The current message deserialised as M into `message`, then converted by `adapter` into
/// `input` (for source `source`; false: of another type). Times reading and converting.
template <typename M>
bool readAs(RecordedMessages& messages, const MessageAdapter& adapter, std::size_t source,
            M& message, ReadTimers& timers, ConvertedInput& input)
{
  if (!messages.read(message))
    return false;
  const auto converted = timers.endReading();
  if constexpr (std::is_same_v<M, sensor_msgs::JointState> || std::is_same_v<M, sensor_msgs::Imu>) {
    input = adapter.convert(message, messages.publisher());
  } else if constexpr (std::is_same_v<M, sensor_msgs::PointCloud2>) {
    double filtering_s = 0.0;
    input = adapter.convert(message, source, messages.publisher(), &filtering_s);
    const auto filtering =
        std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(filtering_s));
    timers.converting -= filtering;
    timers.filtering += filtering;
  } else {
    input = adapter.convert(message, source, messages.publisher());
  }
  timers.endConverting(converted);
  return true;
}

/// The current message as a wheel tick of `route` (its record time as its time: the message has
/// no stamp), converted into `input`; false when it is of another type.
bool readWheelTick(RecordedMessages& messages, const MessageAdapter& adapter, const Route& route,
                   ReadTimers& timers, ConvertedInput& input)
{
  double value = 0.0;
  if (!messages.readWheelTick(route.tick_type, value))
    return false;
  const auto converted = timers.endReading();
  input =
      adapter.convertWheelTick(value, route.wheel, messages.recordTime_s(), messages.publisher());
  timers.endConverting(converted);
  return true;
}

/// The current message as the base's own odometry (wheels.source odometry), converted into
/// `input`; false when it is of another type.
bool readBaseOdometry(RecordedMessages& messages, const MessageAdapter& adapter,
                      nav_msgs::Odometry& message, ReadTimers& timers, ConvertedInput& input)
{
  if (!messages.read(message))
    return false;
  const auto converted = timers.endReading();
  input = adapter.convertBaseOdometry(message, messages.publisher());
  timers.endConverting(converted);
  return true;
}

/// The current message, on `route`'s topic, converted into `input`; false when it is not of
/// the topic's type (a pose source takes Odometry and PoseStamped alike).
bool readCurrent(RecordedMessages& messages, const MessageAdapter& adapter, const Route& route,
                 MessageBuffers& buffers, ReadTimers& timers, ConvertedInput& input)
{
  if (!route.tick_type.empty())
    return readWheelTick(messages, adapter, route, timers, input);
  if (route.joints && route.type == EgoMotionSource::kOdometry)
    return readBaseOdometry(messages, adapter, buffers.odometry, timers, input);
  if (route.joints)
    return readAs(messages, adapter, 0, buffers.joints, timers, input);
  if (route.gyro)
    return readAs(messages, adapter, 0, buffers.imu, timers, input);
  switch (route.type) {
    case EgoMotionSource::kScan:
      return readAs(messages, adapter, route.source, buffers.scan, timers, input);
    case EgoMotionSource::kCloud:
      return readAs(messages, adapter, route.source, buffers.cloud, timers, input);
    case EgoMotionSource::kOdometry:
    case EgoMotionSource::kPose:
      return readAs(messages, adapter, route.source, buffers.odometry, timers, input) ||
             readAs(messages, adapter, route.source, buffers.pose, timers, input);
  }
  return false;
}

/// readCurrent, with a message that cannot be deserialised (UnreadableMessage) made a bad input
/// of its route, skipped and counted by the session as any other bad message.
bool readOrMarkBad(RecordedMessages& messages, const MessageAdapter& adapter, const Route& route,
                   MessageBuffers& buffers, ReadTimers& timers, ConvertedInput& input)
{
  try {
    return readCurrent(messages, adapter, route, buffers, timers, input);
  } catch (const UnreadableMessage& error) {
    input = ConvertedInput();
    input.kind = route.gyro     ? ConvertedInput::Kind::kGyro
                 : route.joints ? ConvertedInput::Kind::kBadJoints
                                : ConvertedInput::Kind::kBadEgoMessage;
    input.source = route.joints ? 0 : route.source;
    input.stamp_s = messages.recordTime_s();
    input.problem = error.what();
    input.message_type = route.type == EgoMotionSource::kCloud  ? "PointCloud2"
                         : route.type == EgoMotionSource::kScan ? "LaserScan"
                                                                : "pose";
    input.publisher = messages.publisher();
    timers.endConverting(timers.endReading());
    return true;
  }
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

BagMessageReader::BagMessageReader(RecordedMessages& messages, const CalibrationConfig& config,
                                   const std::string& bags)
{
  thread_ = std::thread([this, &messages, config, bags] {
    const BagReadScope reading(bags);
    try {
      read(messages, config);
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

void BagMessageReader::read(RecordedMessages& messages, const CalibrationConfig& config)
{
  const MessageAdapter adapter(config);
  const std::vector<Route> topic_routes = routes(config);
  MessageBuffers buffers;
  const double begin_s = messages.beginTime_s();
  const double span_s = std::max(1e-9, messages.endTime_s() - begin_s);
  ReadTimers timers;
  std::vector<BagInput> batch;
  while (messages.next()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (stopping_)
        return;
    }
    const std::string& topic = messages.topic();
    const auto route = std::find_if(topic_routes.begin(), topic_routes.end(),
                                    [&](const Route& r) { return r.topic == topic; });
    BagInput input;
    if (route == topic_routes.end() ||
        !readOrMarkBad(messages, adapter, *route, buffers, timers, input.input))
      continue;  // another topic, or another message type on the topic
    input.fraction = (messages.recordTime_s() - begin_s) / span_s;
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

std::vector<std::string> readTopics(const CalibrationConfig& config)
{
  std::vector<std::string> topics;
  if (config.wheels.source == WheelSource::kTicks || config.wheels.source == WheelSource::kOdometry)
    topics = config.wheels.topics;
  else
    topics.push_back(config.joint_state_topic);
  for (const EgoMotionSourceConfig& source : egoMotionSources(config))
    topics.push_back(source.topic);
  if (!config.gyro.topic.empty())
    topics.push_back(config.gyro.topic);
  return topics;
}

}  // namespace odometry_calibration
