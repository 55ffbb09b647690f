// Reads recorded messages (recorded_messages.h: a bag view, or another bag format behind the same
// interface) on a thread of its own, ahead of the pairing: deserialised and converted into
// session inputs by the node's own adapter (message_adapter.h) in batches through a bounded
// queue, in record-time order: the joint states and every ego-motion source's messages, each
// tagged with its source's index. The pairing thread then only pairs, and the reading fills
// the moments the pairing threads wait for each other.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "odometry_calibration/bag/recorded_messages.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/session/converted_input.h"

namespace odometry_calibration {

/// One recorded message, converted (message_adapter.h), and where it lies in the recording.
struct BagInput
{
  ConvertedInput input;
  double fraction = 0.0;  ///< position in the recording's time span [0, 1]
};

/// The topics the reader reads for `config`: the joint states' and every ego-motion source's
/// (egoMotionSources order), then gyro.topic when set.
std::vector<std::string> readTopics(const CalibrationConfig& config);

/// rosbag trusts a bag's index: a corrupted index entry makes it read outside its buffers
/// (SIGSEGV, SIGBUS) where no exception can be caught. A tool calls this once at start: from
/// then on such a fault in a thread that holds a BagReadScope ends the program with exit
/// status 1 and "error: <bags> is corrupted: ..." on stderr; a fault anywhere else still
/// crashes as it would have (so that real bugs are not hidden).
void containBagReadFaults();

/// Marks the calling thread as reading `bags` (named in words, e.g. "bag 'a.bag'") while it
/// lives. Only the latest scope's names are kept for the message.
class BagReadScope
{
public:
  explicit BagReadScope(const std::string& bags);
  ~BagReadScope();
  BagReadScope(const BagReadScope&) = delete;
  BagReadScope& operator=(const BagReadScope&) = delete;
};

/// The reading thread. Not copyable; stops and joins when destroyed.
class BagMessageReader
{
public:
  /// Starts reading `messages` (which must outlive the reader) for the topics of `config`
  /// (readTopics; messages on other topics, or of another type than their topic's, are passed
  /// over). `bags` names the recording in words for a fault's message (BagReadScope).
  BagMessageReader(RecordedMessages& messages, const CalibrationConfig& config,
                   const std::string& bags = "a bag");
  ~BagMessageReader();
  BagMessageReader(const BagMessageReader&) = delete;
  BagMessageReader& operator=(const BagMessageReader&) = delete;

  /// The next batch of inputs in order (empty at the end). Rethrows what reading threw (a bag
  /// read error).
  std::vector<BagInput> next();

  /// Time the reading thread spent reading and deserialising, converting, and filtering clouds
  /// into scans (cloud source) [s] (final once next() returned an empty batch).
  double readTime() const { return read_time_s_; }
  double conversionTime() const { return conversion_time_s_; }
  double filteringTime() const { return filtering_time_s_; }

private:
  void read(RecordedMessages& messages, const CalibrationConfig& config);
  void push(std::vector<BagInput> batch);

  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::vector<BagInput>> batches_;
  bool finished_ = false;
  bool stopping_ = false;
  std::exception_ptr error_;
  double read_time_s_ = 0.0;
  double conversion_time_s_ = 0.0;
  double filtering_time_s_ = 0.0;
  std::thread thread_;
};

}  // namespace odometry_calibration
