// Fuzz target: the CDR reader (cdr_reader.h) on arbitrary bytes. The first byte picks the
// message type (JointState, LaserScan, PointCloud2, Odometry, PoseStamped, Imu, TFMessage), the
// rest is the CDR message, encapsulation header first. A message that reads must write back
// (cdr_writer.h) into bytes that read as the same message; bad bytes may only throw CdrError.
#include <cstdint>
#include <cstdlib>
#include <vector>

#include "odometry_calibration/bag/cdr_reader.h"
#include "odometry_calibration/bag_writers/cdr_writer.h"

using namespace odometry_calibration;

namespace {

template <typename M>
void readAndWriteBack(const std::uint8_t* data, std::size_t size)
{
  M message;
  try {
    readCdr(data, size, message);
  } catch (const CdrError&) {
    return;
  }
  CdrReader header(data, size, "header");
  const std::vector<std::uint8_t> again = writeCdr(message, header.bigEndian());
  M read_again;
  readCdr(again.data(), again.size(), read_again);
  // NaNs compare unequal: compare the bytes they write instead.
  if (writeCdr(read_again, header.bigEndian()) != again)
    std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (size == 0)
    return 0;
  const std::uint8_t* message = data + 1;
  const std::size_t length = size - 1;
  switch (data[0] % 7) {
    case 0:
      readAndWriteBack<sensor_msgs::JointState>(message, length);
      break;
    case 1:
      readAndWriteBack<sensor_msgs::LaserScan>(message, length);
      break;
    case 2:
      readAndWriteBack<sensor_msgs::PointCloud2>(message, length);
      break;
    case 3:
      readAndWriteBack<nav_msgs::Odometry>(message, length);
      break;
    case 4:
      readAndWriteBack<geometry_msgs::PoseStamped>(message, length);
      break;
    case 5:
      readAndWriteBack<sensor_msgs::Imu>(message, length);
      break;
    default:
      readAndWriteBack<tf2_msgs::TFMessage>(message, length);
      break;
  }
  return 0;
}
