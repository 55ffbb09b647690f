#include "odometry_calibration/pairing/match_queue.h"

#include <chrono>
#include <utility>

namespace odometry_calibration {

PlicpResult timedMatch(const LazyPreparedScan& reference, const LazyPreparedScan& current,
                       const Pose2& T_ref_new_guess, const PlicpOptions& options,
                       double* preparation_time_s, double* matching_time_s,
                       const ScanMatcher& matcher)
{
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const PreparedScan& prepared_reference = reference.get();
  const PreparedScan& prepared_current = current.get();
  const auto prepared = Clock::now();
  PlicpResult result =
      matcher ? matcher(prepared_reference, prepared_current, T_ref_new_guess, options)
              : matchScans(prepared_reference, prepared_current, T_ref_new_guess, options);
  *preparation_time_s += std::chrono::duration<double>(prepared - start).count();
  *matching_time_s += std::chrono::duration<double>(Clock::now() - prepared).count();
  return result;
}

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
                                             const PlicpOptions& options, ScanMatcher matcher,
                                             std::shared_ptr<const LazyPreparedScan> fine_reference,
                                             std::shared_ptr<const LazyPreparedScan> fine_current)
{
  auto job = std::make_shared<MatchJob>();
  job->reference = std::move(reference);
  job->current = std::move(current);
  if (fine_reference && fine_current) {
    job->fine_reference = std::move(fine_reference);
    job->fine_current = std::move(fine_current);
  }
  job->T_ref_new_guess = T_ref_new_guess;
  job->options = options;
  job->matcher = std::move(matcher);
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
    job->result = timedMatch(*job->reference, *job->current, job->T_ref_new_guess, job->options,
                             &job->preparation_time_s, &job->matching_time_s, job->matcher);
    if (!job->result.valid() && job->fine_reference) {
      job->fine_rematched = true;
      job->result =
          timedMatch(*job->fine_reference, *job->fine_current, job->T_ref_new_guess, job->options,
                     &job->preparation_time_s, &job->matching_time_s, job->matcher);
    }
  } catch (...) {
    job->error = std::current_exception();
  }
  job->reference.reset();  // the scans are not needed any more
  job->current.reset();
  job->fine_reference.reset();
  job->fine_current.reset();
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

bool MatchQueue::done(const std::shared_ptr<MatchJob>& job)
{
  std::lock_guard<std::mutex> lock(mutex_);
  return job->done;
}

void MatchQueue::runWhileQueuedAbove(std::size_t jobs)
{
  std::unique_lock<std::mutex> lock(mutex_);
  while (queue_.size() > jobs)
    runFront(lock);
}

}  // namespace odometry_calibration
