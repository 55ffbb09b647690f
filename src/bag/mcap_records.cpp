#include "odometry_calibration/bag/mcap_records.h"

#include <cstring>

#include <libdeflate.h>
#include <lz4frame.h>
#include <zstd.h>

namespace odometry_calibration {
namespace mcap {

const std::uint8_t kMagic[8] = {0x89, 'M', 'C', 'A', 'P', '0', '\r', '\n'};

void Cursor::need(std::uint64_t n, const char* what) const
{
  if (n > size_ - offset_) {
    throw FormatError(fileOffset(), std::string(what) + " needs " + std::to_string(n) +
                                        " bytes, only " + std::to_string(size_ - offset_) +
                                        " remain in its record");
  }
}

std::uint8_t Cursor::u8(const char* what)
{
  need(1, what);
  return data_[offset_++];
}

std::uint16_t Cursor::u16(const char* what)
{
  const std::uint8_t low = u8(what);  // (the operands of | have no order of evaluation)
  const std::uint8_t high = u8(what);
  return static_cast<std::uint16_t>(low | high << 8);
}

std::uint32_t Cursor::u32(const char* what)
{
  need(4, what);
  std::uint32_t v = 0;
  for (int k = 3; k >= 0; --k)
    v = (v << 8) | data_[offset_ + static_cast<std::size_t>(k)];
  offset_ += 4;
  return v;
}

std::uint64_t Cursor::u64(const char* what)
{
  need(8, what);
  std::uint64_t v = 0;
  for (int k = 7; k >= 0; --k)
    v = (v << 8) | data_[offset_ + static_cast<std::size_t>(k)];
  offset_ += 8;
  return v;
}

std::string Cursor::text(const char* what)
{
  const std::uint32_t length = u32(what);
  const std::uint8_t* start = bytes(length, what);
  return std::string(reinterpret_cast<const char*>(start), length);
}

const std::uint8_t* Cursor::bytes(std::uint64_t n, const char* what)
{
  need(n, what);
  const std::uint8_t* start = data_ + offset_;
  offset_ += static_cast<std::size_t>(n);
  return start;
}

Cursor Cursor::block32(const char* what)
{
  const std::uint32_t length = u32(what);
  const std::uint64_t base = fileOffset();
  return Cursor(bytes(length, what), length, base);
}

void Appender::text(const std::string& s)
{
  u32(static_cast<std::uint32_t>(s.size()));
  bytes(reinterpret_cast<const std::uint8_t*>(s.data()), s.size());
}

void Appender::bytes(const std::uint8_t* data, std::size_t size)
{
  out_.insert(out_.end(), data, data + size);
}

std::size_t Appender::beginRecord(Opcode opcode)
{
  const std::size_t start = out_.size();
  u8(opcode);
  u64(0);
  return start;
}

void Appender::finishRecord(std::size_t start)
{
  std::uint64_t length = out_.size() - start - kRecordPrefixSize;
  for (std::size_t k = 0; k < 8; ++k, length >>= 8)
    out_[start + 1 + k] = static_cast<std::uint8_t>(length & 0xFF);
}

void Appender::little(std::uint64_t v, int n)
{
  for (int k = 0; k < n; ++k, v >>= 8)
    out_.push_back(static_cast<std::uint8_t>(v & 0xFF));
}

std::uint32_t crc32(const std::uint8_t* data, std::size_t size, std::uint32_t crc)
{
  return libdeflate_crc32(crc, data, size);
}

namespace {

void decompressLz4(const std::uint8_t* compressed, std::size_t size, std::vector<std::uint8_t>& out)
{
  LZ4F_dctx* context = nullptr;
  if (LZ4F_isError(LZ4F_createDecompressionContext(&context, LZ4F_VERSION)))
    throw std::runtime_error("no lz4 decompression context");
  std::size_t written = 0, read = 0;
  std::size_t status = 1;
  while (status != 0 && read < size && written <= out.size()) {
    std::size_t out_size = out.size() - written, in_size = size - read;
    status = LZ4F_decompress(context, out.data() + written, &out_size, compressed + read, &in_size,
                             nullptr);
    if (LZ4F_isError(status)) {
      const std::string name = LZ4F_getErrorName(status);
      LZ4F_freeDecompressionContext(context);
      throw std::runtime_error("lz4: " + name);
    }
    written += out_size;
    read += in_size;
    if (out_size == 0 && in_size == 0)
      break;  // no progress: the output is full while the frame goes on
  }
  LZ4F_freeDecompressionContext(context);
  if (status != 0)
    throw std::runtime_error("the lz4 frame is cut off or holds more than the chunk's size");
  if (written != out.size()) {
    throw std::runtime_error("lz4 gave " + std::to_string(written) + " bytes, the chunk says " +
                             std::to_string(out.size()));
  }
}

}  // namespace

void decompressChunk(const std::string& compression, const std::uint8_t* compressed,
                     std::size_t size, std::uint64_t uncompressed_size,
                     std::vector<std::uint8_t>& out)
{
  if (uncompressed_size > kMaxChunkSize) {
    throw std::runtime_error("the chunk claims " + std::to_string(uncompressed_size) +
                             " bytes uncompressed, more than the " + std::to_string(kMaxChunkSize) +
                             " this reader takes");
  }
  if (compression != "" && compression != "zstd" && compression != "lz4")
    throw std::runtime_error("unknown chunk compression '" + compression + "'");
  if (compression.empty() && uncompressed_size != size) {
    throw std::runtime_error("an uncompressed chunk of " + std::to_string(size) + " bytes claims " +
                             std::to_string(uncompressed_size));
  }
  out.resize(static_cast<std::size_t>(uncompressed_size));
  if (compression.empty()) {
    if (size > 0)
      std::memcpy(out.data(), compressed, size);
  } else if (compression == "zstd") {
    const std::size_t result = ZSTD_decompress(out.data(), out.size(), compressed, size);
    if (ZSTD_isError(result))
      throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(result));
    if (result != out.size()) {
      throw std::runtime_error("zstd gave " + std::to_string(result) + " bytes, the chunk says " +
                               std::to_string(out.size()));
    }
  } else {
    decompressLz4(compressed, size, out);
  }
}

std::vector<std::uint8_t> compressChunk(const std::string& compression,
                                        const std::vector<std::uint8_t>& records)
{
  std::vector<std::uint8_t> out;
  if (compression.empty())
    return records;
  if (compression == "zstd") {
    out.resize(ZSTD_compressBound(records.size()));
    const std::size_t size =
        ZSTD_compress(out.data(), out.size(), records.data(), records.size(), 3);
    if (ZSTD_isError(size))
      throw std::runtime_error(std::string("zstd: ") + ZSTD_getErrorName(size));
    out.resize(size);
    return out;
  }
  if (compression == "lz4") {
    LZ4F_preferences_t preferences{};
    preferences.frameInfo.contentSize = records.size();
    out.resize(LZ4F_compressFrameBound(records.size(), &preferences));
    const std::size_t size =
        LZ4F_compressFrame(out.data(), out.size(), records.data(), records.size(), &preferences);
    if (LZ4F_isError(size))
      throw std::runtime_error(std::string("lz4: ") + LZ4F_getErrorName(size));
    out.resize(size);
    return out;
  }
  throw std::invalid_argument("unknown chunk compression '" + compression +
                              "' (zstd, lz4 or none)");
}

}  // namespace mcap
}  // namespace odometry_calibration
