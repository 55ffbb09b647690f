// The pairs collected so far and the pairs file that keeps them across crashes (README, "Files"):
// each pair is appended and flushed as it is collected; a restarted session resumes the file;
// another robot's file (other joints) is moved aside, never overwritten; a full or read-only
// disk keeps the pairs in memory and writes them as soon as it can, never half a row.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/data/pair_features.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/session/session_messages.h"

namespace odometry_calibration {

class PairsStore
{
public:
  /// Pairs kept in memory only (`directory` empty), or also in `directory`/pairs.csv: resumed
  /// when `resume` (else moved aside as pairs-<date>-<time>.csv). Throws std::runtime_error when
  /// the file can neither be opened nor moved aside.
  PairsStore(const std::string& directory, const JointLayout& joints, bool resume, SessionLog log);
  ~PairsStore();
  PairsStore(const PairsStore&) = delete;
  PairsStore& operator=(const PairsStore&) = delete;

  /// Keeps `pair` and writes it (and any earlier unwritten ones) to the file.
  void add(const MotionPair& pair);
  /// Writes the pairs the file does not hold yet; on failure says so once and keeps them.
  void writePending();
  /// Sets every pair aside (the file moved to pairs-<date>-<time>.csv when it holds any) and
  /// starts an empty file; returns what was done, in words.
  std::string reset();
  /// The pairs become `pairs` (made again from the same inputs): the file is rewritten
  /// atomically; when it cannot be, it keeps the previous pairs until writePending() manages
  /// the rewrite (every pair counts as unwritten meanwhile).
  void replace(const std::vector<MotionPair>& pairs);

  const std::vector<MotionPair>& pairs() const { return pairs_; }
  std::size_t resumed() const { return resumed_; }
  std::size_t unwritten() const { return unwritten_; }
  /// Why the file cannot be written now (empty: it can, or there is no file).
  const std::string& problem() const { return problem_; }
  /// The pairs file ("" when the pairs are kept in memory only).
  std::string path() const;

private:
  void open(bool resume);
  /// Writes every pair into a new file (atomically) and appends to it from then on; throws.
  void rewrite();
  std::string archive(const std::string& why);
  void say(SessionLogLevel level, const std::string& text) const;

  std::string directory_;
  JointLayout joints_;
  SessionLog log_;
  std::unique_ptr<PairsCsvAppender> appender_;
  std::vector<MotionPair> pairs_;
  std::size_t resumed_ = 0;
  std::size_t unwritten_ = 0;     ///< the last unwritten_ of pairs_ are not in the file yet
  bool rewrite_pending_ = false;  ///< the file holds other pairs than pairs_ (replace())
  std::string problem_;
};

}  // namespace odometry_calibration
