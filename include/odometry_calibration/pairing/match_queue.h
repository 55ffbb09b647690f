// Scan matches run in the background: a queue served in submission order by one worker thread,
// and by whichever thread waits for a result (it runs queued matches itself meanwhile), so two
// cores share the matching. A match's result is a function of its inputs only (matchScans keeps
// no state), so results never depend on which thread ran a match or when.
#pragma once

#include <condition_variable>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <mutex>
#include <thread>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/pairing/lazy_prepared_scan.h"
#include "odometry_calibration/scan/plicp.h"

namespace odometry_calibration {

/// A scan matcher in place of matchScans (same contract: the pose of the current scan in the
/// reference scan's frame from a first guess, with a status and, when options ask, a
/// covariance), so that another implementation can be compared inside the same pairing. Empty:
/// matchScans.
using ScanMatcher =
    std::function<PlicpResult(const PreparedScan& reference, const PreparedScan& current,
                              const Pose2& T_ref_new_guess, const PlicpOptions& options)>;

/// One submitted match: its inputs, then its result.
struct MatchJob
{
  std::shared_ptr<const LazyPreparedScan> reference;  ///< prepared by the job if not yet
  std::shared_ptr<const LazyPreparedScan> current;
  Pose2 T_ref_new_guess;
  PlicpOptions options;
  ScanMatcher matcher;  ///< empty: matchScans
  /// Optional: the same two scans with more rays (the coarse scans are decimated), matched
  /// instead when the match of `reference` and `current` fails.
  std::shared_ptr<const LazyPreparedScan> fine_reference;
  std::shared_ptr<const LazyPreparedScan> fine_current;
  bool fine_rematched = false;      ///< whether the result is the fine scans' match
  PlicpResult result;               ///< valid once done
  double preparation_time_s = 0.0;  ///< spent preparing the scans (if this job did) [s]
  double matching_time_s = 0.0;     ///< spent matching [s]
  std::exception_ptr error;         ///< what matchScans threw, if it did
  bool done = false;
};

/// matchScans (or `matcher` when given) on two lazily prepared scans, adding the time spent
/// preparing them (if this call does) and matching to the two counters [s].
PlicpResult timedMatch(const LazyPreparedScan& reference, const LazyPreparedScan& current,
                       const Pose2& T_ref_new_guess, const PlicpOptions& options,
                       double* preparation_time_s, double* matching_time_s,
                       const ScanMatcher& matcher = nullptr);

/// The queue and its worker. Not copyable (it owns a thread).
class MatchQueue
{
public:
  /// With `background_thread` false (e.g. one core) matches run only inside wait().
  explicit MatchQueue(bool background_thread = std::thread::hardware_concurrency() > 1);
  /// Drops the matches nobody started, waits for the running one, stops the worker.
  ~MatchQueue();
  MatchQueue(const MatchQueue&) = delete;
  MatchQueue& operator=(const MatchQueue&) = delete;

  /// Queues matchScans(reference->get(), current->get(), guess, options) (or `matcher`'s);
  /// when that fails and fine_reference and fine_current are given, their match (same guess and
  /// options) is the result.
  std::shared_ptr<MatchJob> submit(std::shared_ptr<const LazyPreparedScan> reference,
                                   std::shared_ptr<const LazyPreparedScan> current,
                                   const Pose2& T_ref_new_guess, const PlicpOptions& options,
                                   ScanMatcher matcher = nullptr,
                                   std::shared_ptr<const LazyPreparedScan> fine_reference = nullptr,
                                   std::shared_ptr<const LazyPreparedScan> fine_current = nullptr);

  /// The job's result, once it is done; runs queued jobs on the calling thread while it waits.
  /// Rethrows what matchScans threw.
  PlicpResult wait(const std::shared_ptr<MatchJob>& job);

  /// Whether the job is done (wait() then returns at once).
  bool done(const std::shared_ptr<MatchJob>& job);

  /// Runs queued jobs on the calling thread while more than `jobs` wait to start: a caller
  /// that submits faster than the background thread matches shares the matching.
  void runWhileQueuedAbove(std::size_t jobs);

private:
  /// Runs the front job with the lock released; returns with the lock held.
  void runFront(std::unique_lock<std::mutex>& lock);
  void serve();

  std::mutex mutex_;
  std::condition_variable queued_;  ///< a job was queued, or stop
  std::condition_variable done_;    ///< a job finished
  std::deque<std::shared_ptr<MatchJob>> queue_;
  bool stopping_ = false;
  std::thread worker_;
};

}  // namespace odometry_calibration
