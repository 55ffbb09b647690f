// Reads bags directly with the rosbag C++ API (no playback), in timestamp order, and feeds the
// same calibration session as the live node (session/calibration_session.h): the offline half
// of the calibration.
#pragma once

#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/session/joint_calibration_session.h"

namespace odometry_calibration {

/// Progress of a run, for a terminal display.
struct BagProgress
{
  double fraction = 0.0;     ///< of the bags' time span [0, 1]
  std::size_t messages = 0;  ///< messages read so far
  double elapsed_s = 0.0;    ///< wall time so far [s]
};

/// What a run produced, and where the time went.
struct BagRunResult
{
  /// The session the bags were fed to (one CalibrationSession per ego-motion source, fed the
  /// same encoders): each source's pairs (also at the candidate intervals), counts and encoder
  /// history, and calibrate() on them.
  std::shared_ptr<JointCalibrationSession> session;
  /// Source 0's pairs, encoder history (every decoded sample in time order; empty after a
  /// restart: not continuous then) and counts at the end of the run.
  std::vector<MotionPair> pairs;
  std::vector<EncoderSample> encoder_history;
  SessionCounts counts;
  double bag_span_s = 0.0;         ///< time covered by the bags [s]
  double wall_time_s = 0.0;        ///< total wall time [s]
  double read_time_s = 0.0;        ///< reading and deserialising messages (reading thread) [s]
  double conversion_time_s = 0.0;  ///< messages to the core's types (reading thread) [s]
  double filtering_time_s = 0.0;   ///< clouds to scans: band, voxels, binning (reading thread) [s]
  double pairing_time_s = 0.0;     ///< scan preparation, matching, pairing [s]
  /// The files read only in part (an MCAP recording cut off while recording), each in words
  /// naming the file, the byte where reading stopped and why; empty when all were read whole.
  std::vector<std::string> partial_reads;
};

/// Runs the bags once through a JointCalibrationSession (calibrate_bag's: no files, odometry or
/// assistant; every encoder sample kept; result.yaml's `source` the first bag): the joint
/// states and every ego-motion source's messages. Only messages within [start_offset_s,
/// end_offset_s] after the first message are used (end <= 0: to the end). Throws
/// std::runtime_error for a bag that cannot be read (missing, truncated, unindexed: the message
/// says which and what to do), a topic that carries no (usable) message, or two nodes
/// publishing one input (the connections' callerids; the message names both and how to choose:
/// session/input_publishers.h). With `candidate_intervals_s`, each source's session also pairs
/// at those keyframe intervals (for the choice of the fit interval). `fit_jointly`: the
/// session's joint fit of several sources.
BagRunResult runBags(const std::vector<std::string>& bag_paths, const CalibrationConfig& config,
                     double start_offset_s = 0.0, double end_offset_s = 0.0,
                     const std::function<void(const BagProgress&)>& progress = nullptr,
                     const std::vector<double>& candidate_intervals_s = {},
                     const JointFitFunction& fit_jointly = fitSourcesJointly);

/// A source's part of the run in a few lines: the run's data span and speed (reading,
/// conversion, pairing times), a warning per file read only in part, then from the source's
/// `counts`: pairs, scans and keyframes, consecutive-match failures, rejections by reason; then
/// `notes`, what went wrong (CalibrationSession::collectionNotes).
std::string formatBagRunSummary(const BagRunResult& run, const SessionCounts& counts,
                                const std::vector<std::string>& notes);

}  // namespace odometry_calibration
