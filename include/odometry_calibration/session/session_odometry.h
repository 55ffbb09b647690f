// The session's odometry (README, "Topics": ~odom and the three paths): the encoders integrated
// through the nominal robot and through the active model (calibration/odometry_integrator.h,
// windows of one keyframe interval chained on SE(2) with their covariance), stamped in the
// laser's clock (encoder time - time offset), and the chain of scan-matched displacements. After
// a fit the corrected odometry is integrated again over the kept samples with the new model.
#pragma once

#include <cstddef>
#include <deque>
#include <memory>
#include <optional>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// A pose of a path, in the odometry frame, at a laser-clock stamp.
struct StampedPose2
{
  double stamp_s = 0.0;  ///< laser clock [s]
  Pose2 pose;            ///< T_odom_base (or T_odom_sensor when no sensor pose is known)
};

/// One corrected odometry output (what ~odom carries).
struct OdometryState
{
  double stamp_s = 0.0;  ///< laser clock: encoder stamp - time offset [s]
  Pose2 pose;            ///< T_odom_base, or T_odom_sensor when !tracks_base
  bool tracks_base = true;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();  ///< of (x, y, yaw) [m^2, rad^2]
  Eigen::Vector3d velocity = Eigen::Vector3d::Zero();    ///< (vx, vy, omega) [m/s, rad/s]
  /// One window's covariance divided by its length squared (the velocity's spread).
  Eigen::Matrix3d velocity_covariance = Eigen::Matrix3d::Zero();
  /// Changes when the pose may jump from the previous state's: a restart, another model's
  /// odometry taking over (SessionOdometry::swapCorrected).
  std::size_t continuity = 0;
};

/// The paths for rviz.
struct OdometryPaths
{
  std::vector<StampedPose2> nominal, corrected, scan_matched;
};

struct SessionOdometryOptions
{
  double path_spacing_s = 0.1;  ///< time between the paths' poses [s]
  int path_max_poses = 20000;   ///< longest path kept (oldest poses dropped)
};

/// What integrating the kept samples again needs (copied, so that it runs without the lock).
struct OdometryReplayInput
{
  std::vector<EncoderSample> samples;  ///< laser clock
  Pose2 start;                         ///< the corrected path's pose at the first sample
  std::size_t generation = 0;          ///< restarts so far
};

/// The active model's odometry, ready to replace the current one (SessionOdometry::replay).
struct OdometryReplay
{
  std::unique_ptr<OdometryIntegrator> integrator;
  std::vector<StampedPose2> path;
  std::size_t generation = 0;
};

/// Not thread-safe: the session calls it with its lock held.
class SessionOdometry
{
public:
  SessionOdometry(const std::vector<EncoderChannelOptions>& channels,
                  const SessionOdometryOptions& options);
  /// A copy of `other` with integrators of its own: kept aside, it can take over again as it
  /// was (a refused adoption's odometry, calibration_session.h).
  SessionOdometry(const SessionOdometry& other);
  SessionOdometry& operator=(const SessionOdometry&) = delete;

  /// The nominal robot's integrator (none without a prior model).
  void setNominal(std::unique_ptr<OdometryIntegrator> nominal);
  /// The active model's integrator (none: no corrected odometry).
  void setCorrected(std::unique_ptr<OdometryIntegrator> corrected);

  /// Integrates an accepted encoder reading (raw units, signs applied) at encoder time
  /// `encoder_stamp_s`; returns the corrected odometry (none without an active model, or for a
  /// repeated stamp). Throws what the model's prediction throws.
  std::optional<OdometryState> add(double encoder_stamp_s, const Eigen::VectorXd& raw,
                                   double time_offset_s);
  /// Starts again from the origin (time went backwards, a reset, a new time offset).
  void restart();
  /// Chains a pair's matched displacement onto the scan-matched path (after a gap, from the
  /// corrected odometry's sensor pose at the pair's start).
  void addScanMatched(const MotionPair& pair);

  /// The kept samples, for replay().
  OdometryReplayInput replayInput() const;
  /// The corrected odometry integrated again over `input` with `integrator`; throws what the
  /// model's prediction throws.
  static OdometryReplay replay(const OdometryReplayInput& input,
                               std::unique_ptr<OdometryIntegrator> integrator);
  /// Adds what arrived since replayInput to `replay` (started afresh when the odometry
  /// restarted meanwhile), then exchanges it with the corrected odometry and its path: the
  /// replay becomes the corrected odometry, `replay` holds the one it replaced (swapped back,
  /// that one takes what arrived meanwhile). Throws what the model's prediction throws, before
  /// anything is exchanged.
  void swapCorrected(OdometryReplay* replay);

  /// The paths; the scan-matched sensor poses drawn through `T_base_sensor` (inverted).
  OdometryPaths paths(const Pose2& T_base_sensor) const;

private:
  void addToPaths(const EncoderSample& sample, const Pose2& pose);
  void keepRecentSensorPose(double stamp_s, const Pose2& T_odom_sensor);

  // A member added below must be copied by the copy constructor too (session_odometry.cpp):
  // a rolled-back adoption puts the copy back as the session's odometry.

  SessionOdometryOptions options_;
  EncoderDecoder decoder_;
  double last_encoder_stamp_s_ = -1e300;
  double last_path_stamp_s_ = -1e300;
  std::unique_ptr<OdometryIntegrator> nominal_, corrected_;
  std::deque<StampedPose2> nominal_path_, corrected_path_;
  /// Encoder samples (laser clock) at the corrected path's poses, to redraw it after a fit, and
  /// the path's pose at the first of them.
  std::deque<EncoderSample> path_samples_;
  Pose2 path_samples_start_;
  /// Recent corrected sensor poses, to place the scan-matched path after a gap.
  std::vector<std::pair<double, Pose2>> recent_sensor_poses_;
  std::deque<StampedPose2> scan_matched_sensor_poses_;
  std::optional<double> scan_matched_end_s_;
  std::size_t generation_ = 0;  ///< restarts so far
  std::size_t continuity_ = 0;  ///< restarts and swaps so far (OdometryState::continuity)
};

}  // namespace odometry_calibration
