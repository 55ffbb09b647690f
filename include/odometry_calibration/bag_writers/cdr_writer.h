// Serialises the ROS 1 C++ message types as the CDR-encoded ROS 2 messages rosbag2 records
// (the layouts: cdr_layout.h; the reader: cdr_reader.h), in either endianness.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include <ros/time.h>
#include <boost/array.hpp>

#include "odometry_calibration/bag/cdr_layout.h"

namespace odometry_calibration {

/// Appends one CDR message to a buffer: the encapsulation header first, then the fields.
class CdrWriter
{
public:
  explicit CdrWriter(bool big_endian = false);

  /// The message so far.
  const std::vector<std::uint8_t>& bytes() const { return bytes_; }

  template <typename T>
  void value(const T& v)
  {
    static_assert(std::is_arithmetic_v<T>, "CDR primitives only");
    primitives(&v, sizeof(T), 1);
  }
  void text(const std::string& s);
  void stamp(const ros::Time& t);
  template <typename T, std::size_t N>
  void array(const boost::array<T, N>& a)
  {
    static_assert(std::is_arithmetic_v<T>, "CDR primitives only");
    primitives(a.data(), sizeof(T), N);
  }
  template <typename T>
  void sequence(const std::vector<T>& v)
  {
    static_assert(std::is_arithmetic_v<T>, "CDR primitives only");
    count(v.size());
    if (!v.empty())  // an empty sequence is not aligned to its elements (as Fast CDR writes it)
      primitives(v.data(), sizeof(T), v.size());
  }
  template <typename T, typename Element>
  void sequence(const std::vector<T>& v, Element element)
  {
    count(v.size());
    for (const T& item : v)
      element(item);
  }

private:
  /// Pads to `size` and appends `n` primitives of `size` bytes from `in` in the stream's order.
  void primitives(const void* in, std::size_t size, std::size_t n);
  /// A sequence's uint32 count (throws std::length_error beyond 2^32 - 1).
  void count(std::size_t n);

  std::vector<std::uint8_t> bytes_;
  bool big_endian_;
};

/// `message` (one of cdr_layout.h's types) as CDR bytes, encapsulation header first.
template <typename M>
std::vector<std::uint8_t> writeCdr(const M& message, bool big_endian = false)
{
  CdrWriter writer(big_endian);
  cdr::layout(writer, message);
  return writer.bytes();
}

}  // namespace odometry_calibration
