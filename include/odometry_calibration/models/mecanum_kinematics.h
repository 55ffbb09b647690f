// Kinematics of a four-wheel mecanum drive in the standard X roller configuration (the GP
// calibration paper's second robot, Sec. IV, whose parametric model is its ref. [16]: Taheri,
// Qiao, Ghaeminezhad, "Kinematic model of a four mecanum wheeled mobile robot", IJCA 2015),
// templated for Ceres autodiff.
//
// base_link is the centre of the four wheels, x forward, y left. The wheels sit at
// (+-lx, +-ly); their rollers are at 45 degrees, so that seen from above they form an X
// (front-left and rear-right rollers slide freely along x = y, front-right and rear-left along
// x = -y). With equal radii r and wheel rates w_i (i = FL, FR, RL, RR) the forward kinematics
// of [16] are
//   vx    = r/4 (w_FL + w_FR + w_RL + w_RR)
//   vy    = r/4 (-w_FL + w_FR + w_RL - w_RR)
//   omega = r/(4 (lx + ly)) (-w_FL + w_FR - w_RL + w_RR),
// written here with one radius per wheel (the wheel travel d_i = r_i dphi_i over a step):
//   dx = (d_FL + d_FR + d_RL + d_RR) / 4
//   dy = (-d_FL + d_FR + d_RL - d_RR) / 4
//   dtheta = (-d_FL + d_FR - d_RL + d_RR) / (4 (lx + ly)),
// the least-squares inverse of the inverse kinematics d_FL = dx - dy - (lx+ly) dtheta,
// d_FR = dx + dy + (lx+ly) dtheta, d_RL = dx + dy - (lx+ly) dtheta, d_RR = dx - dy + (lx+ly)
// dtheta. Only the sum lx + ly enters, so only it is calibrated. Between consecutive encoder
// samples the wheel speeds are taken as constant, so the base moves with a constant body twist
// (dx, dy, dtheta) per step: the exact SE(2) exponential (an arc), and the motion over a pair
// is the composition of the steps.
#pragma once

#include <cmath>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/models/encoder_steps.h"  // sinc, composeEncoderSteps

namespace odometry_calibration {

/// Where the four wheel encoders are in an EncoderSample and their resolution.
struct MecanumEncoderLayout
{
  int front_left_index = 0;        ///< cumulative ticks of the front-left wheel
  int front_right_index = 1;       ///< ... front-right wheel
  int rear_left_index = 2;         ///< ... rear-left wheel
  int rear_right_index = 3;        ///< ... rear-right wheel
  double ticks_per_turn = 2000.0;  ///< encoder ticks per wheel revolution
};

/// Indices into the 5-vector of intrinsic parameters.
enum MecanumParameterIndex
{
  kFrontLeftRadius = 0,   ///< r_FL [m]
  kFrontRightRadius = 1,  ///< r_FR [m]
  kRearLeftRadius = 2,    ///< r_RL [m]
  kRearRightRadius = 3,   ///< r_RR [m]
  kLxPlusLy = 4,          ///< lx + ly: half wheelbase plus half track [m]
  kMecanumParameterCount  ///< 5
};

/// The SE(2) exponential of a constant body twist (dx, dy, dtheta) over one step, in a form
/// Ceres can differentiate: theta = dtheta, t = V(dtheta) (dx, dy) with
/// V = [sin/th, -(1-cos)/th; (1-cos)/th, sin/th], (1 - cos th)/th = sin(th/2) sinc(th/2).
template <typename T>
Pose2T<T> twistStep(const T& dx, const T& dy, const T& dtheta)
{
  using std::sin;
  const T a = sinc(dtheta);
  const T b = sin(dtheta / T(2.0)) * sinc(dtheta / T(2.0));
  return Pose2T<T>(a * dx - b * dy, b * dx + a * dy, dtheta);
}

/// Base motion of one sub-interval from the four wheels' tick increments (FL, FR, RL, RR).
template <typename T>
Pose2T<T> mecanumStep(const T* intrinsic, const double ticks[4], double ticks_per_turn)
{
  const double to_rad = 2.0 * M_PI / ticks_per_turn;
  T d[4];
  for (int i = 0; i < 4; ++i)
    d[i] = intrinsic[i] * T(ticks[i] * to_rad);
  const T dx = (d[0] + d[1] + d[2] + d[3]) / T(4.0);
  const T dy = (-d[0] + d[1] + d[2] - d[3]) / T(4.0);
  const T dtheta = (-d[0] + d[1] - d[2] + d[3]) / (T(4.0) * intrinsic[kLxPlusLy]);
  return twistStep(dx, dy, dtheta);
}

/// Base motion from the first to the last sample: the composition of all sub-intervals.
template <typename T>
Pose2T<T> integrateMecanumMotion(const T* intrinsic, const MecanumEncoderLayout& layout,
                                 const std::vector<EncoderSample>& samples)
{
  const int index[4] = {layout.front_left_index, layout.front_right_index, layout.rear_left_index,
                        layout.rear_right_index};
  return composeEncoderSteps<T>(samples,
                                [&](const EncoderSample& previous, const EncoderSample& current) {
                                  double ticks[4];
                                  for (int i = 0; i < 4; ++i)
                                    ticks[i] = current.values(index[i]) - previous.values(index[i]);
                                  return mecanumStep(intrinsic, ticks, layout.ticks_per_turn);
                                });
}

/// The mecanum drive as a kinematic model for fitSensorMotion (intrinsics r_FL, r_FR, r_RL,
/// r_RR, lx + ly).
struct MecanumKinematics
{
  using Layout = MecanumEncoderLayout;
  static constexpr int kIntrinsics = kMecanumParameterCount;
  template <typename T>
  static Pose2T<T> integrate(const T* intrinsic, const Layout& layout,
                             const std::vector<EncoderSample>& samples)
  {
    return integrateMecanumMotion(intrinsic, layout, samples);
  }
};

}  // namespace odometry_calibration
