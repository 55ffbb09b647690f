// The MCAP blocks a reader will open next (mcap_file.h), loaded on a thread of their own in the
// order the reader takes them, a few ahead: each chunk decompressed, its CRC checked and its
// messages on the topics asked for listed, while the reader deserialises the blocks before it.
// A block that fails carries its error to the reader, which throws it when it gets there.
#pragma once

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <deque>
#include <exception>
#include <memory>
#include <mutex>
#include <thread>
#include <utility>
#include <vector>

#include "odometry_calibration/bag/mcap_file.h"

namespace odometry_calibration {
namespace mcap {

/// One block loaded: which it is, its decompressed records and its messages (File::read).
struct LoadedBlock
{
  std::size_t file = 0, block = 0;
  std::vector<std::uint8_t> buffer;
  std::vector<Entry> entries;
  std::exception_ptr error;  ///< why it could not be loaded (null: loaded)
};

/// Loads blocks ahead of their reader. Not copyable; one reader.
class BlockLoader
{
public:
  /// Starts loading the blocks `order` (file index in `files`, block index in its blocks(), in
  /// the order take() will be called), their messages within [begin_ns, end_ns], at most
  /// `ahead` blocks ahead of take(). Without a thread to run on, take() loads each itself.
  BlockLoader(std::vector<const File*> files,
              std::vector<std::pair<std::size_t, std::size_t>> order, std::int64_t begin_ns,
              std::int64_t end_ns, std::size_t ahead = 4);
  ~BlockLoader();
  BlockLoader(const BlockLoader&) = delete;
  BlockLoader& operator=(const BlockLoader&) = delete;

  /// The next block of the order (waiting for it). Throws its error (File::read's).
  std::unique_ptr<LoadedBlock> take();
  /// Hands a block the reader is done with back, so that its buffers are reused.
  void recycle(std::unique_ptr<LoadedBlock> block);

private:
  void run();
  /// Loads block `k` of the order into `block` (a recycled one, or new).
  void load(std::size_t k, std::unique_ptr<LoadedBlock>& block) const;

  std::vector<const File*> files_;
  std::vector<std::pair<std::size_t, std::size_t>> order_;
  std::int64_t begin_ns_, end_ns_;
  std::size_t ahead_;
  std::size_t taken_ = 0;  ///< blocks take() has returned
  std::mutex mutex_;
  std::condition_variable changed_;
  std::deque<std::unique_ptr<LoadedBlock>> ready_;
  std::vector<std::unique_ptr<LoadedBlock>> spare_;
  bool stop_ = false;
  std::thread thread_;
};

}  // namespace mcap
}  // namespace odometry_calibration
