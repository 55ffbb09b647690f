// SE(2) rigid motions in the plane, with the paper's roto-translation operators.
//
// A pose named T_a_b is the pose of frame b expressed in frame a (it maps points from b to a).
// Composition follows the frames: T_a_c = T_a_b * T_b_c. Units: metres and radians, x forward,
// y left, counter-clockwise positive (REP 103).
//
// Operators of the GP calibration paper (Nutalapati et al., Table I):
//   a ⊕ b  = compose(a, b)                   (roto-translation)
//   ⊖ a    = a.inverse()
//   ⊖ a ⊕ b = between(a, b)                  (relative motion from a to b)
//
// The class is templated on the scalar so that Ceres' Jet types flow through the same code that
// the tests check with doubles.
#pragma once

#include <cmath>

#include <Eigen/Core>

namespace odometry_calibration {

/// Wraps an angle to (-pi, pi] [rad]. Works for double and ceres::Jet.
template <typename T>
T normalizeAngle(const T& angle_rad)
{
  using std::atan2;
  using std::cos;
  using std::sin;
  return atan2(sin(angle_rad), cos(angle_rad));
}

/// The same for plain doubles without trigonometry (poses are composed millions of times per
/// bag): angles already in (-pi, pi] are returned as they are, others reduced by remainder().
inline double normalizeAngle(double angle_rad)
{
  if (angle_rad > -M_PI && angle_rad <= M_PI)
    return angle_rad;
  if (!std::isfinite(angle_rad))
    return std::nan("");
  double wrapped = std::remainder(angle_rad, 2.0 * M_PI);  // in [-pi, pi]
  if (wrapped <= -M_PI)
    wrapped += 2.0 * M_PI;
  return wrapped;
}

/// A rigid motion in the plane: translation (x, y) [m] and rotation theta [rad].
template <typename T>
class Pose2T
{
public:
  Pose2T() : x_(T(0)), y_(T(0)), theta_(T(0)) {}
  Pose2T(const T& x_m, const T& y_m, const T& theta_rad) : x_(x_m), y_(y_m), theta_(theta_rad) {}

  /// From a vector (x [m], y [m], theta [rad]).
  static Pose2T fromVector(const Eigen::Matrix<T, 3, 1>& xytheta)
  {
    return Pose2T(xytheta(0), xytheta(1), xytheta(2));
  }

  const T& x() const { return x_; }
  const T& y() const { return y_; }
  const T& theta() const { return theta_; }

  /// (x [m], y [m], theta [rad]) as stored (theta not re-normalised).
  Eigen::Matrix<T, 3, 1> vector() const { return Eigen::Matrix<T, 3, 1>(x_, y_, theta_); }

  /// Homogeneous 3x3 matrix [R t; 0 1].
  Eigen::Matrix<T, 3, 3> matrix() const
  {
    using std::cos;
    using std::sin;
    Eigen::Matrix<T, 3, 3> m;
    const T c = cos(theta_);
    const T s = sin(theta_);
    m << c, -s, x_, s, c, y_, T(0), T(0), T(1);
    return m;
  }

  /// this ⊕ other (paper Table I): T_a_c = T_a_b * T_b_c. The angle is wrapped to (-pi, pi].
  Pose2T operator*(const Pose2T& other) const
  {
    using std::cos;
    using std::sin;
    const T c = cos(theta_);
    const T s = sin(theta_);
    return Pose2T(x_ + c * other.x_ - s * other.y_, y_ + s * other.x_ + c * other.y_,
                  normalizeAngle(theta_ + other.theta_));
  }

  /// ⊖ this (paper Table I): T_b_a from T_a_b.
  Pose2T inverse() const
  {
    using std::cos;
    using std::sin;
    const T c = cos(theta_);
    const T s = sin(theta_);
    return Pose2T(-c * x_ - s * y_, s * x_ - c * y_, normalizeAngle(-theta_));
  }

  /// Maps a point given in this pose's child frame into its parent frame [m].
  Eigen::Matrix<T, 2, 1> transformPoint(const Eigen::Matrix<T, 2, 1>& p_child) const
  {
    using std::cos;
    using std::sin;
    const T c = cos(theta_);
    const T s = sin(theta_);
    return Eigen::Matrix<T, 2, 1>(x_ + c * p_child(0) - s * p_child(1),
                                  y_ + s * p_child(0) + c * p_child(1));
  }

  /// Casts to another scalar type (e.g. double -> ceres::Jet).
  template <typename U>
  Pose2T<U> cast() const
  {
    return Pose2T<U>(U(x_), U(y_), U(theta_));
  }

private:
  T x_;
  T y_;
  T theta_;
};

using Pose2 = Pose2T<double>;

/// Relative motion from pose `from` to pose `to`, both in the same world frame:
/// ⊖from ⊕ to (paper eq. 10's building block). T_from_to = T_w_from^-1 * T_w_to.
template <typename T>
Pose2T<T> between(const Pose2T<T>& T_w_from, const Pose2T<T>& T_w_to)
{
  return T_w_from.inverse() * T_w_to;
}

/// Motion of a rigidly mounted sensor given the motion of the body carrying it:
/// h = T_body_sensor^-1 * Delta_body * T_body_sensor (tricycle seed, "prediction function").
/// @param T_body_sensor the sensor's pose in the body frame
/// @param delta_body the body's motion, expressed in the body frame at the start
/// @return the sensor's motion, expressed in the sensor frame at the start
template <typename T>
Pose2T<T> sensorMotionFromBodyMotion(const Pose2T<T>& T_body_sensor, const Pose2T<T>& delta_body)
{
  return T_body_sensor.inverse() * delta_body * T_body_sensor;
}

/// Error between a predicted and a measured motion on SE(2), the seed's box-minus
/// e = Z^-1 * h as a vector (x [m], y [m], theta [rad]); zero when they agree.
template <typename T>
Eigen::Matrix<T, 3, 1> boxMinus(const Pose2T<T>& predicted, const Pose2T<T>& measured)
{
  return (measured.inverse() * predicted).vector();
}

/// The SE(2) exponential: the pose reached by moving for unit time at the constant body
/// velocity xi = (vx [m], vy [m], omega [rad]) along a circular arc: theta = omega,
/// t = V(theta) (vx, vy) with V as in se2Log (first-order terms below 1e-9 rad).
Pose2 se2Exp(const Eigen::Vector3d& xi);

/// The SE(2) logarithm: the constant body velocity (vx, vy, omega) times duration that moves
/// through `step` along a circular arc: t = V(θ) v with V = [sinθ/θ, -(1-cosθ)/θ; (1-cosθ)/θ,
/// sinθ/θ].
Eigen::Vector3d se2Log(const Pose2& step);

/// First-order covariance of a ⊕ d for independent a and d (Jacobians J_a = [I, R_a [-d_y, d_x]^T;
/// 0 1], J_d = diag(R_a, 1)).
Eigen::Matrix3d composeCovariance(const Pose2& a, const Eigen::Matrix3d& covariance_a,
                                  const Pose2& d, const Eigen::Matrix3d& covariance_d);

}  // namespace odometry_calibration
