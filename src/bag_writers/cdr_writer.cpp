#include "odometry_calibration/bag_writers/cdr_writer.h"

#include <algorithm>
#include <cstring>
#include <limits>
#include <stdexcept>

namespace odometry_calibration {
namespace {

bool hostIsBigEndian()
{
  const std::uint16_t one = 1;
  std::uint8_t first = 0;
  std::memcpy(&first, &one, 1);
  return first == 0;
}

}  // namespace

CdrWriter::CdrWriter(bool big_endian)
    : bytes_{0, big_endian ? std::uint8_t{0} : std::uint8_t{1}, 0, 0}, big_endian_(big_endian)
{
}

void CdrWriter::primitives(const void* in, std::size_t size, std::size_t n)
{
  const std::size_t body = bytes_.size() - 4;  // alignment counts from the header's end
  bytes_.resize(bytes_.size() + (size - body % size) % size, 0);
  const std::size_t at = bytes_.size();
  bytes_.resize(at + size * n);
  std::memcpy(bytes_.data() + at, in, size * n);
  if (size > 1 && big_endian_ != hostIsBigEndian()) {
    for (std::size_t k = 0; k < n; ++k)
      std::reverse(bytes_.data() + at + k * size, bytes_.data() + at + (k + 1) * size);
  }
}

void CdrWriter::count(std::size_t n)
{
  if (n > std::numeric_limits<std::uint32_t>::max())
    throw std::length_error("a CDR sequence of " + std::to_string(n) + " elements");
  const auto n32 = static_cast<std::uint32_t>(n);
  primitives(&n32, 4, 1);
}

void CdrWriter::text(const std::string& s)
{
  count(s.size() + 1);  // the length counts the terminating NUL
  bytes_.insert(bytes_.end(), s.begin(), s.end());
  bytes_.push_back(0);
}

void CdrWriter::stamp(const ros::Time& t)
{
  if (t.sec > static_cast<std::uint32_t>(std::numeric_limits<std::int32_t>::max()))
    throw std::out_of_range("a stamp beyond ROS 2's int32 seconds: " + std::to_string(t.sec));
  value(static_cast<std::int32_t>(t.sec));
  value(t.nsec);
}

}  // namespace odometry_calibration
