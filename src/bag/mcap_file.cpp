#include "odometry_calibration/bag/mcap_file.h"

#include <fcntl.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/bag/mcap_records.h"

namespace odometry_calibration {
namespace mcap {
namespace {

/// Footer record: prefix, summary_start, summary_offset_start, summary_crc.
constexpr std::size_t kFooterRecordSize = kRecordPrefixSize + 8 + 8 + 4;
/// A Message record's fields before its data: channel_id, sequence, log_time, publish_time.
constexpr std::size_t kMessageFieldsSize = 2 + 4 + 8 + 8;

std::string hex(std::uint32_t value)
{
  char text[16];
  std::snprintf(text, sizeof(text), "0x%08x", value);
  return text;
}

/// "sensor_msgs/msg/LaserScan" as ROS 1 spells it, "sensor_msgs/LaserScan".
std::string ros1TypeName(const std::string& type)
{
  const std::size_t slash = type.find('/');
  if (slash != std::string::npos && type.compare(slash, 5, "/msg/") == 0)
    return type.substr(0, slash) + type.substr(slash + 4);
  return type;
}

/// A Chunk record's fields.
struct ChunkFields
{
  std::int64_t start_ns = 0, end_ns = 0;
  std::uint64_t uncompressed_size = 0;
  std::uint32_t uncompressed_crc = 0;
  std::string compression;
  const std::uint8_t* records = nullptr;
  std::uint64_t size = 0;
};

ChunkFields parseChunk(const std::uint8_t* content, std::size_t size, std::uint64_t base)
{
  Cursor cursor(content, size, base);
  ChunkFields chunk;
  chunk.start_ns = static_cast<std::int64_t>(cursor.u64("the chunk's message_start_time"));
  chunk.end_ns = static_cast<std::int64_t>(cursor.u64("the chunk's message_end_time"));
  chunk.uncompressed_size = cursor.u64("the chunk's uncompressed_size");
  chunk.uncompressed_crc = cursor.u32("the chunk's uncompressed_crc");
  chunk.compression = cursor.text("the chunk's compression");
  chunk.size = cursor.u64("the chunk's records length");
  chunk.records = cursor.bytes(chunk.size, "the chunk's records");
  if (chunk.uncompressed_size > kMaxChunkSize) {
    throw FormatError(base + 16, "the chunk claims " + std::to_string(chunk.uncompressed_size) +
                                     " bytes uncompressed, more than the " +
                                     std::to_string(kMaxChunkSize) + " this reader takes");
  }
  return chunk;
}

/// Calls `record(opcode, content, size, offset)` for each record of `size` bytes at `records`
/// (at file byte `base`). Throws FormatError for a record that runs past the end.
template <typename Function>
void walkRecords(const std::uint8_t* records, std::size_t size, std::uint64_t base, Function record)
{
  std::size_t at = 0;
  while (at < size) {
    if (size - at < kRecordPrefixSize)
      throw FormatError(base + at, "a record's opcode and length are cut off");
    Cursor prefix(records + at, kRecordPrefixSize, base + at);
    const std::uint8_t opcode = prefix.u8("the opcode");
    const std::uint64_t length = prefix.u64("the record length");
    if (length > size - at - kRecordPrefixSize) {
      throw FormatError(base + at + 1, "a record of " + std::to_string(length) +
                                           " bytes runs past the end of its " +
                                           std::to_string(size) + " bytes");
    }
    record(opcode, records + at + kRecordPrefixSize, static_cast<std::size_t>(length),
           base + at + kRecordPrefixSize);
    at += kRecordPrefixSize + static_cast<std::size_t>(length);
  }
}

}  // namespace

void File::Span::add(std::int64_t time_ns)
{
  ++count;
  first_ns = std::min(first_ns, time_ns);
  last_ns = std::max(last_ns, time_ns);
}

File::File(const std::string& path, const std::vector<std::string>& topics)
    : path_(path), topics_(topics)
{
  map();
  try {
    const std::uint64_t header_end = readHeader();
    std::uint64_t data_end = size_;
    const bool whole = readFooter(data_end);
    scan(header_end, data_end, whole);
    indexBlocks(whole);
  } catch (const FormatError& error) {
    fail(error.offset(), error.what());
  }
  for (const auto& [id, channel] : channels_) {
    if (channel.wanted && channel.message_encoding != "cdr") {
      throw std::runtime_error("MCAP file '" + path_ + "': topic '" + channel.topic +
                               "' is serialised as '" + channel.message_encoding +
                               "'; only 'cdr' is read");
    }
  }
}

File::~File()
{
  if (data_)
    ::munmap(const_cast<std::uint8_t*>(data_), size_);
}

void File::map()
{
  std::error_code error;
  if (!std::filesystem::is_regular_file(path_, error))
    throw std::runtime_error("no MCAP file '" + path_ + "'");
  const int fd = ::open(path_.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat status;
  if (fd < 0 || ::fstat(fd, &status) != 0) {
    const std::string cause = std::strerror(errno);
    if (fd >= 0)
      ::close(fd);
    throw std::runtime_error("cannot read MCAP file '" + path_ + "': " + cause);
  }
  size_ = static_cast<std::size_t>(status.st_size);
  if (size_ > 0) {
    void* mapped = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (mapped == MAP_FAILED) {
      const std::string cause = std::strerror(errno);
      ::close(fd);
      throw std::runtime_error("cannot map MCAP file '" + path_ + "': " + cause);
    }
    ::madvise(mapped, size_, MADV_SEQUENTIAL);
    data_ = static_cast<const std::uint8_t*>(mapped);
  }
  ::close(fd);
}

std::uint64_t File::readHeader() const
{
  if (size_ < kMagicSize || std::memcmp(data_, kMagic, kMagicSize) != 0)
    throw FormatError(0, "it does not start with MCAP's magic bytes: not an MCAP file");
  if (size_ < kMagicSize + kRecordPrefixSize)
    throw FormatError(kMagicSize, "it is cut off before its header record");
  Cursor prefix(data_ + kMagicSize, kRecordPrefixSize, kMagicSize);
  if (prefix.u8("the header's opcode") != kHeader)
    throw FormatError(kMagicSize, "the first record is not the header record");
  const std::uint64_t length = prefix.u64("the header's length");
  if (length > size_ - kMagicSize - kRecordPrefixSize)
    throw FormatError(kMagicSize + 1, "the header record runs past the end of the file");
  return kMagicSize + kRecordPrefixSize + length;
}

bool File::readFooter(std::uint64_t& data_end)
{
  if (size_ < 2 * kMagicSize + kRecordPrefixSize + kFooterRecordSize ||
      std::memcmp(data_ + size_ - kMagicSize, kMagic, kMagicSize) != 0)
    return false;
  const std::uint64_t footer = size_ - kMagicSize - kFooterRecordSize;
  Cursor cursor(data_ + footer, kFooterRecordSize, footer);
  if (cursor.u8("the footer's opcode") != kFooter || cursor.u64("the footer's length") != 20)
    return false;
  const std::uint64_t summary = cursor.u64("summary_start");
  const std::uint64_t offsets = cursor.u64("summary_offset_start");
  const std::uint32_t crc = cursor.u32("summary_crc");
  if (summary > footer || offsets > footer || (offsets != 0 && offsets < summary) ||
      (summary != 0 && summary < kMagicSize + kRecordPrefixSize))
    throw FormatError(footer + kRecordPrefixSize,
                      "the footer's summary offsets lie outside the file");
  if (summary != 0 && crc != 0) {
    const std::uint64_t covered = footer + kRecordPrefixSize + 16 - summary;
    const std::uint32_t computed = crc32(data_ + summary, covered);
    if (computed != crc) {
      throw FormatError(summary, "the summary's CRC does not match (the footer says " + hex(crc) +
                                     ", its " + std::to_string(covered) + " bytes give " +
                                     hex(computed) + ")");
    }
  }
  data_end = summary != 0 ? summary : footer;
  if (summary != 0) {
    const std::uint64_t end = offsets != 0 ? offsets : footer;
    walkRecords(data_ + summary, end - summary, summary,
                [&](std::uint8_t opcode, const std::uint8_t* content, std::size_t size,
                    std::uint64_t offset) { registerRecord(opcode, content, size, offset); });
  }
  return true;
}

void File::cutAt(std::uint64_t offset, const std::string& cause)
{
  partial_ = "MCAP file '" + path_ + "' has no intact footer (a recording cut off or damaged) " +
             "and is read only up to byte " + std::to_string(offset) + " of " +
             std::to_string(size_) + ": " + cause + "; its messages after that are not used";
}

void File::scan(std::uint64_t from, std::uint64_t limit, bool whole)
{
  bool data_end = false;
  std::uint64_t at = from;
  try {
    while (at < limit && !data_end) {
      if (limit - at < kRecordPrefixSize)
        throw FormatError(at, "a record's opcode and length are cut off");
      Cursor prefix(data_ + at, kRecordPrefixSize, at);
      const std::uint8_t opcode = prefix.u8("the opcode");
      const std::uint64_t length = prefix.u64("the record length");
      if (length > limit - at - kRecordPrefixSize) {
        throw FormatError(
            at + 1, "a record of " + std::to_string(length) + " bytes runs past the end of the " +
                        (whole ? "data section" : "file") + " at byte " + std::to_string(limit));
      }
      if (opcode == 0)
        throw FormatError(at, "opcode 0 is no record (zeroed or overwritten bytes)");
      const std::uint64_t end = at + kRecordPrefixSize + length;
      scanRecord(opcode, data_ + at + kRecordPrefixSize, static_cast<std::size_t>(length), at, end,
                 data_end);
      at = end;
    }
  } catch (const FormatError& error) {
    if (whole)
      throw;
    if (last_chunk_ >= 0)  // its message indexes may be cut: its messages counted from it
      indexed_[static_cast<std::size_t>(last_chunk_)] = false;
    cutAt(at, std::string(error.what()) + " (at byte " + std::to_string(error.offset()) + ")");
    return;
  }
  // A Data End record closes the data section before a summary (without a summary the
  // format lets the footer follow the data directly).
  if (whole && !data_end && limit < size_ - kMagicSize - kFooterRecordSize)
    throw FormatError(at, "the data section ends without its Data End record");
  if (!whole && !data_end)
    cutAt(at, "the file ends without the records that close a recording");
}

void File::scanRecord(std::uint8_t opcode, const std::uint8_t* content, std::size_t size,
                      std::uint64_t offset, std::uint64_t end, bool& data_end)
{
  const std::uint64_t base = offset + kRecordPrefixSize;
  if (opcode == kDataEnd) {
    const std::uint32_t crc = Cursor(content, size, base).u32("data_section_crc");
    const std::uint32_t computed = crc == 0 ? 0 : crc32(data_, offset);
    if (computed != crc) {
      throw FormatError(offset, "the data section's CRC does not match (the Data End record says " +
                                    hex(crc) + ", its " + std::to_string(offset) + " bytes give " +
                                    hex(computed) + ")");
    }
    data_end = true;
  } else if (opcode == kFooter) {
    data_end = true;
  } else if (opcode == kMessage) {
    Cursor cursor(content, size, base);
    const std::uint16_t channel = cursor.u16("a message's channel_id");
    cursor.u32("a message's sequence");
    const auto time_ns = static_cast<std::int64_t>(cursor.u64("a message's log_time"));
    cursor.u64("a message's publish_time");
    if (loose_ < 0) {
      blocks_.push_back({offset, end, false});
      spans_.emplace_back();
      indexed_.push_back(true);
      loose_ = static_cast<int>(blocks_.size()) - 1;
    }
    blocks_[static_cast<std::size_t>(loose_)].end = end;
    spans_[static_cast<std::size_t>(loose_)][channel].add(time_ns);
    last_chunk_ = -1;
  } else if (opcode == kChunk) {
    parseChunk(content, size, base);
    blocks_.push_back({offset, end, true});
    spans_.emplace_back();
    indexed_.push_back(false);
    last_chunk_ = static_cast<int>(blocks_.size()) - 1;
    loose_ = -1;
  } else if (opcode == kMessageIndex && last_chunk_ >= 0) {
    Cursor cursor(content, size, base);
    const std::uint16_t channel = cursor.u16("a message index's channel_id");
    Cursor entries = cursor.block32("a message index's records");
    if (entries.remaining() % 16 != 0)
      throw FormatError(base + 2, "a message index's records are not 16-byte entries");
    File::Span& span = spans_[static_cast<std::size_t>(last_chunk_)][channel];
    while (entries.remaining() > 0) {
      span.add(static_cast<std::int64_t>(entries.u64("a log_time")));
      entries.u64("an offset");
    }
    indexed_[static_cast<std::size_t>(last_chunk_)] = true;
  } else {
    registerRecord(opcode, content, size, offset);
  }
}

void File::registerRecord(std::uint8_t opcode, const std::uint8_t* content, std::size_t size,
                          std::uint64_t offset)
{
  Cursor cursor(content, size, offset);
  if (opcode == kSchema) {
    const std::uint16_t id = cursor.u16("a schema's id");
    std::string name = cursor.text("a schema's name");
    cursor.text("a schema's encoding");
    cursor.block32("a schema's data");
    schemas_[id] = std::move(name);
  } else if (opcode == kChannel) {
    Channel channel;
    channel.id = cursor.u16("a channel's id");
    const std::uint16_t schema = cursor.u16("a channel's schema_id");
    channel.topic = cursor.text("a channel's topic");
    channel.message_encoding = cursor.text("a channel's message_encoding");
    cursor.block32("a channel's metadata");
    if (const auto known = schemas_.find(schema); known != schemas_.end())
      channel.recorded_type = known->second;
    channel.type = ros1TypeName(channel.recorded_type);
    channel.wanted = std::find(topics_.begin(), topics_.end(), channel.topic) != topics_.end();
    channels_.emplace(channel.id, std::move(channel));  // a repeated channel kept as first seen
  }
}

void File::indexBlocks(bool whole)
{
  std::vector<std::uint8_t> buffer;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    if (!blocks_[k].chunk)
      continue;  // messages outside chunks: counted in the scan
    bool known = indexed_[k];
    for (const auto& [channel, span] : spans_[k])
      known = known && channels_.count(channel) > 0;
    if (known)
      continue;
    // Decompressed now for its channels (defined inside it) or its messages' times.
    try {
      const std::uint8_t* records = nullptr;
      std::size_t size = 0;
      chunkRecords(blocks_[k], buffer, records, size);
      spans_[k].clear();
      walkRecords(
          records, size, 0,
          [&](std::uint8_t opcode, const std::uint8_t* content, std::size_t length, std::uint64_t) {
            if (opcode == kMessage && length >= kMessageFieldsSize) {
              Cursor cursor(content, length, blocks_[k].offset);
              const std::uint16_t channel = cursor.u16("channel_id");
              cursor.u32("sequence");
              spans_[k][channel].add(static_cast<std::int64_t>(cursor.u64("log_time")));
            } else {
              registerRecord(opcode, content, length, blocks_[k].offset);
            }
          });
    } catch (const FormatError& error) {
      if (whole)
        throw FormatError(blocks_[k].offset, error.what());
      cutAt(blocks_[k].offset, error.what());
      blocks_.resize(k);
      break;
    }
  }
  std::vector<Block> kept;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    Block block = blocks_[k];
    for (const auto& [id, span] : spans_[k]) {
      const auto channel = channels_.find(id);
      if (channel == channels_.end())
        continue;  // messages of a channel never defined: not read
      channel->second.count += span.count;
      if (channel->second.wanted) {
        block.first_ns = std::min(block.first_ns, span.first_ns);
        block.last_ns = std::max(block.last_ns, span.last_ns);
      }
    }
    if (block.first_ns <= block.last_ns)
      kept.push_back(block);
  }
  blocks_ = std::move(kept);
  spans_.clear();
  indexed_.clear();
}

void File::chunkRecords(const Block& block, std::vector<std::uint8_t>& buffer,
                        const std::uint8_t*& records, std::size_t& size) const
{
  const std::uint64_t base = block.offset + kRecordPrefixSize;
  const ChunkFields chunk = parseChunk(data_ + base, block.end - base, base);
  if (chunk.compression.empty() && chunk.uncompressed_size == chunk.size) {
    records = chunk.records;  // read in place
    size = static_cast<std::size_t>(chunk.size);
  } else {
    try {
      decompressChunk(chunk.compression, chunk.records, static_cast<std::size_t>(chunk.size),
                      chunk.uncompressed_size, buffer);
    } catch (const std::runtime_error& error) {
      throw FormatError(block.offset,
                        std::string("its chunk does not decompress: ") + error.what());
    }
    records = buffer.data();
    size = buffer.size();
  }
  if (chunk.uncompressed_crc != 0) {
    const std::uint32_t computed = crc32(records, size);
    if (computed != chunk.uncompressed_crc) {
      throw FormatError(block.offset, "its chunk's CRC does not match (the chunk says " +
                                          hex(chunk.uncompressed_crc) + ", its " +
                                          std::to_string(size) + " bytes give " + hex(computed) +
                                          ")");
    }
  }
}

void File::read(const Block& block, std::int64_t begin_ns, std::int64_t end_ns,
                std::vector<std::uint8_t>& buffer, std::vector<Entry>& entries) const
{
  entries.clear();
  const std::uint8_t* records = data_ + block.offset;
  std::size_t size = static_cast<std::size_t>(block.end - block.offset);
  try {
    if (block.chunk)
      chunkRecords(block, buffer, records, size);
    const std::uint64_t base = block.chunk ? 0 : block.offset;
    walkRecords(
        records, size, base,
        [&](std::uint8_t opcode, const std::uint8_t* content, std::size_t length, std::uint64_t) {
          if (opcode != kMessage || length < kMessageFieldsSize)
            return;
          Cursor cursor(content, length, 0);
          const auto channel = channels_.find(cursor.u16("channel_id"));
          cursor.u32("sequence");
          const auto time_ns = static_cast<std::int64_t>(cursor.u64("log_time"));
          if (channel == channels_.end() || !channel->second.wanted || time_ns < begin_ns ||
              time_ns > end_ns)
            return;
          entries.push_back({time_ns, content + kMessageFieldsSize, length - kMessageFieldsSize,
                             &channel->second});
        });
  } catch (const FormatError& error) {
    fail(block.chunk ? block.offset : error.offset(), error.what());
  }
  std::stable_sort(entries.begin(), entries.end(),
                   [](const Entry& a, const Entry& b) { return a.time_ns < b.time_ns; });
}

void File::fail(std::uint64_t offset, const std::string& cause) const
{
  throw std::runtime_error("MCAP file '" + path_ + "' is corrupted at byte " +
                           std::to_string(offset) + ": " + cause);
}

}  // namespace mcap
}  // namespace odometry_calibration
