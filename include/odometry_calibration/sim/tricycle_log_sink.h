// Writes a simulated tricycle run in the tricycle dataset's text format (the format of
// shared/data/tricycle/dataset.txt), so that calibrate_tricycle can be run on data the
// project generates itself, with the truth known.
#pragma once

#include <memory>
#include <string>

#include "odometry_calibration/models/tricycle_calibration.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace sim {

/// Collects one row per encoder sample: the JointState's ticks (steering absolute, traction
/// incremental) with the tracker's sensor pose of the same instant, and the robot's own
/// odometry integrated with the `nominal` parameters (the format's model_pose). The header
/// carries the nominal parameters as the calibration's initial guess.
class TricycleLogSink : public SimulationSink
{
public:
  /// `steering_ticks_per_rev` / `traction_ticks_per_rev` go into the header's encoder ranges.
  /// Requires encoder output in ticks. Throws std::invalid_argument otherwise.
  TricycleLogSink(const Scenario& scenario, const TricycleParameters& nominal,
                  double steering_ticks_per_rev, double traction_ticks_per_rev);

  void onJointState(const JointStateSample& sample) override;
  void onScan(const ScanSample& /*sample*/) override {}
  void onTruth(const TruthSample& /*sample*/) override {}
  void onTracker(const TrackerSample& sample) override;

  /// The whole log as text.
  const std::string& text() const { return text_; }
  std::size_t rows() const { return rows_; }

private:
  TricycleParameters nominal_;
  TricycleEncoderLayout layout_;
  double start_time_s_;
  std::string text_;
  std::size_t rows_ = 0;
  bool has_joint_sample_ = false;
  JointStateSample last_joint_sample_;
  EncoderSample previous_decoded_;
  Pose2 T_odom_base_nominal_;
  double traction_cumulative_ = 0.0;
  double previous_traction_raw_ = 0.0;
};

/// Whether a scenario can be written as a tricycle log: a tricycle robot with the tracker enabled.
bool canWriteTricycleLog(const Scenario& scenario);

/// A sink for a scenario that canWriteTricycleLog (std::invalid_argument otherwise), with the
/// robot's true tick counts and, in its header, the real log's nominal values (Ksteer 0.1,
/// Ktraction 0.0106141, axis 1.4, offset 0, sensor at x = 1.5) as the calibration's start.
std::unique_ptr<TricycleLogSink> makeTricycleLogSink(const Scenario& scenario);

}  // namespace sim
}  // namespace odometry_calibration
