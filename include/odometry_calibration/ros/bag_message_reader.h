// Reads a bag view's messages on a thread of its own, ahead of the pairing: deserialised and
// converted into the core's types (joint readings, scans, sensor poses) in batches through a
// bounded queue, in the view's order. The pairing thread then only pairs, and the reading fills
// the moments the pairing threads wait for each other.
#pragma once

#include <condition_variable>
#include <cstdint>
#include <deque>
#include <exception>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <rosbag/view.h>
#include <Eigen/Core>

#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// One message, converted.
struct BagInput
{
  enum class Kind
  {
    kJoints,     ///< `raw`: the configured joints' positions, signs applied
    kBadJoints,  ///< a JointState that could not be used (`problem` says why)
    kScan,       ///< `scan` (from a LaserScan, or a PointCloud2 of the cloud source; a
                 ///< non-empty `problem`: the cloud's per-point times were not used, and why)
    kBadScan,    ///< a LaserScan or PointCloud2 that gave no scan (`problem` says why)
    kPose,       ///< `pose`: the sensor's pose from an odometry or pose message
  };
  Kind kind = Kind::kJoints;
  double stamp_s = 0.0;   ///< header stamp [s]
  double fraction = 0.0;  ///< position in the view's time span [0, 1]
  Eigen::VectorXd raw;
  Scan scan;
  Pose2 pose;
  std::string frame;  ///< the scan's or cloud's frame, the odometry's child frame (or empty)
  std::string problem;
  std::string publisher;  ///< the connection's callerid: the node that published it (or empty)
  std::size_t source = 0;  ///< the ego-motion source (egoMotionSources order) of an ego input
};

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
  /// Starts reading `view` (which must outlive the reader) for the topics of `config`: the
  /// joint states and every ego-motion source's (egoMotionSources), each ego input tagged with
  /// its source.
  BagMessageReader(rosbag::View& view, const CalibrationConfig& config,
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
  void read(rosbag::View& view, const CalibrationConfig& config);
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
  std::vector<std::string> cloud_frames_;    ///< each source's first cloud's frame
  std::vector<std::uint8_t> message_bytes_;  ///< the message being deserialised
  std::thread thread_;
};

}  // namespace odometry_calibration
