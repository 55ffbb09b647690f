// What may have changed on a robot since its calibration, and how each change would show in a
// pair: the health monitor's candidate causes and their per-pair sensitivities.
//
// A pair's residual r = measured - predicted sensor motion (x, y, theta). If quantity c of the
// robot changed by delta_c after the fit, the measured motion is the prediction at the changed
// value, so to first order r = J_c delta_c, J_c = d(predicted sensor motion) / d(c) over the
// pair's encoder samples. Each quantity leaves its own pattern over a drive:
//   a wheel radius scales that wheel's travel: forward and rotation residuals follow that
//     wheel's increment (also on straight runs);
//   the wheel separation scales the rotation only: theta residual proportional to the rotation;
//   the sensor's mounting yaw rotates the measured translation: a sideways residual
//     proportional to the forward motion, no rotation residual;
//   the sensor's mounting position: a sideways residual proportional to the rotation (x) or an
//     along-track one (y), no rotation residual.
// The attribution (change_attribution.h) regresses the residuals on these columns.
//
// One set of hypotheses describes one ego-motion source (its mounting on the robot). With
// several sources (a front and a rear laser, one set of wheels), the set holds the
// wheel quantities once (a wheel change shows in every sensor's pairs) and each sensor's
// mounting x, y, yaw (a knocked laser shows in its own pairs only); a pair's sensitivity has
// its own sensor's mounting columns and zeros in the others'.
#pragma once

#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// Whether a change is of the wheels (odometry) or of the sensor's mounting.
enum class ChangeKind
{
  kWheel,
  kMounting
};

/// One candidate change.
struct ChangeHypothesis
{
  std::string name;  ///< e.g. "right wheel radius", "laser mounting yaw"
  ChangeKind kind = ChangeKind::kWheel;
  std::string unit;  ///< unit of its sensitivity's parameter: "%", "cm" or "deg"
  /// Largest change considered [unit]: wear and knocks, not another robot (and the first-order
  /// sensitivity holds); a change point whose estimate lies beyond is not this change.
  double plausible = 20.0;
  /// The sensor whose mounting it is (index of the watched sensors, 0 with one); -1 for a wheel
  /// change, which every sensor sees.
  int sensor = -1;
};

/// The candidate changes of one model and sensor, and their sensitivities per pair.
class ChangeHypotheses
{
public:
  virtual ~ChangeHypotheses() = default;
  const std::vector<ChangeHypothesis>& hypotheses() const { return hypotheses_; }
  /// d(predicted sensor motion x [m], y [m], theta [rad]) per unit of each hypothesis (columns,
  /// in hypotheses() order), by central differences over `samples`. Throws
  /// std::invalid_argument when the model cannot predict the samples.
  virtual Eigen::MatrixXd sensitivity(const std::vector<EncoderSample>& samples) const = 0;
  /// The sensors described (1 unless made by makeSensorsChangeHypotheses).
  virtual std::size_t sensors() const { return 1; }
  /// The sensitivity of a pair of sensor `sensor` (columns in hypotheses() order: the wheels',
  /// that sensor's mounting, zeros for the other sensors' mountings). With one sensor,
  /// sensitivity(). Throws std::invalid_argument for a sensor beyond sensors() or samples the
  /// model cannot predict.
  virtual Eigen::MatrixXd sensorSensitivity(const std::vector<EncoderSample>& samples,
                                            std::size_t sensor) const;

protected:
  std::vector<ChangeHypothesis> hypotheses_;
};

/// The hypotheses of `model` for the sensor called `sensor_name` (e.g. "laser"):
///   diff_drive, skid_steer: left wheel radius, right wheel radius (skid-steer: of a side, its
///     effective radius), wheel separation [%]; the sensor's mounting x, y in base_link [cm] and
///     yaw [deg] (the model's kinematics, integrated again at each changed value);
///   any other model: each joint's travel [%] ("joint <name>": a wheel's radius or a gear),
///     through the model's own prediction with that joint's increments scaled; the sensor's
///     mounting x, y in its own frame [cm] and yaw [deg].
/// `joint_names` names the encoder joints in sample order (may be empty: "joint 1", ...).
std::unique_ptr<ChangeHypotheses> makeChangeHypotheses(
    std::shared_ptr<const MotionModel> model, const std::string& sensor_name,
    const std::vector<std::string>& joint_names = {});

/// The hypotheses of several sensors on one robot: `models[s]` predicts sensor s's
/// motion (the joint calibration's wheels with that sensor's pose), `sensor_names[s]` names it
/// (e.g. its frame, "laser_rear"). The wheel quantities of makeChangeHypotheses once (each
/// sensor's pairs sense them through its own model), then each sensor's mounting x, y, yaw
/// (ChangeHypothesis::sensor = s). Throws std::invalid_argument for no sensor, a null model,
/// a name missing, empty or repeated, or models of different kinds.
std::unique_ptr<ChangeHypotheses> makeSensorsChangeHypotheses(
    const std::vector<std::shared_ptr<const MotionModel>>& models,
    const std::vector<std::string>& sensor_names, const std::vector<std::string>& joint_names = {});

}  // namespace odometry_calibration
