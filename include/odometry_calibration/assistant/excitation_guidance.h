// Live excitation guidance for the parametric models: while pairs arrive, keep the
// Fisher information they add, H = sum_i J_i^T Sigma_i^-1 J_i, with J_i the Jacobian of pair i's
// SE(2) error (sensor_motion_fit.h, the CMLE of Censi et al. T-RO 2013, Sec. V) with respect to
// the intrinsics and the sensor pose at fixed linearisation values (the nominal or last fitted
// ones). The parameters' covariance "as if fitted now" is H^-1 (Cramer-Rao bound; a weak prior
// keeps it finite for unexcited directions), so no refit per pair is needed. Beside the sigmas,
// each parameter needs the motions that separate it from the others (straight runs, turns both
// ways, turning on the spot or full-lock steering), so that "enough" also means the data would
// expose a model error, and the guidance names the motion still missing in words.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {

/// What the guidance asks for. Motion amounts are per kind of motion, summed over the pairs.
struct ExcitationGuidanceOptions
{
  /// Target sigma by parameter name (e.g. "wheel_separation": 0.0005); a parameter not listed
  /// gets the default of its kind below.
  std::map<std::string, double> target_sigma;
  double relative_target = 0.002;    ///< radii, lengths, scales: target = this * |value| [-]
  double length_target_m = 0.005;    ///< sensor_x, sensor_y [m]
  double angle_target_rad = 0.005;   ///< sensor_theta, steering_offset [rad]
  double straight_distance_m = 2.0;  ///< straight driving needed [m]
  double spot_turn_rad = 6.283185307179586;  ///< diff_drive: turning on the spot, each way [rad]
  double turn_rad = 3.141592653589793;       ///< turning while driving, each way [rad]
  double strafe_distance_m = 1.0;            ///< mecanum: sideways travel, each way [m]
  /// tricycle: steering angle of full lock [rad] (the robot's maximum; the fit does not know it)
  double full_lock_rad = 1.2;
  /// tricycle: steering beyond this fraction of full_lock_rad counts as full lock [-]
  double full_lock_fraction = 0.8;
  double full_lock_travel_m = 1.0;  ///< tricycle: travel at full lock needed, each way [m]
  /// Prior sigma of every parameter, as a multiple of its target: keeps H invertible before a
  /// direction is excited; far above the target so it never makes a parameter "enough".
  double prior_factor = 1000.0;
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const ExcitationGuidanceOptions& options);

/// One parameter's state.
struct ParameterGuidance
{
  std::string name;           ///< as in the fit's report, e.g. "wheel_separation"
  std::string unit;           ///< e.g. "m"
  double value = 0.0;         ///< linearisation value
  double sigma = 0.0;         ///< sqrt of the diagonal of H^-1 [unit]
  double target_sigma = 0.0;  ///< [unit]
  bool enough = false;        ///< sigma <= target and every needed motion driven
  /// The motions this parameter still needs, in words (empty when all were driven).
  std::vector<std::string> missing_motions;
};

/// The guidance at one moment.
struct ExcitationStatus
{
  std::string model;
  std::size_t pairs = 0;  ///< pairs accumulated
  std::vector<ParameterGuidance> parameters;
  /// Every motion still missing (the union over the parameters), in words, most needed first.
  std::vector<std::string> missing_motions;
  bool ready_to_fit = false;  ///< every parameter "enough"
  /// One line: "ready to fit" or "collecting: <motions>; <parameter> sigma x > target y".
  std::string summary() const;
};

/// Accumulates pairs and tells what is still missing. Not thread-safe.
class ExcitationGuidance
{
public:
  virtual ~ExcitationGuidance() = default;
  /// Adds a pair's information (pairs with fewer than two samples or a singular covariance are
  /// ignored and counted in skipped()).
  virtual void addPair(const MotionPair& pair) = 0;
  virtual ExcitationStatus status() const = 0;
  /// Forgets all pairs.
  virtual void reset() = 0;
  virtual std::size_t skipped() const = 0;
};

/// Whether makeExcitationGuidance supports `model` (diff_drive, tricycle, mecanum).
bool hasExcitationGuidance(const std::string& model);

/// Guidance for `model` linearised at the model options' start values (`factory.diff_drive`,
/// `factory.tricycle` or `factory.mecanum`: layout, initial intrinsics and sensor pose), or, for
/// the parameters named in `linearise_at` (e.g. a fit's report), at those values. Throws
/// std::invalid_argument for a model without guidance, invalid options or a name in `linearise_at`
/// the model does not have.
std::unique_ptr<ExcitationGuidance> makeExcitationGuidance(
    const std::string& model, const ModelFactoryOptions& factory,
    const ExcitationGuidanceOptions& options,
    const std::vector<ParameterEstimate>& linearise_at = {});

}  // namespace odometry_calibration
