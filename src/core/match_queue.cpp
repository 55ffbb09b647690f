#include "odometry_calibration/pipeline/match_queue.h"

#include <utility>

namespace odometry_calibration {

MatchQueue::MatchQueue(bool background_thread)
{
  if (background_thread)
    worker_ = std::thread([this] { serve(); });
}

MatchQueue::~MatchQueue()
{
  {
    std::lock_guard<std::mutex> lock(mutex_);
    stopping_ = true;
    queue_.clear();
  }
  queued_.notify_all();
  if (worker_.joinable())
    worker_.join();
}

std::shared_ptr<MatchJob> MatchQueue::submit(std::shared_ptr<const LazyPreparedScan> reference,
                                             std::shared_ptr<const LazyPreparedScan> current,
                                             const Pose2& T_ref_new_guess,
                                             const PlicpOptions& options)
{
  auto job = std::make_shared<MatchJob>();
  job->reference = std::move(reference);
  job->current = std::move(current);
  job->T_ref_new_guess = T_ref_new_guess;
  job->options = options;
  {
    std::lock_guard<std::mutex> lock(mutex_);
    queue_.push_back(job);
  }
  queued_.notify_one();
  return job;
}

void MatchQueue::runFront(std::unique_lock<std::mutex>& lock)
{
  const std::shared_ptr<MatchJob> job = std::move(queue_.front());
  queue_.pop_front();
  lock.unlock();
  try {
    job->result =
        matchScans(job->reference->get(), job->current->get(), job->T_ref_new_guess, job->options);
  } catch (...) {
    job->error = std::current_exception();
  }
  job->reference.reset();  // the scans are not needed any more
  job->current.reset();
  lock.lock();
  job->done = true;
  done_.notify_all();
}

void MatchQueue::serve()
{
  std::unique_lock<std::mutex> lock(mutex_);
  while (true) {
    queued_.wait(lock, [this] { return stopping_ || !queue_.empty(); });
    if (stopping_)
      return;
    runFront(lock);
  }
}

PlicpResult MatchQueue::wait(const std::shared_ptr<MatchJob>& job)
{
  std::unique_lock<std::mutex> lock(mutex_);
  while (!job->done) {
    if (!queue_.empty())
      runFront(lock);  // help: queued jobs are all needed sooner or later
    else
      done_.wait(lock);
  }
  if (job->error)
    std::rethrow_exception(job->error);
  return job->result;
}

}  // namespace odometry_calibration
