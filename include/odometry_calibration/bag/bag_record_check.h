// Checks the record structure of a ROS bag (format 2.0) before rosbag reads its messages.
//
// rosbag trusts the lengths written in a bag: a message record's data length is copied or
// deserialised from the chunk without a check against the chunk's size, and an index entry's
// offset is read as a record header wherever it points. One flipped byte in a chunk therefore
// makes rosbag read outside its buffer (a crash, or worse, a silently wrong message). This
// check walks what rosbag will walk, with every length bounded by what holds it:
//
//   file:  "#ROSBAG V2.0\n", bag header record (op 0x03: index_pos, conn_count, chunk_count),
//          chunk records (op 0x05: compression, size) each followed by its index data records
//          (op 0x04: ver, conn, count; data = count x (uint32 sec, uint32 nsec, uint32 offset)),
//          then at index_pos the connection (op 0x07) and chunk info (op 0x06) records.
//   record: uint32 header_len, header fields (uint32 field_len, "name=value"), uint32 data_len,
//           data (ROS wiki, "Bags/Format/2.0").
//
// Every chunk the chunk infos name is decompressed (none, bz2, lz4: rosbag's own codecs) and
// its records must tile it exactly; every index entry must point at the start of a message
// data record (op 0x02) of its chunk. Then each message rosbag hands out lies inside its chunk,
// and ros_conversions::wireLengthsFit can bound its arrays before it is deserialised.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace odometry_calibration {

/// A bag of a kind the check cannot walk (format 1.2, encrypted): not corrupted, refused with the
/// way to convert it.
struct UnsupportedBagFormat : std::runtime_error
{
  using std::runtime_error::runtime_error;
};

/// What the check looked at, for a summary.
struct BagRecordCheckSummary
{
  std::uint64_t chunks = 0;         ///< chunks walked
  std::uint64_t records = 0;        ///< records inside them
  std::uint64_t index_entries = 0;  ///< index entries checked
};

/// Walks the bag at `path` as above. Throws std::runtime_error naming the first problem and
/// the byte where it is ("chunk at byte 4117: record at chunk offset 880 claims 4294967040
/// data bytes, 600 are left") when the bag is not well formed; a bag rosbag would refuse for a
/// missing or unreadable index (truncated, never closed) throws too. Bags this check cannot walk,
/// format 1.2 (ROS before 2010) and encrypted ones, throw UnsupportedBagFormat (the message says
/// how to convert them). Reads record headers only for uncompressed chunks; a compressed chunk is
/// decompressed once more.
BagRecordCheckSummary checkBagRecords(const std::string& path);

}  // namespace odometry_calibration
