#include "odometry_calibration/bag/bag_record_check.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <rosbag/chunked_file.h>
#include <rosbag/exceptions.h>

namespace odometry_calibration {
namespace {

constexpr char kMagic[] = "#ROSBAG V2.0\n";
constexpr char kOldMagic[] = "#ROSBAG V1.2\n";
constexpr std::size_t kMagicBytes = sizeof(kMagic) - 1;
constexpr std::uint8_t kOpMessageData = 0x02;
constexpr std::uint8_t kOpBagHeader = 0x03;
constexpr std::uint8_t kOpIndexData = 0x04;
constexpr std::uint8_t kOpChunk = 0x05;
constexpr std::uint8_t kOpChunkInfo = 0x06;
constexpr std::uint8_t kOpConnection = 0x07;
constexpr std::size_t kWindowBytes = 64 * 1024;               // file bytes read at a time
constexpr std::uint32_t kMaxHeaderBytes = 1024 * 1024;        // record headers hold a few fields
constexpr std::uint32_t kIndexEntryBytes = 12;                // uint32 sec, nsec, offset
constexpr std::uint32_t kMaxCompressedChunkBytes = 1u << 30;  // decompressed

[[noreturn]] void fail(const std::string& what)
{
  throw std::runtime_error(what);
}

/// An open file descriptor, closed on scope exit.
class FileDescriptor
{
public:
  explicit FileDescriptor(const std::string& path) : fd_(::open(path.c_str(), O_RDONLY | O_CLOEXEC))
  {
    if (fd_ < 0)
      fail("cannot open '" + path + "': " + std::strerror(errno));
  }
  ~FileDescriptor() { ::close(fd_); }
  FileDescriptor(const FileDescriptor&) = delete;
  FileDescriptor& operator=(const FileDescriptor&) = delete;
  int get() const { return fd_; }

private:
  int fd_;
};

/// The bytes a walk reads: a region of the file (read through a window, so that large message
/// data is skipped rather than read) or a chunk decompressed into memory.
class ByteSource
{
public:
  ByteSource(int fd, std::uint64_t begin, std::uint64_t size) : fd_(fd), begin_(begin), size_(size)
  {
  }
  explicit ByteSource(std::vector<std::uint8_t> memory)
      : size_(memory.size()), window_(std::move(memory)), in_memory_(true)
  {
  }

  std::uint64_t size() const { return size_; }

  /// The `n` bytes at `offset`, valid until the next call; nullptr unless all are inside.
  const std::uint8_t* at(std::uint64_t offset, std::size_t n)
  {
    if (offset > size_ || n > size_ - offset)
      return nullptr;
    if (in_memory_)
      return window_.data() + offset;
    if (offset < window_offset_ || offset + n > window_offset_ + window_.size()) {
      const std::size_t length = static_cast<std::size_t>(
          std::min<std::uint64_t>(std::max(n, kWindowBytes), size_ - offset));
      window_.resize(length);
      std::size_t done = 0;
      while (done < length) {
        const ssize_t got = ::pread(fd_, window_.data() + done, length - done,
                                    static_cast<off_t>(begin_ + offset + done));
        if (got <= 0) {
          window_.clear();
          return nullptr;
        }
        done += static_cast<std::size_t>(got);
      }
      window_offset_ = offset;
    }
    return window_.data() + (offset - window_offset_);
  }

  std::uint32_t u32(std::uint64_t offset)
  {
    const std::uint8_t* bytes = at(offset, 4);
    std::uint32_t value = 0;
    if (bytes)
      std::memcpy(&value, bytes, 4);  // little-endian, as the format and every ROS 1 host
    return value;
  }

private:
  int fd_ = -1;
  std::uint64_t begin_ = 0;
  std::uint64_t size_ = 0;
  std::vector<std::uint8_t> window_;
  std::uint64_t window_offset_ = 0;
  bool in_memory_ = false;
};

/// A record header's fields by name, the last of a repeated name winning (as in rosbag's
/// ros::Header). A flat list: a header holds a handful of fields, and a 60-minute bag has a
/// quarter of a million records, which a map's node per field made a third of the check's time.
class HeaderFields
{
public:
  void clear() { fields_.clear(); }
  void set(std::string name, std::string value)
  {
    for (auto& [known, known_value] : fields_) {
      if (known == name) {
        known_value = std::move(value);
        return;
      }
    }
    fields_.emplace_back(std::move(name), std::move(value));
  }
  /// The value of `name`, or nullptr.
  const std::string* find(const std::string& name) const
  {
    for (const auto& [known, value] : fields_) {
      if (known == name)
        return &value;
    }
    return nullptr;
  }

private:
  std::vector<std::pair<std::string, std::string>> fields_;
};

/// One record's header fields and where its data lies.
struct Record
{
  HeaderFields fields;
  std::uint8_t op = 0;
  std::uint64_t data_offset = 0;  ///< in its source
  std::uint32_t data_bytes = 0;
  std::uint64_t end() const { return data_offset + data_bytes; }

  /// A fixed-size little-endian field; "" or the problem.
  template <typename T>
  std::string number(const std::string& name, T* value) const
  {
    const std::string* field = fields.find(name);
    if (!field)
      return "has no '" + name + "' field";
    if (field->size() != sizeof(T))
      return "has a '" + name + "' field of " + std::to_string(field->size()) + " bytes, not " +
             std::to_string(sizeof(T));
    std::memcpy(value, field->data(), sizeof(T));
    return "";
  }
};

/// Reads `bytes` as header fields (uint32 length, then "name=value"), as rosbag does for record
/// headers and connection records' data (ros::Header::parse, which takes each length as given):
/// into `fields` when given; "" or what is wrong ("has a <what> field ...").
std::string readFields(const std::uint8_t* bytes, std::size_t size, const std::string& what,
                       HeaderFields* fields)
{
  for (std::size_t position = 0; position < size;) {
    std::uint32_t field_bytes = 0;
    if (size - position < 4)
      return "has a " + what + " field cut off";
    std::memcpy(&field_bytes, bytes + position, 4);
    position += 4;
    if (field_bytes > size - position)
      return "has a " + what + " field of " + std::to_string(field_bytes) + " bytes in a " + what +
             " of " + std::to_string(size);
    const char* field = reinterpret_cast<const char*>(bytes + position);
    position += field_bytes;
    const char* equals = static_cast<const char*>(std::memchr(field, '=', field_bytes));
    if (!equals)
      return "has a " + what + " field without '='";
    if (fields)
      fields->set(std::string(field, equals), std::string(equals + 1, field + field_bytes));
  }
  return "";
}

/// Reads the record at `offset` of `source` into `record`; "" or what is wrong with it.
std::string readRecord(ByteSource& source, std::uint64_t offset, Record& record)
{
  record.fields.clear();  // keeps its memory for the next record
  record.op = 0;
  record.data_offset = 0;
  record.data_bytes = 0;
  if (!source.at(offset, 4))
    return "the header length is cut off";
  const std::uint32_t header_bytes = source.u32(offset);
  if (header_bytes > kMaxHeaderBytes)
    return "claims a header of " + std::to_string(header_bytes) + " bytes";
  const std::uint8_t* header = source.at(offset + 4, header_bytes);
  if (!header)
    return "claims a header of " + std::to_string(header_bytes) + " bytes, " +
           std::to_string(source.size() - std::min(source.size(), offset + 4)) + " are left";
  const std::string fields_problem = readFields(header, header_bytes, "header", &record.fields);
  if (!fields_problem.empty())
    return fields_problem;
  const std::string op_problem = record.number("op", &record.op);
  if (!op_problem.empty())
    return op_problem;
  const std::uint64_t length_offset = offset + 4 + header_bytes;
  if (!source.at(length_offset, 4))
    return "has its data length cut off";
  record.data_bytes = source.u32(length_offset);
  record.data_offset = length_offset + 4;
  if (record.data_offset > source.size() || record.data_bytes > source.size() - record.data_offset)
    return "claims " + std::to_string(record.data_bytes) + " data bytes, " +
           std::to_string(source.size() - record.data_offset) + " are left";
  if (record.op == kOpConnection) {  // its data is the connection's header, parsed as one
    if (record.data_bytes > kMaxHeaderBytes)
      return "holds a connection header of " + std::to_string(record.data_bytes) + " bytes";
    const std::uint8_t* data = source.at(record.data_offset, record.data_bytes);
    if (!data)
      return "cannot be read";
    const std::string problem = readFields(data, record.data_bytes, "connection header", nullptr);
    if (!problem.empty())
      return problem;
  }
  return "";
}

/// Reads the record at `offset`, which must be of `op`; throws "<where>: <problem>" otherwise.
Record expectRecord(ByteSource& source, std::uint64_t offset, std::uint8_t op,
                    const std::string& where)
{
  Record record;
  const std::string problem = readRecord(source, offset, record);
  if (!problem.empty())
    fail(where + " " + problem);
  if (record.op != op)
    fail(where + " is of type 0x" + std::to_string(record.op) + ", not 0x" + std::to_string(op));
  return record;
}

template <typename T>
T expectNumber(const Record& record, const std::string& name, const std::string& where)
{
  T value{};
  const std::string problem = record.number(name, &value);
  if (!problem.empty())
    fail(where + " " + problem);
  return value;
}

/// "<what> at byte <offset>": where in the file a problem is, for messages.
std::string placeOf(const char* what, std::uint64_t offset)
{
  return std::string(what) + " at byte " + std::to_string(offset);
}

/// The chunk's records, decompressed when they are compressed.
ByteSource chunkContents(const FileDescriptor& file, ByteSource& bag, const Record& chunk,
                         const std::string& where)
{
  const std::string* compression = chunk.fields.find("compression");
  if (!compression)
    fail(where + " names no compression");
  const auto size = expectNumber<std::uint32_t>(chunk, "size", where);
  if (*compression == "none") {
    if (size != chunk.data_bytes)
      fail(where + " is uncompressed but claims " + std::to_string(size) + " bytes in " +
           std::to_string(chunk.data_bytes));
    return ByteSource(file.get(), chunk.data_offset, chunk.data_bytes);
  }
  rosbag::CompressionType type = rosbag::compression::Uncompressed;
  if (*compression == "bz2") {
    type = rosbag::compression::BZ2;
  } else if (*compression == "lz4") {
    type = rosbag::compression::LZ4;
  } else {
    fail(where + " has an unknown compression '" + *compression + "'");
  }
  // The decompressed bytes are zeroed first, so that a chunk that decompresses short ends in
  // zero-length records (refused) rather than in whatever the memory held. A chunk is cut at
  // 768 KiB by default; only one message of over 1 GiB would need more.
  if (size > kMaxCompressedChunkBytes)
    fail(where + " claims " + std::to_string(size) + " bytes once decompressed, over 1 GiB");
  const std::uint8_t* packed = bag.at(chunk.data_offset, chunk.data_bytes);
  if (!packed)
    fail(where + " cannot be read");
  std::vector<std::uint8_t> source(packed, packed + chunk.data_bytes);
  std::vector<std::uint8_t> records(size);
  try {
    rosbag::ChunkedFile codec;
    codec.decompress(type, records.data(), size, source.data(), chunk.data_bytes);
  } catch (const rosbag::BagException& error) {
    fail(where + " does not decompress (" + *compression + "): " + error.what());
  }
  return ByteSource(std::move(records));
}

/// Refuses a file that does not start as a bag of format 2.0 (naming the old format 1.2).
void checkMagic(ByteSource& bag)
{
  const std::uint8_t* magic = bag.at(0, kMagicBytes);
  if (magic && std::memcmp(magic, kOldMagic, kMagicBytes) == 0)
    throw UnsupportedBagFormat(
        "it is in the bag format 1.2 of ROS before 2010, which is not read "
        "here; 'rosbag filter OLD.bag NEW.bag True' rewrites it in 2.0");
  if (!magic || std::memcmp(magic, kMagic, kMagicBytes) != 0)
    fail("it does not start as a ROS bag of format 2.0 ('#ROSBAG V2.0')");
}

/// What the bag header says of the index section.
struct BagIndexPosition
{
  std::uint64_t position = 0;  ///< of the first connection record [byte]
  std::uint32_t connections = 0;
  std::uint32_t chunks = 0;
};

/// The bag header record: not encrypted, with an index that was written and lies in the bag.
BagIndexPosition readBagHeader(ByteSource& bag)
{
  const Record header = expectRecord(bag, kMagicBytes, kOpBagHeader, "the bag header record");
  const std::string* encryptor = header.fields.find("encryptor");
  if (encryptor && !encryptor->empty() && *encryptor != "rosbag/NoEncryptor")
    throw UnsupportedBagFormat("it is encrypted (" + *encryptor +
                               "), which is not read here; 'rosbag decrypt' writes a plain copy");
  BagIndexPosition index;
  index.position = expectNumber<std::uint64_t>(header, "index_pos", "the bag header");
  index.connections = expectNumber<std::uint32_t>(header, "conn_count", "the bag header");
  index.chunks = expectNumber<std::uint32_t>(header, "chunk_count", "the bag header");
  if (index.position == 0)
    fail(
        "its index was never written (a recording that was not closed); 'rosbag reindex' "
        "rebuilds it");
  if (index.position < header.end() || index.position >= bag.size())
    fail("the bag header puts the index at byte " + std::to_string(index.position) +
         ", outside the bag's " + std::to_string(bag.size()) + " bytes");
  return index;
}

/// One chunk info record: where the chunk is and how many connections it indexes.
struct ChunkInfo
{
  std::uint64_t position;
  std::uint32_t connections;
};

/// The index section, as rosbag reads it: the connections, then one info per chunk.
std::vector<ChunkInfo> readChunkInfos(ByteSource& bag, const BagIndexPosition& index)
{
  std::uint64_t offset = index.position;
  for (std::uint32_t i = 0; i < index.connections; ++i)
    offset = expectRecord(bag, offset, kOpConnection, placeOf("connection record", offset)).end();
  std::vector<ChunkInfo> infos;
  for (std::uint32_t i = 0; i < index.chunks; ++i) {
    const std::string where = placeOf("chunk info record", offset);
    const Record info = expectRecord(bag, offset, kOpChunkInfo, where);
    infos.push_back({expectNumber<std::uint64_t>(info, "chunk_pos", where),
                     expectNumber<std::uint32_t>(info, "count", where)});
    if (std::uint64_t{infos.back().connections} * 8 != info.data_bytes)  // (conn, count) pairs
      fail(where + " claims " + std::to_string(infos.back().connections) + " connections in " +
           std::to_string(info.data_bytes) + " bytes");
    offset = info.end();
  }
  return infos;
}

/// The start (chunk offset) and op of each record of a chunk, in order of offset.
using RecordStarts = std::vector<std::pair<std::uint64_t, std::uint8_t>>;

/// The chunk's records, which must tile it: the op of the record at each start (chunk
/// offset). Counts them.
RecordStarts chunkRecordStarts(ByteSource& contents, const std::string& where,
                               BagRecordCheckSummary& summary)
{
  RecordStarts starts;
  Record record;
  for (std::uint64_t inner = 0; inner < contents.size(); inner = record.end()) {
    const std::string problem = readRecord(contents, inner, record);
    if (!problem.empty())
      fail(where + ": record at chunk offset " + std::to_string(inner) + " " + problem);
    if (record.op != kOpMessageData && record.op != kOpConnection)
      fail(where + ": record at chunk offset " + std::to_string(inner) + " is of type 0x" +
           std::to_string(record.op) + ", which a chunk does not hold");
    starts.emplace_back(inner, record.op);  // offsets grow: the list stays sorted
    ++summary.records;
  }
  return starts;
}

/// The chunk's index records (one per connection, after the chunk): each entry must point at a
/// message data record's start. Counts the entries.
void checkChunkIndex(ByteSource& bag, const Record& chunk, const ChunkInfo& info,
                     const RecordStarts& starts, const std::string& where,
                     BagRecordCheckSummary& summary)
{
  std::uint64_t index_offset = chunk.end();
  for (std::uint32_t c = 0; c < info.connections; ++c) {
    const std::string index_where = placeOf("index record", index_offset);
    const Record index = expectRecord(bag, index_offset, kOpIndexData, index_where);
    const auto count = expectNumber<std::uint32_t>(index, "count", index_where);
    if (std::uint64_t{count} * kIndexEntryBytes != index.data_bytes)
      fail(index_where + " claims " + std::to_string(count) + " entries in " +
           std::to_string(index.data_bytes) + " bytes");
    for (std::uint32_t e = 0; e < count; ++e) {
      const std::uint32_t entry =
          bag.u32(index.data_offset + std::uint64_t{e} * kIndexEntryBytes + 8);
      const auto start = std::lower_bound(starts.begin(), starts.end(), entry,
                                          [](const std::pair<std::uint64_t, std::uint8_t>& a,
                                             std::uint64_t b) { return a.first < b; });
      if (start == starts.end() || start->first != entry || start->second != kOpMessageData)
        fail(index_where + ": entry " + std::to_string(e) + " points at chunk offset " +
             std::to_string(entry) + ", where no message record of " + where + " starts");
    }
    summary.index_entries += count;
    index_offset = index.end();
  }
}

}  // namespace

BagRecordCheckSummary checkBagRecords(const std::string& path)
{
  BagRecordCheckSummary summary;
  const FileDescriptor file(path);
  struct stat status = {};
  if (::fstat(file.get(), &status) != 0)
    fail("cannot read '" + path + "': " + std::strerror(errno));
  ByteSource bag(file.get(), 0, static_cast<std::uint64_t>(status.st_size));
  checkMagic(bag);
  const std::vector<ChunkInfo> infos = readChunkInfos(bag, readBagHeader(bag));
  for (const ChunkInfo& info : infos) {
    const std::string where = placeOf("chunk", info.position);
    const Record chunk = expectRecord(bag, info.position, kOpChunk, where);
    ByteSource contents = chunkContents(file, bag, chunk, where);
    // Its records must tile it; the index may point only at message data records' starts.
    const auto starts = chunkRecordStarts(contents, where, summary);
    checkChunkIndex(bag, chunk, info, starts, where, summary);
    ++summary.chunks;
  }
  return summary;
}

}  // namespace odometry_calibration
