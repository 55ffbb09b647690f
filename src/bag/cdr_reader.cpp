#include "odometry_calibration/bag/cdr_reader.h"

#include <algorithm>
#include <cstring>
#include <utility>

namespace odometry_calibration {
namespace {

/// Reverses the bytes of each of `n` elements of `size` bytes at `data`.
void swapEach(std::uint8_t* data, std::size_t size, std::size_t n)
{
  for (std::size_t k = 0; k < n; ++k, data += size)
    std::reverse(data, data + size);
}

bool hostIsBigEndian()
{
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

}  // namespace

CdrReader::CdrReader(const std::uint8_t* data, std::size_t size, const char* type)
    : data_(data), size_(size), type_(type)
{
  if (size < 4) {
    throw CdrError("a " + std::string(type_) + " of " + std::to_string(size) +
                   " bytes is cut off in its 4-byte encapsulation header");
  }
  if (data[0] != 0 || data[1] > 1) {
    const bool parameter_list = data[0] == 0 && (data[1] == 2 || data[1] == 3);
    throw CdrError("a " + std::string(type_) + " in an unsupported encapsulation (" +
                   (parameter_list
                        ? std::string("parameter-list CDR")
                        : "bytes " + std::to_string(data[0]) + " " + std::to_string(data[1])) +
                   "; plain CDR expected)");
  }
  big_endian_ = data[1] == 0;
  swap_ = big_endian_ != hostIsBigEndian();
}

void CdrReader::cutOff(std::size_t n, const char* what) const
{
  throw CdrError("a " + std::string(type_) + " of " + std::to_string(size_) +
                 " bytes is cut off at byte " + std::to_string(offset_) + ": " + what + " needs " +
                 std::to_string(n) + " bytes, " + std::to_string(size_ - offset_) + " remain");
}

void CdrReader::primitives(void* out, std::size_t size, std::size_t n, const char* what)
{
  align(size);
  need(size * n, what);  // n <= size_ / size: checked by count() for sequences
  std::memcpy(out, data_ + offset_, size * n);
  offset_ += size * n;
  if (size > 1 && swap_)
    swapEach(static_cast<std::uint8_t*>(out), size, n);
}

std::size_t CdrReader::count(std::size_t min_size)
{
  std::uint32_t n = 0;
  primitives(&n, 4, 1, "a sequence's count");
  // Checked before anything is allocated: n elements need at least n * min_size bytes.
  if (n > (size_ - offset_) / min_size) {
    throw CdrError("a " + std::string(type_) + " of " + std::to_string(size_) + " bytes claims " +
                   std::to_string(n) + " elements at byte " + std::to_string(offset_) +
                   ", more than its " + std::to_string(size_ - offset_) + " remaining bytes hold");
  }
  return n;
}

void CdrReader::text(std::string& s)
{
  std::uint32_t length = 0;
  primitives(&length, 4, 1, "a string's length");
  need(length, "a string");
  if (length == 0) {  // not written by ROS 2 (its empty string is the NUL alone), but harmless
    s.clear();
    return;
  }
  if (data_[offset_ + length - 1] != 0) {
    throw CdrError("a " + std::string(type_) +
                   " has a string without its terminating NUL at byte " + std::to_string(offset_));
  }
  s.assign(reinterpret_cast<const char*>(data_ + offset_), length - 1);
  offset_ += length;
}

void CdrReader::stamp(ros::Time& t)
{
  std::int32_t sec = 0;
  std::uint32_t nanosec = 0;
  value(sec);
  value(nanosec);
  if (sec < 0 || nanosec >= 1000000000u) {
    throw CdrError("a " + std::string(type_) + " has a stamp out of range (" + std::to_string(sec) +
                   " s, " + std::to_string(nanosec) + " ns) before byte " +
                   std::to_string(offset_));
  }
  t.sec = static_cast<std::uint32_t>(sec);
  t.nsec = nanosec;
}

}  // namespace odometry_calibration
