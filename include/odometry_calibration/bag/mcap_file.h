// One MCAP file (mcap_records.h) opened for reading: memory-mapped, its records walked forward
// from the start (the order the format guarantees), its schemas, channels and message blocks
// (chunks, and runs of messages outside chunks) indexed, every CRC the file carries checked.
// A file whose footer and summary are intact is read whole or refused; one without them (cut
// off while recording) is read up to its first damage, and says where and why.
#pragma once

#include <cstddef>
#include <cstdint>
#include <limits>
#include <map>
#include <string>
#include <vector>

namespace odometry_calibration {
namespace mcap {

struct Channel
{
  std::uint16_t id = 0;
  std::string topic;
  std::string message_encoding;  ///< "cdr" for ROS 2
  std::string type;              ///< ROS 1's spelling, "sensor_msgs/LaserScan" ("" no schema)
  std::string recorded_type;     ///< the schema's name, "sensor_msgs/msg/LaserScan"
  bool wanted = false;           ///< one of the topics asked for
  std::uint64_t count = 0;       ///< its messages in the blocks read
};

/// A chunk, or a run of messages outside chunks, and the record times of its messages on the
/// topics asked for (first_ns > last_ns: none).
struct Block
{
  std::uint64_t offset = 0;  ///< the first record's opcode byte
  std::uint64_t end = 0;     ///< the byte after the last record
  bool chunk = false;
  std::int64_t first_ns = std::numeric_limits<std::int64_t>::max();
  std::int64_t last_ns = std::numeric_limits<std::int64_t>::min();
};

/// One message of a block read: its record time, bytes (valid while the block's buffer is) and
/// channel.
struct Entry
{
  std::int64_t time_ns = 0;
  const std::uint8_t* data = nullptr;
  std::size_t size = 0;
  const Channel* channel = nullptr;
};

/// An MCAP file, mapped and indexed. Not copyable.
class File
{
public:
  /// Opens and indexes `path` for the messages on `topics`. Throws std::runtime_error naming
  /// the file and the cause: missing, not MCAP, corrupted (the byte and what is wrong there,
  /// a CRC that does not match), a topic asked for that is not CDR-serialised.
  File(const std::string& path, const std::vector<std::string>& topics);
  ~File();
  File(const File&) = delete;
  File& operator=(const File&) = delete;

  const std::string& path() const { return path_; }
  const std::map<std::uint16_t, Channel>& channels() const { return channels_; }
  /// The blocks holding messages on the topics asked for, in file order.
  const std::vector<Block>& blocks() const { return blocks_; }
  /// Why the file was read only in part, in words naming the file and the byte ("" whole).
  const std::string& partial() const { return partial_; }

  /// `block`'s messages on the topics asked for with record times within [begin_ns, end_ns],
  /// in record-time order (the file's order on ties) into `entries`; `buffer` holds a chunk's
  /// decompressed records. Throws std::runtime_error naming the file, the byte and the cause
  /// for a chunk that does not decompress or whose CRC does not match.
  void read(const Block& block, std::int64_t begin_ns, std::int64_t end_ns,
            std::vector<std::uint8_t>& buffer, std::vector<Entry>& entries) const;

  /// A channel's messages in one block: how many, the first and last record time [ns].
  struct Span
  {
    std::uint64_t count = 0;
    std::int64_t first_ns = std::numeric_limits<std::int64_t>::max();
    std::int64_t last_ns = std::numeric_limits<std::int64_t>::min();
    void add(std::int64_t time_ns);
  };

private:
  /// Maps the file (a missing or unreadable one refused).
  void map();
  /// Checks the leading magic and the header record; returns the byte after the header.
  std::uint64_t readHeader() const;
  /// The footer and its summary when intact: true (their schemas and channels registered),
  /// `data_end` the byte where the data section's records end. Throws FormatError for a
  /// footer that is there but wrong (its CRC, its offsets).
  bool readFooter(std::uint64_t& data_end);
  /// Walks the records of [from, limit): schemas, channels, blocks and message indexes. A
  /// `whole` file's damage throws FormatError; another file's ends the walk (partial_ says so).
  void scan(std::uint64_t from, std::uint64_t limit, bool whole);
  /// One record of the data section at `offset` (opcode, content of `size` bytes).
  void scanRecord(std::uint8_t opcode, const std::uint8_t* content, std::size_t size,
                  std::uint64_t offset, std::uint64_t end, bool& data_end);
  /// A Schema or Channel record registered (others ignored).
  void registerRecord(std::uint8_t opcode, const std::uint8_t* content, std::size_t size,
                      std::uint64_t offset);
  /// Every block's spans (a chunk without message indexes, or with channels not yet seen,
  /// decompressed for them), then the blocks without a message asked for dropped.
  void indexBlocks(bool whole);
  /// A chunk's records: in place when uncompressed, else decompressed into `buffer`; its CRC
  /// checked. Throws FormatError.
  void chunkRecords(const Block& block, std::vector<std::uint8_t>& buffer,
                    const std::uint8_t*& records, std::size_t& size) const;
  /// Refuses the file: std::runtime_error naming it, the byte and the cause.
  [[noreturn]] void fail(std::uint64_t offset, const std::string& cause) const;
  /// Records partial_ for damage at `offset`.
  void cutAt(std::uint64_t offset, const std::string& cause);

  std::string path_;
  std::vector<std::string> topics_;
  const std::uint8_t* data_ = nullptr;
  std::size_t size_ = 0;
  std::map<std::uint16_t, std::string> schemas_;  ///< id -> name
  std::map<std::uint16_t, Channel> channels_;
  std::vector<Block> blocks_;
  /// Per block, its channels' spans; whether they come from message indexes (chunks).
  std::vector<std::map<std::uint16_t, Span>> spans_;
  std::vector<bool> indexed_;
  std::string partial_;
  int loose_ = -1;       ///< the scan's current block of messages outside chunks
  int last_chunk_ = -1;  ///< the chunk the message indexes that follow it belong to
};

}  // namespace mcap
}  // namespace odometry_calibration
