// Reads bags directly with the rosbag C++ API (no playback), in timestamp order, and feeds the
// same calibration session as the live node (session/calibration_session.h): the offline half
// of DESIGN.md's data flow.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/session/calibration_session.h"

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
  std::vector<MotionPair> pairs;
  /// Every decoded encoder sample, in time order (empty after a restart: the history is not
  /// continuous then), for re-cutting the pairs' windows at another time offset.
  std::vector<EncoderSample> encoder_history;
  CollectorStatistics statistics;
  std::size_t joint_state_messages = 0;
  std::size_t ego_motion_messages = 0;
  std::size_t bad_joint_states = 0;   ///< skipped: missing joints, mismatched arrays, NaN
  std::string first_bad_joint_state;  ///< the first such problem, in words
  /// JointStates from another node than joint_state_publisher (ignored), that node and the
  /// one used (connection callerids).
  std::size_t ignored_joint_states = 0;
  std::string ignored_joint_state_publisher, joint_state_publisher;
  /// Ego-motion messages from another node than ego_motion.publisher (ignored), that node and
  /// the one used (connection callerids).
  std::size_t ignored_ego_messages = 0;
  std::string ignored_ego_publisher, ego_publisher;
  std::string ego_publisher_key = "ego_motion.publisher";  ///< the key choosing it (notes)
  std::string ego_message_type;  ///< "LaserScan", "PointCloud2" or "pose", for messages
  std::size_t bad_clouds = 0;    ///< skipped ego-motion messages (clouds: layout, band, frame)
  std::string first_bad_cloud;   ///< the first such problem, in words
  /// PointCloud2 used without their per-point times (a bad time, a missing configured field)
  std::size_t clouds_without_times = 0;
  std::string first_cloud_time_problem;  ///< why the first of them, in words
  std::vector<std::string> restarts;     ///< time going backwards, in words
  double bag_span_s = 0.0;               ///< time covered by the bags [s]
  double wall_time_s = 0.0;              ///< total wall time [s]
  double read_time_s = 0.0;        ///< reading and deserialising messages (reading thread) [s]
  double conversion_time_s = 0.0;  ///< messages to the core's types (reading thread) [s]
  double filtering_time_s = 0.0;   ///< clouds to scans: band, voxels, binning (reading thread) [s]
  double pairing_time_s = 0.0;     ///< scan preparation, matching, pairing [s]
  /// The session the bags were fed to: its pairs (also at the candidate intervals) and encoder
  /// history, and calibrate() on them.
  std::shared_ptr<CalibrationSession> session;
};

/// Runs the bags through a collector. Only messages within [start_offset_s, end_offset_s]
/// after the first message are used (end <= 0: to the end). Throws std::runtime_error for a
/// bag that cannot be read (missing, truncated, unindexed: the message says which and what to
/// do), a topic that carries no message, or two nodes publishing one input (the connections'
/// callerids; the message names both and how to choose: session/input_publishers.h).
/// With `candidate_intervals_s`, the session also pairs at those keyframe intervals (for the
/// choice of the fit interval).
BagRunResult runBags(const std::vector<std::string>& bag_paths, const CalibrationConfig& config,
                     double start_offset_s = 0.0, double end_offset_s = 0.0,
                     const std::function<void(const BagProgress&)>& progress = nullptr,
                     const std::vector<double>& candidate_intervals_s = {});

/// The run's pairs, encoder history and collector statistics as its session holds them now:
/// after its calibrate() paired the inputs again at the estimated time offset (CalibrateOutcome::
/// offset_pairing), the pairs made at the estimate.
void takeSessionPairs(BagRunResult* run);

/// What went wrong while reading, in words: skipped JointState and PointCloud2 messages (how
/// many, the first reason) and restarts after time went backwards; empty for a clean run.
std::vector<std::string> bagRunNotes(const BagRunResult& run);

/// The run in a few lines: data span and speed (reading, conversion, pairing times), pairs,
/// scans and keyframes, consecutive-match failures, rejections by reason, then bagRunNotes.
std::string formatBagRunSummary(const BagRunResult& run);

}  // namespace odometry_calibration
