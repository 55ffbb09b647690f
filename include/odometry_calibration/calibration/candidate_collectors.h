// Pairs at several keyframe intervals from one live stream, for the node's choice of the fit
// interval (calibration/fit_interval.h): one PairCollector per candidate interval, each fed the
// same encoder readings, scans and sensor poses as the node's own collector, keeping only their
// pairs. Costs one more set of scan matches per candidate (the node's CPU, see README).
#pragma once

#include <memory>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/calibration/fit_interval.h"
#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

class CandidateCollectors
{
public:
  /// One collector per interval of `intervals_s` (each > 0), with `options` otherwise.
  /// Throws std::invalid_argument for invalid options or intervals.
  CandidateCollectors(const std::vector<EncoderChannelOptions>& channels,
                      const CollectorOptions& options, const MotionPredictor& predictor,
                      const std::vector<double>& intervals_s);
  ~CandidateCollectors();
  CandidateCollectors(const CandidateCollectors&) = delete;
  CandidateCollectors& operator=(const CandidateCollectors&) = delete;

  /// The same inputs as PairCollector's; bad readings throw as there (check them first with the
  /// node's own collector, which reports them).
  void addEncoders(double stamp_s, const Eigen::VectorXd& raw);
  void addScan(double stamp_s, const Scan& scan);
  void addSensorPose(double stamp_s, const Pose2& T_world_sensor,
                     const Eigen::Matrix3d& covariance);
  /// Pairs waiting scans now (end of a bag).
  void flush();
  /// Forgets every pair and keyframe (the node's ~reset).
  void clear();

  /// The pairs of each candidate so far, in the candidates' order.
  std::vector<IntervalPairs> pairs() const;

private:
  struct Candidate;
  void keep(Candidate& candidate, const std::vector<CollectorEvent>& events);

  std::vector<EncoderChannelOptions> channels_;
  CollectorOptions options_;
  MotionPredictor predictor_;
  std::vector<std::unique_ptr<Candidate>> candidates_;
};

}  // namespace odometry_calibration
