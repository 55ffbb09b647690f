// The MCAP file format's building blocks (https://mcap.dev/spec, major version 0), shared by
// the reader (mcap_file.h) and the writer (rosbag2_mcap_writer.h): the magic, the record
// opcodes, a bounded little-endian cursor over a record's fields, an appender of fields, the
// CRC-32 the format uses (libdeflate's), and chunk compression ("", "zstd" through libzstd, "lz4"
// through liblz4's frame format). Every length read is checked against the bytes that remain before
// anything is allocated.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace odometry_calibration {
namespace mcap {

/// The 8 bytes an MCAP file starts and ends with: 0x89 "MCAP" '0' "\r\n".
extern const std::uint8_t kMagic[8];
constexpr std::size_t kMagicSize = 8;
/// A record's opcode (1 byte) and content length (uint64) before its content.
constexpr std::size_t kRecordPrefixSize = 9;
/// The largest chunk this reader decompresses [bytes]: writers close chunks at a few MB.
constexpr std::uint64_t kMaxChunkSize = 1ull << 30;

enum Opcode : std::uint8_t
{
  kHeader = 0x01,
  kFooter = 0x02,
  kSchema = 0x03,
  kChannel = 0x04,
  kMessage = 0x05,
  kChunk = 0x06,
  kMessageIndex = 0x07,
  kChunkIndex = 0x08,
  kAttachment = 0x09,
  kAttachmentIndex = 0x0A,
  kStatistics = 0x0B,
  kMetadata = 0x0C,
  kMetadataIndex = 0x0D,
  kSummaryOffset = 0x0E,
  kDataEnd = 0x0F,
};

/// Bytes that do not hold what the format says they must: `offset` is the file's byte where it
/// shows, the text says what was expected there.
class FormatError : public std::runtime_error
{
public:
  FormatError(std::uint64_t offset, const std::string& cause)
      : std::runtime_error(cause), offset_(offset)
  {
  }
  std::uint64_t offset() const { return offset_; }

private:
  std::uint64_t offset_;
};

/// A cursor over `size` bytes at `data`, which sit at byte `base` of the file (for the errors'
/// offsets). Each read throws FormatError, naming `what`, when the bytes run out.
class Cursor
{
public:
  Cursor(const std::uint8_t* data, std::size_t size, std::uint64_t base)
      : data_(data), size_(size), base_(base)
  {
  }
  std::uint8_t u8(const char* what);
  std::uint16_t u16(const char* what);
  std::uint32_t u32(const char* what);
  std::uint64_t u64(const char* what);
  /// A string: uint32 length, then its bytes.
  std::string text(const char* what);
  /// `n` bytes (returned in place, not copied).
  const std::uint8_t* bytes(std::uint64_t n, const char* what);
  /// A uint32-length-prefixed block of bytes, as a cursor of its own.
  Cursor block32(const char* what);

  std::size_t offset() const { return offset_; }
  std::size_t remaining() const { return size_ - offset_; }
  std::uint64_t fileOffset() const { return base_ + offset_; }

private:
  void need(std::uint64_t n, const char* what) const;

  const std::uint8_t* data_;
  std::size_t size_;
  std::uint64_t base_;
  std::size_t offset_ = 0;
};

/// Appends little-endian fields to a byte buffer.
class Appender
{
public:
  explicit Appender(std::vector<std::uint8_t>& out) : out_(out) {}
  void u8(std::uint8_t v) { out_.push_back(v); }
  void u16(std::uint16_t v) { little(v, 2); }
  void u32(std::uint32_t v) { little(v, 4); }
  void u64(std::uint64_t v) { little(v, 8); }
  void text(const std::string& s);
  void bytes(const std::uint8_t* data, std::size_t size);
  /// A record's opcode and a length placeholder; `finishRecord` fills in the length.
  std::size_t beginRecord(Opcode opcode);
  void finishRecord(std::size_t start);

private:
  void little(std::uint64_t v, int n);
  std::vector<std::uint8_t>& out_;
};

/// The CRC-32 (IEEE, as zlib computes it; libdeflate's, several GB/s with the CPU's carry-less
/// multiply) of `size` bytes, continuing `crc` (0 to start).
std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc = 0);

/// A chunk's records `compressed` with `compression` ("", "zstd", "lz4") decompressed into
/// `out` (resized to `uncompressed_size`, at most kMaxChunkSize). Throws std::runtime_error
/// saying why they do not decompress to exactly that size.
void decompressChunk(const std::string& compression, const std::uint8_t* compressed,
                     std::size_t size, std::uint64_t uncompressed_size,
                     std::vector<std::uint8_t>& out);

/// `records` compressed with `compression` ("", "zstd" or "lz4"). Throws std::invalid_argument
/// for another name.
std::vector<std::uint8_t> compressChunk(const std::string& compression,
                                        const std::vector<std::uint8_t>& records);

}  // namespace mcap
}  // namespace odometry_calibration
