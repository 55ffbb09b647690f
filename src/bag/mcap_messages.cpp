#include "odometry_calibration/bag/mcap_messages.h"

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <tuple>

#include "odometry_calibration/bag/cdr_reader.h"
#include "odometry_calibration/bag/mcap_block_loader.h"
#include "odometry_calibration/bag/mcap_file.h"
#include "odometry_calibration/bag/rosbag2_metadata.h"
#include "odometry_calibration/ros/wheel_tick_messages.h"

namespace odometry_calibration {

namespace fs = std::filesystem;

/// A block being read: its messages on the topics asked for, and the next one.
struct McapMessages::Open
{
  std::unique_ptr<mcap::LoadedBlock> loaded;
  std::size_t at = 0;
  const mcap::Entry& entry() const { return loaded->entries[at]; }
  std::size_t file() const { return loaded->file; }
  std::size_t block() const { return loaded->block; }
};

namespace {

bool endsWith(const std::string& text, const std::string& end)
{
  return text.size() >= end.size() && text.compare(text.size() - end.size(), end.size(), end) == 0;
}

/// A bag folder's metadata.yaml, parsed; false when it has none.
bool folderMetadata(const std::string& folder, Rosbag2Metadata& metadata)
{
  const std::string path = (fs::path(folder) / "metadata.yaml").string();
  std::ifstream file(path);
  if (!file)
    return false;
  std::stringstream text;
  text << file.rdbuf();
  metadata = parseRosbag2Metadata(text.str(), path);
  return true;
}

/// A bag folder's MCAP files, its metadata.yaml checked for what this reader reads.
std::vector<std::string> folderFiles(const std::string& folder)
{
  Rosbag2Metadata metadata;
  if (!folderMetadata(folder, metadata))
    throw std::runtime_error("the folder '" + folder + "' has no readable metadata.yaml");
  if (!metadata.compression_mode.empty() || !metadata.compression_format.empty()) {
    throw std::runtime_error("the bag '" + folder + "' is compressed per " +
                             (metadata.compression_mode == "MESSAGE" ? "message" : "file") +
                             " with '" + metadata.compression_format +
                             "'; MCAP bags are read with their chunks compressed (zstd, lz4), "
                             "not compressed by rosbag2 (convert it with 'ros2 bag convert')");
  }
  return rosbag2StorageFiles(folder, metadata);
}

}  // namespace

bool isMcapPath(const std::string& path)
{
  std::error_code error;
  if (!fs::is_directory(path, error))
    return endsWith(path, ".mcap");
  Rosbag2Metadata metadata;
  try {
    return folderMetadata(path, metadata) && metadata.storage_identifier == "mcap";
  } catch (const std::runtime_error&) {
    return false;  // the SQLite reader names the bad metadata.yaml
  }
}

McapMessages::McapMessages(const std::vector<std::string>& paths,
                           const std::vector<std::string>& topics)
    : topics_(topics)
{
  for (const std::string& path : paths) {
    std::error_code error;
    const std::vector<std::string> files =
        fs::is_directory(path, error) ? folderFiles(path) : std::vector<std::string>{path};
    for (const std::string& file : files)
      files_.push_back(std::make_unique<mcap::File>(file, topics));
  }
  for (const auto& file : files_) {
    for (const mcap::Block& block : file->blocks()) {
      first_ns_ = empty() ? block.first_ns : std::min(first_ns_, block.first_ns);
      last_ns_ = empty() ? block.last_ns : std::max(last_ns_, block.last_ns);
    }
  }
  begin_ns_ = first_ns_;
  end_ns_ = last_ns_;
}

McapMessages::~McapMessages()
{
  loader_.reset();  // its thread stopped before the files it reads go
}

void McapMessages::restrictTo(std::int64_t begin_ns, std::int64_t end_ns)
{
  begin_ns_ = begin_ns;
  end_ns_ = end_ns;
}

std::string McapMessages::describeTopics() const
{
  std::vector<const mcap::Channel*> channels;
  for (const auto& file : files_) {
    for (const auto& [id, channel] : file->channels())
      channels.push_back(&channel);
  }
  std::stable_sort(
      channels.begin(), channels.end(),
      [](const mcap::Channel* a, const mcap::Channel* b) { return a->topic < b->topic; });
  std::string text;
  for (const mcap::Channel* channel : channels) {
    text += (text.empty() ? "'" : ", '") + channel->topic + "' (" + channel->recorded_type + ", " +
            std::to_string(channel->count) + " messages)";
  }
  return text.empty() ? "none" : text;
}

std::vector<std::string> McapMessages::missingTopics() const
{
  std::vector<std::string> missing;
  for (const std::string& topic : topics_) {
    bool recorded = false;
    for (const auto& file : files_) {
      for (const auto& [id, channel] : file->channels())
        recorded = recorded || channel.topic == topic;
    }
    if (!recorded && std::find(missing.begin(), missing.end(), topic) == missing.end())
      missing.push_back(topic);
  }
  return missing;
}

std::vector<std::string> McapMessages::partialReads() const
{
  std::vector<std::string> partial;
  for (const auto& file : files_) {
    if (!file->partial().empty())
      partial.push_back(file->partial());
  }
  return partial;
}

double McapMessages::beginTime_s() const
{
  return static_cast<double>(begin_ns_) * 1e-9;
}

double McapMessages::endTime_s() const
{
  return static_cast<double>(end_ns_) * 1e-9;
}

void McapMessages::openPending()
{
  auto earliestOpen = [&] {
    std::int64_t time_ns = std::numeric_limits<std::int64_t>::max();
    for (const auto& open : open_)
      time_ns = std::min(time_ns, open->entry().time_ns);
    return time_ns;
  };
  // A block not opened yet holds no message before its first: those up to the earliest open
  // message are opened, so that the next message is among the open ones.
  while (!pending_.empty() && (open_.empty() || pending_.back().first_ns <= earliestOpen())) {
    pending_.pop_back();
    auto open = std::make_unique<Open>();
    open->loaded = loader_->take();
    if (!open->loaded->entries.empty())
      open_.push_back(std::move(open));
    else
      loader_->recycle(std::move(open->loaded));
  }
}

void McapMessages::startLoading()
{
  std::vector<const mcap::File*> files;
  for (const auto& file : files_)
    files.push_back(file.get());
  std::vector<std::pair<std::size_t, std::size_t>> order;  // as openPending takes them
  for (auto pending = pending_.rbegin(); pending != pending_.rend(); ++pending)
    order.emplace_back(pending->file, pending->block);
  loader_ = std::make_unique<mcap::BlockLoader>(files, order, begin_ns_, end_ns_);
}

bool McapMessages::next()
{
  if (!started_) {
    started_ = true;
    for (std::size_t f = 0; f < files_.size(); ++f) {
      const std::vector<mcap::Block>& blocks = files_[f]->blocks();
      for (std::size_t b = 0; b < blocks.size(); ++b) {
        if (blocks[b].last_ns >= begin_ns_ && blocks[b].first_ns <= end_ns_)
          pending_.push_back({f, b, blocks[b].first_ns});
      }
    }
    // Latest first: the earliest at the back (on a tie, the earlier file and block).
    std::stable_sort(pending_.begin(), pending_.end(), [](const Pending& a, const Pending& b) {
      return a.first_ns != b.first_ns ? a.first_ns > b.first_ns
                                      : std::tie(a.file, a.block) > std::tie(b.file, b.block);
    });
    startLoading();
  } else if (current_ && ++current_->at == current_->loaded->entries.size()) {
    const auto done =
        std::find_if(open_.begin(), open_.end(),
                     [&](const std::unique_ptr<Open>& open) { return open.get() == current_; });
    loader_->recycle(std::move((*done)->loaded));
    open_.erase(done);
  }
  openPending();
  // The earliest current message of the open blocks (the earlier block's on a tie).
  current_ = nullptr;
  for (const auto& open : open_) {
    if (!current_ || open->entry().time_ns < current_->entry().time_ns ||
        (open->entry().time_ns == current_->entry().time_ns &&
         std::make_pair(open->file(), open->block()) <
             std::make_pair(current_->file(), current_->block())))
      current_ = open.get();
  }
  return current_ != nullptr;
}

const std::string& McapMessages::topic() const
{
  return current_->entry().channel->topic;
}

double McapMessages::recordTime_s() const
{
  return static_cast<double>(current_->entry().time_ns) * 1e-9;
}

std::string McapMessages::publisher() const
{
  return "";
}

template <typename M>
bool McapMessages::readAs(M& message)
{
  const mcap::Entry& entry = current_->entry();
  if (entry.channel->type != ros::message_traits::datatype<M>())
    return false;
  try {
    readCdr(entry.data, entry.size, message);
  } catch (const CdrError& error) {
    throw UnreadableMessage("a message on '" + entry.channel->topic + "' recorded at " +
                            std::to_string(recordTime_s()) + " s in '" +
                            files_[current_->file()]->path() + "' is skipped: " + error.what());
  }
  return true;
}

bool McapMessages::read(sensor_msgs::JointState& message)
{
  return readAs(message);
}

bool McapMessages::read(sensor_msgs::LaserScan& message)
{
  return readAs(message);
}

bool McapMessages::read(sensor_msgs::PointCloud2& message)
{
  return readAs(message);
}

bool McapMessages::read(nav_msgs::Odometry& message)
{
  return readAs(message);
}

bool McapMessages::read(geometry_msgs::PoseStamped& message)
{
  return readAs(message);
}

bool McapMessages::read(sensor_msgs::Imu& message)
{
  return readAs(message);
}

bool McapMessages::readWheelTick(const std::string& type, double& value)
{
  return visitWheelTickType(type, [&](auto message) {
    if (!readAs(message))
      return false;
    value = static_cast<double>(message.data);
    return true;
  });
}

}  // namespace odometry_calibration
