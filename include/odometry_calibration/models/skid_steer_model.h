// Skid-steer calibration: a differential drive whose sides each have several wheel joints
// (e.g. four wheels, two per side). The joints of a side are averaged into one virtual wheel
// and the differential-drive model (diff_drive_model.h, CMLE) is fitted to the two virtual
// wheels. Lateral skidding while turning makes the fitted ("effective") wheel separation larger
// than the geometric track width (Mandow et al., "Experimental kinematics for wheeled
// skid-steer mobile robots", IROS 2007: the effective separation is the geometric one times a
// slip factor, typically 1.2-2); the model reports it also as the multipliers a
// diff_drive_controller applies to its geometric values.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/model.h"

namespace odometry_calibration {

/// Options of the skid-steer model. The geometric (nominal) values are the fit's start values
/// and the reference of the multipliers.
struct SkidSteerOptions
{
  std::vector<int> left_indices;    ///< the left side's wheel joints (averaged)
  std::vector<int> right_indices;   ///< the right side's wheel joints (averaged)
  double ticks_per_turn = 2000.0;   ///< encoder units per wheel revolution (all wheels)
  double wheel_radius_m = 0.1;      ///< geometric wheel radius [m]
  double wheel_separation_m = 0.5;  ///< geometric track width (wheel centre to centre) [m]
  Pose2 initial_T_base_sensor;      ///< start value of the sensor pose
  double huber_threshold = 3.0;     ///< as DiffDriveOptions
  int max_iterations = 500;         ///< as DiffDriveOptions
  int yaw_starts = 8;               ///< as DiffDriveOptions
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const SkidSteerOptions& options);

/// The two virtual wheels of `samples`: values (mean of the left joints, mean of the right
/// joints). Throws std::invalid_argument when a sample lacks one of the joints.
std::vector<EncoderSample> averageSides(const std::vector<EncoderSample>& samples,
                                        const std::vector<int>& left_indices,
                                        const std::vector<int>& right_indices);

/// Every pair's encoder samples averaged into the two virtual wheels (averageSides). Throws
/// std::invalid_argument for a pair with fewer than two samples or without a wheel joint.
std::vector<MotionPair> averageSidesOfPairs(const std::vector<MotionPair>& pairs,
                                            const SkidSteerOptions& options);

/// The differential drive of the two virtual wheels (joints 0 and 1 of averageSides), started
/// at the geometric values and the options' sensor pose, with the options' solver settings.
/// Throws std::invalid_argument for invalid options.
DiffDriveOptions skidSteerVirtualWheels(const SkidSteerOptions& options);

/// The multipliers a diff_drive_controller applies to its geometric values, from the fitted
/// effective left radius, right radius and separation (the first three of `effective`, in that
/// order): wheel_separation_multiplier, left_wheel_radius_multiplier,
/// right_wheel_radius_multiplier, each fitted / geometric with σ (and start value) scaled alike.
std::vector<ParameterEstimate> skidSteerMultipliers(const std::vector<ParameterEstimate>& effective,
                                                    const SkidSteerOptions& options);

/// The fitted skid-steer model. Its report lists the diff-drive parameters (effective radii
/// and separation, sensor pose) and then wheel_separation_multiplier,
/// left_wheel_radius_multiplier and right_wheel_radius_multiplier (fitted / geometric, with
/// sigma).
class SkidSteerModel : public MotionModel
{
public:
  explicit SkidSteerModel(SkidSteerOptions options);
  /// The model of `options`' sides whose virtual wheels are `wheels` (a differential drive on
  /// joints 0 and 1, e.g. skidSteerVirtualWheels with a joint fit's values). Throws
  /// std::invalid_argument for invalid options.
  SkidSteerModel(SkidSteerOptions options, DiffDriveModel wheels);

  std::string name() const override { return "skid_steer"; }
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  std::string toYaml() const override;

  /// Loads a model written by toYaml(); throws std::runtime_error naming a missing key.
  static SkidSteerModel fromYaml(const std::string& text);

  /// Effective (r_L, r_R, b) [m].
  const Eigen::Vector3d& intrinsics() const { return wheels_.intrinsics(); }
  const Pose2& T_base_sensor() const { return wheels_.T_base_sensor(); }
  const SkidSteerOptions& options() const { return options_; }

private:
  SkidSteerOptions options_;
  DiffDriveModel wheels_;  ///< the differential drive of the two averaged sides
};

}  // namespace odometry_calibration
