// The tricycle calibration (docs/models.md, "The tricycle": Ks, Kt, axis length, steering offset
// and the sensor pose, by robust least squares on keyframe pairs) behind the common model
// interface, so that the live node and calibrate_bag fit it like any other model.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/models/model.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// Options of the tricycle model: which joints, start values, the fit's noise and loss.
struct TricycleModelOptions
{
  TricycleEncoderLayout layout;  ///< steering (absolute) and traction (incremental) joints
  TricycleParameters initial;    ///< start values of the fit and the nominal prediction
  TricycleCalibrationOptions calibration;
};

class TricycleModel : public MotionModel
{
public:
  explicit TricycleModel(TricycleModelOptions options);

  std::string name() const override { return "tricycle"; }
  /// calibrateTricycle (seed sections 3-5) from the current parameters.
  ModelReport fit(const std::vector<MotionPair>& pairs) override;
  /// h = T_bs^-1 * Delta_r * T_bs over the samples (seed, "prediction function"), with the
  /// fit's per-pair residual covariance (zero before a fit).
  MotionPrediction predict(const std::vector<EncoderSample>& samples) const override;
  /// The joints, the kinematic parameters, `steering_at_step_end` (the layout's flag: how a
  /// step's steering is read, tricycle_kinematics.h), the sensor pose and the covariance.
  std::string toYaml() const override;
  /// Loads a model written by toYaml(); throws std::runtime_error naming what is missing.
  /// Without `steering_at_step_end` (written before it was saved) a step's steering is the mean
  /// of its two readings, the layout's default.
  static TricycleModel fromYaml(const std::string& text);

  const TricycleParameters& parameters() const { return parameters_; }
  /// The last fit's own result (start and fitted values, covariance, residuals), as the
  /// tracker-log report prints it; none before a fit.
  const std::optional<TricycleCalibrationResult>& lastCalibration() const
  {
    return last_calibration_;
  }

private:
  TricycleModelOptions options_;
  TricycleParameters parameters_;
  Eigen::Matrix3d residual_covariance_ = Eigen::Matrix3d::Zero();
  std::optional<TricycleCalibrationResult> last_calibration_;
};

}  // namespace odometry_calibration
