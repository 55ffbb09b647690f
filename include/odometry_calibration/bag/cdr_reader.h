// Deserialises CDR-encoded ROS 2 messages (as rosbag2 records them) into the ROS 1 C++ message
// types (the layouts: cdr_layout.h). The bytes start with the 4-byte encapsulation header:
// CDR big-endian (00 00) or little-endian (00 01); the parameter-list variants are refused.
// Alignment counts from the end of that header. Every length and count is checked against the
// bytes that remain before anything is allocated: a corrupted count costs nothing.
#pragma once

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <vector>

#include <ros/message_traits.h>
#include <ros/time.h>
#include <boost/array.hpp>

#include "odometry_calibration/bag/cdr_layout.h"

namespace odometry_calibration {

/// A message whose bytes do not hold what its type needs (cut off, a count beyond its bytes, a
/// string without its NUL, an unknown encapsulation). The message names what and the offset.
class CdrError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// A cursor over one CDR message. Not copyable; the bytes must outlive it.
class CdrReader
{
public:
  /// Reads the encapsulation header of `size` bytes at `data`, a message of type `type` (for
  /// the errors' text; must outlive the reader). Throws CdrError.
  CdrReader(const std::uint8_t* data, std::size_t size, const char* type);
  CdrReader(const CdrReader&) = delete;
  CdrReader& operator=(const CdrReader&) = delete;

  bool bigEndian() const { return big_endian_; }
  /// Bytes read so far, the encapsulation header included.
  std::size_t offset() const { return offset_; }

  template <typename T>
  void value(T& v)
  {
    static_assert(std::is_arithmetic_v<T>, "CDR primitives only");
    align(sizeof(T));
    need(sizeof(T), "a value");
    std::memcpy(&v, data_ + offset_, sizeof(T));
    offset_ += sizeof(T);
    if (sizeof(T) > 1 && swap_) {
      auto* bytes = reinterpret_cast<std::uint8_t*>(&v);
      std::reverse(bytes, bytes + sizeof(T));
    }
  }
  void text(std::string& s);
  void stamp(ros::Time& t);
  template <typename T, std::size_t N>
  void array(boost::array<T, N>& a)
  {
    static_assert(std::is_arithmetic_v<T>, "CDR primitives only");
    primitives(a.data(), sizeof(T), N, "a fixed-size array");
  }
  /// A sequence of primitives: one copy (and a byte swap when the endianness differs).
  template <typename T>
  void sequence(std::vector<T>& v)
  {
    static_assert(std::is_arithmetic_v<T>, "CDR primitives only");
    const std::size_t n = count(sizeof(T));
    v.resize(n);
    if (n > 0)
      primitives(v.data(), sizeof(T), n, "a sequence's elements");
  }
  /// A sequence of strings or structures, each at least 4 bytes in CDR.
  template <typename T, typename Element>
  void sequence(std::vector<T>& v, Element element)
  {
    v.resize(count(4));
    for (T& item : v)
      element(item);
  }

private:
  /// Aligns to `size` and copies `n` primitives of `size` bytes into `out` (host order).
  void primitives(void* out, std::size_t size, std::size_t n, const char* what);
  /// A sequence's uint32 count, checked: n elements of at least `min_size` bytes must fit.
  std::size_t count(std::size_t min_size);
  /// Skips the padding before a primitive of `size` (1, 2, 4 or 8) bytes.
  void align(std::size_t size)
  {
    const std::size_t padding = (0 - (offset_ - 4)) & (size - 1);
    need(padding, "the alignment padding");
    offset_ += padding;
  }
  /// Throws unless `n` more bytes remain, naming `what` and where.
  void need(std::size_t n, const char* what) const
  {
    if (n > size_ - offset_)
      cutOff(n, what);
  }
  [[noreturn]] void cutOff(std::size_t n, const char* what) const;

  const std::uint8_t* data_;
  std::size_t size_;
  std::size_t offset_ = 4;
  bool big_endian_ = false;
  bool swap_ = false;  ///< the stream's byte order is not the host's
  const char* type_;
};

/// `size` bytes of CDR (encapsulation header first) as a message of type M (one of cdr_layout.h).
/// Throws CdrError when they do not hold one.
template <typename M>
void readCdr(const std::uint8_t* data, std::size_t size, M& message)
{
  CdrReader reader(data, size, ros::message_traits::datatype<M>());
  cdr::layout(reader, message);
}

}  // namespace odometry_calibration
