#include "odometry_calibration/bag/mcap_block_loader.h"

#include <system_error>

namespace odometry_calibration {
namespace mcap {

BlockLoader::BlockLoader(std::vector<const File*> files,
                         std::vector<std::pair<std::size_t, std::size_t>> order,
                         std::int64_t begin_ns, std::int64_t end_ns, std::size_t ahead)
    : files_(std::move(files)),
      order_(std::move(order)),
      begin_ns_(begin_ns),
      end_ns_(end_ns),
      ahead_(ahead)
{
  if (order_.empty())
    return;
  try {
    thread_ = std::thread([this] { run(); });
  } catch (const std::system_error&) {
    // No thread: take() loads each block itself.
  }
}

BlockLoader::~BlockLoader()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  changed_.notify_all();
  if (thread_.joinable())
    thread_.join();
}

void BlockLoader::load(std::size_t k, std::unique_ptr<LoadedBlock>& block) const
{
  if (!block)
    block = std::make_unique<LoadedBlock>();
  const auto [file, index] = order_[k];
  block->file = file;
  block->block = index;
  block->error = nullptr;
  try {
    files_[file]->read(files_[file]->blocks()[index], begin_ns_, end_ns_, block->buffer,
                       block->entries);
  } catch (...) {
    block->error = std::current_exception();
  }
}

void BlockLoader::run()
{
  for (std::size_t k = 0; k < order_.size(); ++k) {
    std::unique_ptr<LoadedBlock> block;
    {
      std::unique_lock<std::mutex> lock(mutex_);
      changed_.wait(lock, [&] { return stop_ || ready_.size() < ahead_; });
      if (stop_)
        return;
      if (!spare_.empty()) {
        block = std::move(spare_.back());
        spare_.pop_back();
      }
    }
    load(k, block);
    const bool failed = block->error != nullptr;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      ready_.push_back(std::move(block));
    }
    changed_.notify_all();
    if (failed)
      return;  // the reader stops at this block
  }
}

std::unique_ptr<LoadedBlock> BlockLoader::take()
{
  std::unique_ptr<LoadedBlock> block;
  if (!thread_.joinable()) {
    {
      std::lock_guard<std::mutex> lock(mutex_);
      if (!spare_.empty()) {
        block = std::move(spare_.back());
        spare_.pop_back();
      }
    }
    load(taken_++, block);
  } else {
    std::unique_lock<std::mutex> lock(mutex_);
    changed_.wait(lock, [&] { return !ready_.empty(); });
    block = std::move(ready_.front());
    ready_.pop_front();
    ++taken_;
    lock.unlock();
    changed_.notify_all();
  }
  if (block->error)
    std::rethrow_exception(block->error);
  return block;
}

void BlockLoader::recycle(std::unique_ptr<LoadedBlock> block)
{
  std::lock_guard<std::mutex> lock(mutex_);
  if (spare_.size() < ahead_ + 1)
    spare_.push_back(std::move(block));
}

}  // namespace mcap
}  // namespace odometry_calibration
