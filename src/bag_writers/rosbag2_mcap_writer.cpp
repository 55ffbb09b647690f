#include "odometry_calibration/bag_writers/rosbag2_mcap_writer.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/bag/mcap_records.h"
#include "odometry_calibration/common/atomic_file.h"

namespace odometry_calibration {

using mcap::Appender;

Rosbag2McapWriter::Rosbag2McapWriter(const std::string& folder, const std::string& name,
                                     const std::string& compression, std::size_t chunk_size_bytes)
    : folder_(folder),
      file_name_(name + "_0.mcap"),
      path_((std::filesystem::path(folder) / file_name_).string()),
      compression_(compression == "none" ? "" : compression),
      chunk_size_bytes_(chunk_size_bytes)
{
  if (compression_ != "" && compression_ != "zstd" && compression_ != "lz4") {
    throw std::invalid_argument("unknown chunk compression '" + compression +
                                "' (zstd, lz4 or none)");
  }
  file_ = std::fopen(path_.c_str(), "wb");
  if (!file_)
    throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
  std::vector<std::uint8_t> start(mcap::kMagic, mcap::kMagic + mcap::kMagicSize);
  Appender out(start);
  const std::size_t header = out.beginRecord(mcap::kHeader);
  out.text("ros2");
  out.text("odometry_calibration");
  out.finishRecord(header);
  put(start);
  metadata_.version = 5;
  metadata_.storage_identifier = "mcap";
}

Rosbag2McapWriter::~Rosbag2McapWriter()
{
  if (file_)
    std::fclose(file_);
}

void Rosbag2McapWriter::put(const std::vector<std::uint8_t>& bytes)
{
  if (!bytes.empty() && std::fwrite(bytes.data(), 1, bytes.size(), file_) != bytes.size())
    throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
  crc_ = mcap::crc32(bytes.data(), bytes.size(), crc_);
  position_ += bytes.size();
}

void Rosbag2McapWriter::writeSerialized(const std::string& topic, const std::string& type,
                                        std::int64_t time_ns, const std::vector<std::uint8_t>& cdr)
{
  auto known = std::find_if(metadata_.topics.begin(), metadata_.topics.end(),
                            [&](const Rosbag2Topic& t) { return t.name == topic; });
  if (known == metadata_.topics.end()) {
    // The schema and channel go into the chunk before the first message that uses them, and
    // into the summary.
    const auto id = static_cast<std::uint16_t>(metadata_.topics.size() + 1);
    for (std::vector<std::uint8_t>* records : {&chunk_, &schemas_}) {
      Appender out(*records);
      const std::size_t schema = out.beginRecord(mcap::kSchema);
      out.u16(id);
      out.text(type);
      out.text("ros2msg");
      out.u32(0);  // the definition text: not known here
      out.finishRecord(schema);
    }
    for (std::vector<std::uint8_t>* records : {&chunk_, &channels_}) {
      Appender out(*records);
      const std::size_t channel = out.beginRecord(mcap::kChannel);
      out.u16(id);
      out.u16(id);
      out.text(topic);
      out.text("cdr");
      out.u32(0);  // no metadata
      out.finishRecord(channel);
    }
    metadata_.topics.push_back({topic, type, "cdr", 0});
    known = metadata_.topics.end() - 1;
  }
  const auto channel = static_cast<std::uint16_t>(known - metadata_.topics.begin() + 1);
  if (index_.empty()) {
    chunk_start_ns_ = time_ns;
    chunk_end_ns_ = time_ns;
  }
  chunk_start_ns_ = std::min(chunk_start_ns_, time_ns);
  chunk_end_ns_ = std::max(chunk_end_ns_, time_ns);
  index_[channel].emplace_back(static_cast<std::uint64_t>(time_ns), chunk_.size());
  Appender out(chunk_);
  const std::size_t message = out.beginRecord(mcap::kMessage);
  out.u16(channel);
  out.u32(static_cast<std::uint32_t>(known->message_count));
  out.u64(static_cast<std::uint64_t>(time_ns));
  out.u64(static_cast<std::uint64_t>(time_ns));
  out.bytes(cdr.data(), cdr.size());
  out.finishRecord(message);
  ++known->message_count;
  ++channel_counts_[channel];
  if (metadata_.message_count++ == 0 || time_ns < metadata_.starting_time_ns)
    metadata_.starting_time_ns = time_ns;
  last_ns_ = std::max(last_ns_, time_ns);
  if (chunk_.size() >= chunk_size_bytes_)
    flushChunk();
}

void Rosbag2McapWriter::flushChunk()
{
  if (chunk_.empty())
    return;
  const std::uint64_t chunk_start = position_;
  const std::vector<std::uint8_t> compressed = mcap::compressChunk(compression_, chunk_);
  std::vector<std::uint8_t> record;
  Appender out(record);
  const std::size_t start = out.beginRecord(mcap::kChunk);
  out.u64(static_cast<std::uint64_t>(chunk_start_ns_));
  out.u64(static_cast<std::uint64_t>(chunk_end_ns_));
  out.u64(chunk_.size());
  out.u32(mcap::crc32(chunk_.data(), chunk_.size()));
  out.text(compression_);
  out.u64(compressed.size());
  out.bytes(compressed.data(), compressed.size());
  out.finishRecord(start);
  put(record);
  const std::uint64_t chunk_length = record.size();
  // A message index per channel, each channel's offset kept for the chunk index.
  record.clear();
  std::vector<std::pair<std::uint16_t, std::uint64_t>> index_offsets;
  for (const auto& [channel, entries] : index_) {
    index_offsets.emplace_back(channel, position_ + record.size());
    const std::size_t index = out.beginRecord(mcap::kMessageIndex);
    out.u16(channel);
    out.u32(static_cast<std::uint32_t>(entries.size() * 16));
    for (const auto& [time_ns, offset] : entries) {
      out.u64(time_ns);
      out.u64(offset);
    }
    out.finishRecord(index);
  }
  put(record);
  Appender summary(chunk_indexes_);
  const std::size_t chunk_index = summary.beginRecord(mcap::kChunkIndex);
  summary.u64(static_cast<std::uint64_t>(chunk_start_ns_));
  summary.u64(static_cast<std::uint64_t>(chunk_end_ns_));
  summary.u64(chunk_start);
  summary.u64(chunk_length);
  summary.u32(static_cast<std::uint32_t>(index_offsets.size() * 10));
  for (const auto& [channel, offset] : index_offsets) {
    summary.u16(channel);
    summary.u64(offset);
  }
  summary.u64(record.size());
  summary.text(compression_);
  summary.u64(compressed.size());
  summary.u64(chunk_.size());
  summary.finishRecord(chunk_index);
  ++chunk_count_;
  chunk_.clear();
  index_.clear();
}

std::uint64_t Rosbag2McapWriter::writeSummary()
{
  std::vector<std::uint8_t> statistics;
  Appender out(statistics);
  const std::size_t record = out.beginRecord(mcap::kStatistics);
  out.u64(metadata_.message_count);
  out.u16(static_cast<std::uint16_t>(metadata_.topics.size()));
  out.u32(static_cast<std::uint32_t>(metadata_.topics.size()));
  out.u32(0);  // attachments
  out.u32(0);  // metadata
  out.u32(chunk_count_);
  out.u64(metadata_.message_count > 0 ? static_cast<std::uint64_t>(metadata_.starting_time_ns) : 0);
  out.u64(metadata_.message_count > 0 ? static_cast<std::uint64_t>(last_ns_) : 0);
  out.u32(static_cast<std::uint32_t>(channel_counts_.size() * 10));
  for (const auto& [channel, count] : channel_counts_) {
    out.u16(channel);
    out.u64(count);
  }
  out.finishRecord(record);
  // The groups in order, each followed by its place for the summary offsets.
  std::vector<std::uint8_t> offsets;
  Appender offset(offsets);
  const std::pair<mcap::Opcode, const std::vector<std::uint8_t>*> groups[] = {
      {mcap::kSchema, &schemas_},
      {mcap::kChannel, &channels_},
      {mcap::kStatistics, &statistics},
      {mcap::kChunkIndex, &chunk_indexes_}};
  for (const auto& [opcode, bytes] : groups) {
    if (bytes->empty())
      continue;
    const std::size_t entry = offset.beginRecord(mcap::kSummaryOffset);
    offset.u8(opcode);
    offset.u64(position_);
    offset.u64(bytes->size());
    offset.finishRecord(entry);
    put(*bytes);
  }
  const std::uint64_t offsets_start = position_;
  put(offsets);
  return offsets_start;
}

void Rosbag2McapWriter::close()
{
  flushChunk();
  std::vector<std::uint8_t> data_end;
  Appender end(data_end);
  const std::size_t record = end.beginRecord(mcap::kDataEnd);
  end.u32(crc_);
  end.finishRecord(record);
  put(data_end);
  const std::uint64_t summary_start = position_;
  crc_ = 0;  // from here: the summary's CRC
  const std::uint64_t offsets_start = writeSummary();
  std::vector<std::uint8_t> footer;
  Appender out(footer);
  out.u8(mcap::kFooter);
  out.u64(20);  // summary_start, summary_offset_start, summary_crc
  out.u64(summary_start);
  out.u64(offsets_start);
  const std::uint32_t summary_crc = mcap::crc32(footer.data(), footer.size(), crc_);
  Appender(footer).u32(summary_crc);
  footer.insert(footer.end(), mcap::kMagic, mcap::kMagic + mcap::kMagicSize);
  put(footer);
  std::FILE* file = file_;
  file_ = nullptr;
  if (std::fclose(file) != 0)
    throw std::runtime_error("cannot write '" + path_ + "': " + std::strerror(errno));
  metadata_.duration_ns = metadata_.message_count > 0 ? last_ns_ - metadata_.starting_time_ns : 0;
  metadata_.relative_file_paths = {file_name_};
  writeFileAtomically((std::filesystem::path(folder_) / "metadata.yaml").string(),
                      rosbag2MetadataYaml(metadata_));
}

}  // namespace odometry_calibration
