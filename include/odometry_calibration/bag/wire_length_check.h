// Checks a serialised ROS message's claimed lengths before deserialising it. roscpp's
// ros::serialization resizes each array to the length its 4-byte count claims before it reads
// the elements, so one corrupted count makes it allocate up to 4 G elements (130 GB of strings)
// before it notices that the bytes are missing: on a small robot computer that is the
// out-of-memory killer, under AddressSanitizer an abort. These walkers follow the wire format
// (little-endian; string = uint32 length + bytes; array = uint32 count + elements; ROS wiki,
// "roscpp/Overview/MessagesSerializationAndAdaptingTypes") of the message types this package
// reads and say whether every length fits in the bytes that are there. The messages fuzz target
// passes only such messages on (what it finds should be this package's faults, not roscpp's),
// and the bag reader checks every message with them, after checkBagRecords (bag_record_check.h)
// made sure that the length each record claims lies inside its chunk.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

namespace odometry_calibration {
namespace ros_conversions {

/// The message types the node and the bag tools deserialise.
enum class WireMessage
{
  kJointState,
  kLaserScan,
  kPointCloud2,
  kOdometry,
  kPoseStamped,
  kImu,
};

/// The type's name as in a bag ("sensor_msgs/JointState", ...).
std::string wireMessageName(WireMessage type);

/// True when every string and array length in the serialised `type` at `data` (`size` bytes)
/// fits in `size`: deserialising it then allocates at most what the bytes describe. Does not
/// require the message to use all `size` bytes.
bool wireLengthsFit(WireMessage type, const std::uint8_t* data, std::size_t size);

}  // namespace ros_conversions
}  // namespace odometry_calibration
