// The pairs file: one keyframe pair per line, so that pairs from any source (the live node,
// the bag tool, the simulator, another tool) can be fitted and compared, and so that a
// collection survives a crash (rows are appended and flushed as they come).
//
// Format (text, comma-separated, '#' comment lines):
//   # odometry_calibration pairs v1
//   # joints: <name>:<incremental|absolute> <name>:<incremental|absolute> ...
//   start_stamp_s,end_stamp_s,x_m,y_m,theta_rad,cov_xx,cov_xy,cov_xtheta,cov_yy,cov_ytheta,
//     cov_thetatheta,samples                                  (the column header, one line)
//   <row per pair>
// x_m, y_m, theta_rad: the measured sensor displacement s_hat (end pose in the start frame);
// cov_*: its covariance (upper triangle) [m^2, m rad, rad^2]; samples: the decoded encoder
// samples of the interval, ';'-separated, each "<stamp_s> <value joint 1> <value joint 2> ..."
// (cumulative counts of incremental joints, readings of absolute ones).
#pragma once

#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/data/pair_features.h"

namespace odometry_calibration {

/// A pairs file's content.
struct PairsFile
{
  JointLayout joints;
  std::vector<MotionPair> pairs;
};

/// The header lines (comment, joints, column names), each ending in '\n'.
std::string pairsCsvHeader(const JointLayout& joints);

/// One row for a pair, ending in '\n' (doubles printed to full precision).
std::string pairsCsvRow(const MotionPair& pair);

/// Parses a pairs file. Throws std::runtime_error naming `source`, the line and what was
/// expected (bad numbers, a sample with the wrong number of values, a missing joints line).
PairsFile parsePairsCsv(std::istream& input, const std::string& source);

/// Reads a pairs file from disk.
PairsFile readPairsCsv(const std::string& path);

/// Writes a whole pairs file atomically.
void writePairsCsv(const std::string& path, const PairsFile& file);

/// The pairs of several files, in order, which must share their joints (names and order): the
/// joints are the first file's. Throws std::invalid_argument "'<path>' has other joints than the
/// first file", or readPairsCsv's errors. No path gives an empty PairsFile.
PairsFile readPairsCsvFiles(const std::vector<std::string>& paths);

/// Pairs to train on and pairs to test on, with the same joints.
struct TrainTestPairs
{
  PairsFile training;
  PairsFile testing;
};

/// readPairsCsvFiles of each list; throws std::invalid_argument "the test pairs have other
/// joints than the training pairs" unless both have the same joints.
TrainTestPairs readTrainTestPairsCsv(const std::vector<std::string>& training_paths,
                                     const std::vector<std::string>& testing_paths);

/// Appends pairs to a file as they are collected, flushing each row to disk, so that a crash
/// loses at most the row being written. An existing file is continued after checking that its
/// joints match (and its rows are loaded: `existing()`).
class PairsCsvAppender
{
public:
  /// Opens or creates `path`. Throws std::runtime_error if the file cannot be written or holds
  /// other joints. A last line cut off by a crash is dropped (with `dropped_partial_line()`).
  PairsCsvAppender(const std::string& path, const JointLayout& joints);
  ~PairsCsvAppender();
  PairsCsvAppender(const PairsCsvAppender&) = delete;
  PairsCsvAppender& operator=(const PairsCsvAppender&) = delete;

  /// Appends one pair and flushes it to disk. Throws std::runtime_error (naming the file and
  /// the system error) when it cannot: the file is then cut back to its previous end, so it
  /// never keeps half a row, and the same pair can be appended again later.
  void append(const MotionPair& pair);

  /// Pairs that were in the file when it was opened.
  const std::vector<MotionPair>& existing() const { return existing_; }
  bool dropped_partial_line() const { return dropped_partial_line_; }

private:
  /// Writes `text` at the end, all or nothing (see append()).
  void appendText(const std::string& text);

  std::string path_;
  int fd_ = -1;
  std::vector<MotionPair> existing_;
  bool dropped_partial_line_ = false;
};

}  // namespace odometry_calibration
