#include "odometry_calibration/assistant/excitation_guidance.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <functional>
#include <stdexcept>

#include <ceres/ceres.h>
#include <Eigen/Cholesky>

#include "odometry_calibration/models/diff_drive_kinematics.h"
#include "odometry_calibration/models/mecanum_kinematics.h"
#include "odometry_calibration/models/parameter_layouts.h"
#include "odometry_calibration/models/sensor_motion_fit.h"
#include "odometry_calibration/models/tricycle_residual.h"

namespace odometry_calibration {
namespace {

/// Kinds of motion the guidance counts (amounts in m or rad, as noted).
enum Motion
{
  kStraight = 0,  ///< straight driving, either direction [m]
  kSpotLeft,      ///< turning on the spot counter-clockwise [rad]
  kSpotRight,     ///< turning on the spot clockwise [rad]
  kTurnLeft,      ///< heading change to the left, any way [rad]
  kTurnRight,     ///< heading change to the right, any way [rad]
  kFullLeft,      ///< travel with the steering beyond the full-lock fraction, left [m]
  kFullRight,     ///< the same, right [m]
  kStrafeLeft,    ///< mecanum: sideways travel to the left [m]
  kStrafeRight,   ///< mecanum: sideways travel to the right [m]
  kMotionCount
};

using MotionAmounts = std::array<double, kMotionCount>;

std::string format(const char* pattern, double a, double b)
{
  char text[160];
  std::snprintf(text, sizeof(text), pattern, a, b);
  return text;
}

constexpr double kDegrees = 180.0 / M_PI;

/// The motion in words, with how much of it was driven.
std::string motionWords(Motion motion, bool turns_in_place, double driven, double needed)
{
  switch (motion) {
    case kStraight:
      return format("drive straight at least %.1f m (%.1f m so far)", needed, driven);
    case kSpotLeft:
      return format("turn on the spot to the left (%.0f of %.0f deg)", driven * kDegrees,
                    needed * kDegrees);
    case kSpotRight:
      return format("turn on the spot to the right (%.0f of %.0f deg)", driven * kDegrees,
                    needed * kDegrees);
    case kTurnLeft:
      return format(turns_in_place ? "turn left (%.0f of %.0f deg)"
                                   : "turn left while driving (%.0f of %.0f deg)",
                    driven * kDegrees, needed * kDegrees);
    case kTurnRight:
      return format(turns_in_place ? "turn right (%.0f of %.0f deg)"
                                   : "turn right while driving (%.0f of %.0f deg)",
                    driven * kDegrees, needed * kDegrees);
    case kFullLeft:
      return format("steer full left while driving (%.1f of %.1f m)", driven, needed);
    case kFullRight:
      return format("steer full right while driving (%.1f of %.1f m)", driven, needed);
    case kStrafeLeft:
      return format("strafe to the left (%.1f of %.1f m)", driven, needed);
    case kStrafeRight:
      return format("strafe to the right (%.1f of %.1f m)", driven, needed);
    default:
      return "?";
  }
}

/// What a model needs: its parameters, which motions each needs, how a pair is classified.
struct ModelTraits
{
  std::string model;
  ParameterLayout layout;                  ///< names, units, which have a relative target
  std::vector<std::vector<Motion>> needs;  ///< per parameter
  bool turns_in_place = true;
};

/// Accumulates H = sum J^T Sigma^-1 J for Kinematics at fixed linearisation values.
template <class Kinematics>
class Guidance : public ExcitationGuidance
{
public:
  static constexpr int N = Kinematics::kIntrinsics;
  static constexpr int P = N + 3;
  using Classifier = std::function<void(const MotionPair&, MotionAmounts&)>;

  Guidance(ModelTraits traits, const typename Kinematics::Layout& layout,
           const Eigen::Matrix<double, N, 1>& intrinsic, const Pose2& T_base_sensor,
           const ExcitationGuidanceOptions& options, Classifier classify)
      : traits_(std::move(traits)),
        layout_(layout),
        intrinsic_(intrinsic),
        sensor_pose_(T_base_sensor.vector()),
        options_(options),
        classify_(std::move(classify))
  {
    validate(options_);
    Eigen::Matrix<double, P, 1> value;
    value << intrinsic_, sensor_pose_;
    for (int i = 0; i < P; ++i) {
      const std::string& name = traits_.layout.names[static_cast<std::size_t>(i)];
      const auto given = options_.target_sigma.find(name);
      if (given != options_.target_sigma.end()) {
        target_(i) = given->second;
      } else if (std::find(traits_.layout.relative.begin(), traits_.layout.relative.end(), name) !=
                 traits_.layout.relative.end()) {
        target_(i) = options_.relative_target * std::abs(value(i));
      } else {
        target_(i) = traits_.layout.units[static_cast<std::size_t>(i)] == "rad"
                         ? options_.angle_target_rad
                         : options_.length_target_m;
      }
      if (!(target_(i) > 0.0)) {
        throw std::invalid_argument("excitation guidance: the target sigma of " + name +
                                    " must be > 0 (a relative target needs a non-zero value)");
      }
    }
    value_ = value;
    reset();
  }

  void addPair(const MotionPair& pair) override
  {
    if (pair.encoder_samples.size() < 2 || !pair.covariance.allFinite() ||
        pair.covariance.determinant() <= 0.0) {
      ++skipped_;
      return;
    }
    using Residual = SensorMotionResidual<Kinematics>;
    ceres::AutoDiffCostFunction<Residual, 3, N, 3> cost(new Residual(pair, layout_));
    const double* parameters[] = {intrinsic_.data(), sensor_pose_.data()};
    Eigen::Vector3d residual;
    Eigen::Matrix<double, 3, N, Eigen::RowMajor> j_intrinsic;
    Eigen::Matrix<double, 3, 3, Eigen::RowMajor> j_pose;
    double* jacobians[] = {j_intrinsic.data(), j_pose.data()};
    if (!cost.Evaluate(parameters, residual.data(), jacobians) || !j_intrinsic.allFinite() ||
        !j_pose.allFinite()) {
      ++skipped_;
      return;
    }
    // The residual is already whitened (L^-1 e), so J^T J is J_e^T Sigma^-1 J_e.
    Eigen::Matrix<double, 3, P> jacobian;
    jacobian << j_intrinsic, j_pose;
    information_.noalias() += jacobian.transpose() * jacobian;
    classify_(pair, driven_);
    ++pairs_;
  }

  ExcitationStatus status() const override
  {
    ExcitationStatus status;
    status.model = traits_.model;
    status.pairs = pairs_;
    Eigen::Matrix<double, P, P> information = information_;
    for (int i = 0; i < P; ++i)
      information(i, i) += 1.0 / std::pow(options_.prior_factor * target_(i), 2);
    const Eigen::Matrix<double, P, P> covariance =
        information.ldlt().solve(Eigen::Matrix<double, P, P>::Identity());
    std::array<int, kMotionCount> wanted{};
    for (int i = 0; i < P; ++i) {
      ParameterGuidance parameter;
      parameter.name = traits_.layout.names[static_cast<std::size_t>(i)];
      parameter.unit = traits_.layout.units[static_cast<std::size_t>(i)];
      parameter.value = value_(i);
      parameter.sigma = std::sqrt(std::max(covariance(i, i), 0.0));
      parameter.target_sigma = target_(i);
      for (Motion motion : traits_.needs[static_cast<std::size_t>(i)]) {
        if (driven_[motion] < needed(motion)) {
          parameter.missing_motions.push_back(
              motionWords(motion, traits_.turns_in_place, driven_[motion], needed(motion)));
          ++wanted[motion];
        }
      }
      parameter.enough =
          parameter.sigma <= parameter.target_sigma && parameter.missing_motions.empty();
      status.parameters.push_back(parameter);
    }
    // Most needed first: by the number of parameters waiting for it, then the least driven.
    std::vector<int> order;
    for (int m = 0; m < kMotionCount; ++m) {
      if (wanted[m] > 0)
        order.push_back(m);
    }
    std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
      if (wanted[a] != wanted[b])
        return wanted[a] > wanted[b];
      return driven_[a] / needed(static_cast<Motion>(a)) <
             driven_[b] / needed(static_cast<Motion>(b));
    });
    for (int m : order) {
      status.missing_motions.push_back(motionWords(static_cast<Motion>(m), traits_.turns_in_place,
                                                   driven_[m], needed(static_cast<Motion>(m))));
    }
    status.ready_to_fit = std::all_of(status.parameters.begin(), status.parameters.end(),
                                      [](const ParameterGuidance& p) { return p.enough; });
    return status;
  }

  void reset() override
  {
    information_.setZero();
    driven_.fill(0.0);
    pairs_ = 0;
    skipped_ = 0;
  }

  std::size_t skipped() const override { return skipped_; }

private:
  double needed(Motion motion) const
  {
    switch (motion) {
      case kStraight:
        return options_.straight_distance_m;
      case kSpotLeft:
      case kSpotRight:
        return options_.spot_turn_rad;
      case kTurnLeft:
      case kTurnRight:
        return options_.turn_rad;
      case kStrafeLeft:
      case kStrafeRight:
        return options_.strafe_distance_m;
      default:
        return options_.full_lock_travel_m;
    }
  }

  ModelTraits traits_;
  typename Kinematics::Layout layout_;
  Eigen::Matrix<double, N, 1> intrinsic_;
  Eigen::Vector3d sensor_pose_;
  ExcitationGuidanceOptions options_;
  Classifier classify_;
  Eigen::Matrix<double, P, 1> value_, target_;
  Eigen::Matrix<double, P, P> information_;
  MotionAmounts driven_{};
  std::size_t pairs_ = 0, skipped_ = 0;
};

/// Adds a step's heading change to the left or right turn amount.
void addTurn(double dtheta, MotionAmounts& driven)
{
  driven[dtheta > 0.0 ? kTurnLeft : kTurnRight] += std::abs(dtheta);
}

std::unique_ptr<ExcitationGuidance> diffDriveGuidance(const DiffDriveOptions& factory,
                                                      const ExcitationGuidanceOptions& options)
{
  ModelTraits traits;
  traits.model = "diff_drive";
  traits.layout = diffDriveParameters();
  // The radii need straight runs (their mean) and turns both ways (their ratio against b);
  // the sensor's position is best seen turning on the spot both ways (a pure rotation moves it
  // on a circle), its yaw on straight runs (the travel's direction in the sensor frame).
  traits.needs = {{kStraight, kTurnLeft, kTurnRight},
                  {kStraight, kTurnLeft, kTurnRight},
                  {kTurnLeft, kTurnRight},
                  {kSpotLeft, kSpotRight},
                  {kSpotLeft, kSpotRight},
                  {kStraight}};
  const Eigen::Vector3d intrinsic(factory.initial_left_radius_m, factory.initial_right_radius_m,
                                  factory.initial_separation_m);
  const DiffDriveEncoderLayout layout = factory.layout;
  auto classify = [intrinsic, layout](const MotionPair& pair, MotionAmounts& driven) {
    // Per encoder step: straight (turning radius beyond 10 m), on the spot (within 5 cm), or
    // an arc; amounts from the nominal kinematics (diff_drive_kinematics.h).
    for (std::size_t k = 1; k < pair.encoder_samples.size(); ++k) {
      const EncoderSample& a = pair.encoder_samples[k - 1];
      const EncoderSample& b = pair.encoder_samples[k];
      const Pose2 step = diffDriveStep<double>(
          intrinsic.data(), b.values(layout.left_index) - a.values(layout.left_index),
          b.values(layout.right_index) - a.values(layout.right_index), layout.ticks_per_turn);
      const double distance = std::hypot(step.x(), step.y());
      const double dtheta = step.theta();
      if (std::abs(dtheta) <= 0.1 * distance) {
        driven[kStraight] += distance;
      } else {
        addTurn(dtheta, driven);
        if (distance < 0.05 * std::abs(dtheta))
          driven[dtheta > 0.0 ? kSpotLeft : kSpotRight] += std::abs(dtheta);
      }
    }
  };
  return std::make_unique<Guidance<DiffDriveKinematics>>(
      traits, layout, intrinsic, factory.initial_T_base_sensor, options, classify);
}

std::unique_ptr<ExcitationGuidance> tricycleGuidance(const TricycleModelOptions& factory,
                                                     const ExcitationGuidanceOptions& options)
{
  ModelTraits traits;
  traits.model = "tricycle";
  traits.layout = tricycleParameters();
  traits.turns_in_place = false;
  // The steering scale is seen at large angles both ways; the offset against straight runs and
  // both turn directions (seed section 6: one-way turns confuse it with the scale); the axis
  // length in turns; the sensor position at full lock (the tightest circles), its yaw straight.
  traits.needs = {{kFullLeft, kFullRight},
                  {kStraight},
                  {kTurnLeft, kTurnRight},
                  {kStraight, kTurnLeft, kTurnRight},
                  {kFullLeft, kFullRight},
                  {kFullLeft, kFullRight},
                  {kStraight}};
  const Eigen::Vector4d kinematic = factory.initial.kinematicVector();
  const TricycleEncoderLayout layout = factory.layout;
  const double full_lock = options.full_lock_fraction * options.full_lock_rad;
  auto classify = [kinematic, layout, full_lock](const MotionPair& pair, MotionAmounts& driven) {
    // Per encoder step, by the nominal steering angle (tricycle_kinematics.h).
    for (std::size_t k = 1; k < pair.encoder_samples.size(); ++k) {
      const EncoderSample& a = pair.encoder_samples[k - 1];
      const EncoderSample& b = pair.encoder_samples[k];
      const double travel = kinematic(kTractionScale) *
                            (b.values(layout.traction_index) - a.values(layout.traction_index)) /
                            layout.traction_ticks_per_turn;
      const double steering = kinematic(kSteeringScale) * b.values(layout.steering_index) * 2.0 *
                                  M_PI / layout.steering_ticks_per_turn +
                              kinematic(kSteeringOffset);
      const double dtheta = travel * std::sin(steering) / kinematic(kAxisLength);
      if (std::abs(steering) < 0.1 * full_lock) {
        driven[kStraight] += std::abs(travel);
      } else {
        addTurn(dtheta, driven);
        if (std::abs(steering) >= full_lock)
          driven[steering > 0.0 ? kFullLeft : kFullRight] += std::abs(travel);
      }
    }
  };
  return std::make_unique<Guidance<TricycleKinematics>>(
      traits, layout, kinematic, factory.initial.T_base_sensor, options, classify);
}

std::unique_ptr<ExcitationGuidance> mecanumGuidance(const MecanumOptions& factory,
                                                    const ExcitationGuidanceOptions& options)
{
  ModelTraits traits;
  traits.model = "mecanum";
  traits.layout = mecanumParameters();
  // Each radius enters forward travel, strafing and rotation with its own signs: all three
  // (both ways) separate the four; lx + ly needs rotation; the sensor as for the diff drive.
  const std::vector<Motion> radius = {kStraight, kStrafeLeft, kStrafeRight, kTurnLeft, kTurnRight};
  traits.needs = {radius,
                  radius,
                  radius,
                  radius,
                  {kTurnLeft, kTurnRight},
                  {kSpotLeft, kSpotRight},
                  {kSpotLeft, kSpotRight},
                  {kStraight}};
  Eigen::Matrix<double, kMecanumParameterCount, 1> intrinsic;
  intrinsic << factory.initial_radius_m[0], factory.initial_radius_m[1],
      factory.initial_radius_m[2], factory.initial_radius_m[3], factory.initial_lx_plus_ly_m;
  const MecanumEncoderLayout layout = factory.layout;
  auto classify = [intrinsic, layout](const MotionPair& pair, MotionAmounts& driven) {
    // Per encoder step (mecanum_kinematics.h): turning, strafing or straight, by what dominates.
    const int index[4] = {layout.front_left_index, layout.front_right_index, layout.rear_left_index,
                          layout.rear_right_index};
    for (std::size_t k = 1; k < pair.encoder_samples.size(); ++k) {
      double ticks[4];
      for (int i = 0; i < 4; ++i) {
        ticks[i] =
            pair.encoder_samples[k].values(index[i]) - pair.encoder_samples[k - 1].values(index[i]);
      }
      const Pose2 step = mecanumStep<double>(intrinsic.data(), ticks, layout.ticks_per_turn);
      const double distance = std::hypot(step.x(), step.y());
      const double dtheta = step.theta();
      if (std::abs(dtheta) > 0.1 * distance) {
        addTurn(dtheta, driven);
        if (distance < 0.05 * std::abs(dtheta))
          driven[dtheta > 0.0 ? kSpotLeft : kSpotRight] += std::abs(dtheta);
      } else if (std::abs(step.y()) > std::abs(step.x())) {
        driven[step.y() > 0.0 ? kStrafeLeft : kStrafeRight] += std::abs(step.y());
      } else {
        driven[kStraight] += std::abs(step.x());
      }
    }
  };
  return std::make_unique<Guidance<MecanumKinematics>>(
      traits, layout, intrinsic, factory.initial_T_base_sensor, options, classify);
}

}  // namespace

void validate(const ExcitationGuidanceOptions& options)
{
  auto positive = [](double value, const char* name) {
    if (!(value > 0.0) || !std::isfinite(value))
      throw std::invalid_argument(std::string("excitation guidance: ") + name + " must be > 0");
  };
  positive(options.relative_target, "relative_target");
  positive(options.length_target_m, "length_target_m");
  positive(options.angle_target_rad, "angle_target_rad");
  positive(options.straight_distance_m, "straight_distance_m");
  positive(options.spot_turn_rad, "spot_turn_rad");
  positive(options.turn_rad, "turn_rad");
  positive(options.strafe_distance_m, "strafe_distance_m");
  positive(options.full_lock_rad, "full_lock_rad");
  positive(options.full_lock_travel_m, "full_lock_travel_m");
  positive(options.prior_factor, "prior_factor");
  if (!(options.full_lock_fraction > 0.0 && options.full_lock_fraction <= 1.0))
    throw std::invalid_argument("excitation guidance: full_lock_fraction must be in (0, 1]");
  for (const auto& [name, sigma] : options.target_sigma)
    positive(sigma, ("target sigma of " + name).c_str());
}

std::string ExcitationStatus::summary() const
{
  if (ready_to_fit)
    return "ready to fit (" + std::to_string(pairs) + " pairs)";
  std::string text = "collecting (" + std::to_string(pairs) + " pairs)";
  if (!missing_motions.empty()) {
    text += ": still missing: ";
    for (std::size_t i = 0; i < missing_motions.size(); ++i)
      text += (i ? "; " : "") + missing_motions[i];
  }
  std::string sigmas;
  for (const ParameterGuidance& p : parameters) {
    if (p.sigma > p.target_sigma) {
      char line[200];
      std::snprintf(line, sizeof(line), "%s%s sigma %.3g > target %.3g %s",
                    sigmas.empty() ? "" : ", ", p.name.c_str(), p.sigma, p.target_sigma,
                    p.unit.c_str());
      sigmas += line;
    }
  }
  if (!sigmas.empty())
    text += (missing_motions.empty() ? ": keep driving: " : "; ") + sigmas;
  return text;
}

bool hasExcitationGuidance(const std::string& model)
{
  return model == "diff_drive" || model == "tricycle" || model == "mecanum";
}

std::unique_ptr<ExcitationGuidance> makeExcitationGuidance(
    const std::string& model, const ModelFactoryOptions& factory,
    const ExcitationGuidanceOptions& options, const std::vector<ParameterEstimate>& linearise_at)
{
  ModelFactoryOptions at = factory;
  DiffDriveOptions& d = at.diff_drive;
  TricycleParameters& t = at.tricycle.initial;
  Pose2& sensor = model == "tricycle"  ? t.T_base_sensor
                  : model == "mecanum" ? at.mecanum.initial_T_base_sensor
                                       : d.initial_T_base_sensor;
  for (const ParameterEstimate& estimate : linearise_at) {
    const std::string& n = estimate.name;
    const double v = estimate.value;
    if (!std::isfinite(v))
      throw std::invalid_argument("excitation guidance: " + n + " is not finite");
    if (n == "sensor_x") {
      sensor = Pose2(v, sensor.y(), sensor.theta());
    } else if (n == "sensor_y") {
      sensor = Pose2(sensor.x(), v, sensor.theta());
    } else if (n == "sensor_theta") {
      sensor = Pose2(sensor.x(), sensor.y(), v);
    } else if (model == "diff_drive" && n == "left_wheel_radius") {
      d.initial_left_radius_m = v;
    } else if (model == "diff_drive" && n == "right_wheel_radius") {
      d.initial_right_radius_m = v;
    } else if (model == "diff_drive" && n == "wheel_separation") {
      d.initial_separation_m = v;
    } else if (model == "mecanum" &&
               (n == "wheel_radius_front_left" || n == "wheel_radius_front_right" ||
                n == "wheel_radius_rear_left" || n == "wheel_radius_rear_right")) {
      const int i = n == "wheel_radius_front_left"    ? 0
                    : n == "wheel_radius_front_right" ? 1
                    : n == "wheel_radius_rear_left"   ? 2
                                                      : 3;
      at.mecanum.initial_radius_m[static_cast<std::size_t>(i)] = v;
    } else if (model == "mecanum" && n == "lx_plus_ly") {
      at.mecanum.initial_lx_plus_ly_m = v;
    } else if (model == "tricycle" && n == "steering_scale") {
      t.steering_scale = v;
    } else if (model == "tricycle" && n == "traction_scale") {
      t.traction_scale_m_per_turn = v;
    } else if (model == "tricycle" && n == "axis_length") {
      t.axis_length_m = v;
    } else if (model == "tricycle" && n == "steering_offset") {
      t.steering_offset_rad = v;
    } else {
      throw std::invalid_argument("excitation guidance: " + model + " has no parameter '" + n +
                                  "'");
    }
  }
  if (model == "diff_drive")
    return diffDriveGuidance(at.diff_drive, options);
  if (model == "tricycle")
    return tricycleGuidance(at.tricycle, options);
  if (model == "mecanum")
    return mecanumGuidance(at.mecanum, options);
  throw std::invalid_argument("excitation guidance: model '" + model +
                              "' has none (diff_drive, tricycle and mecanum have)");
}

}  // namespace odometry_calibration
