// Decoded encoder values between two readings. Keyframes and sweeps fall between encoder
// messages; a robot that logs its wheels at 4 Hz changes speed within one reading interval, and
// a straight line between the readings then misplaces the wheel by up to a''·h²/8 (h the
// spacing, a'' the wheel's angular acceleration): on a simulated 4.5 Hz base that biased the
// fitted radii 0.5 % high. The default is a monotone cubic through the readings instead.
#pragma once

#include <algorithm>
#include <cmath>
#include <iterator>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// How a value between two encoder readings is taken.
enum class EncoderInterpolation
{
  kCubic,    ///< monotone cubic Hermite through the readings around it (the default)
  kLinear,   ///< linear in time between the two readings around it
  kNearest,  ///< the reading nearest in time (as pipelines that pair each scan with a reading)
};

/// A neighbouring reading further from its side of the interval than this many interval
/// lengths does not shape the slope there (a gap: the chord is used instead).
constexpr double kCubicNeighbourSpan = 2.0;

/// The derivative at t_i of the Lagrange polynomial through the readings `first` .. `last`
/// (t_i the stamp of `at`, one of them): sum over k of v_k L_k'(t_i), with
/// L_i'(t_i) = sum_{m != i} 1 / (t_i - t_m) and, for k != i,
/// L_k'(t_i) = prod_{m != k, i} (t_i - t_m) / prod_{m != k} (t_k - t_m).
template <class Iterator>
Eigen::VectorXd lagrangeDerivativeAt(Iterator first, Iterator last, Iterator at)
{
  Eigen::VectorXd slope = Eigen::VectorXd::Zero(at->values.size());
  const double t_i = at->stamp_s;
  for (Iterator k = first; k != std::next(last); ++k) {
    double weight = 0.0;
    if (k == at) {
      for (Iterator m = first; m != std::next(last); ++m)
        if (m != at)
          weight += 1.0 / (t_i - m->stamp_s);
    } else {
      double numerator = 1.0, denominator = 1.0;
      for (Iterator m = first; m != std::next(last); ++m) {
        if (m != k && m != at)
          numerator *= t_i - m->stamp_s;
        if (m != k)
          denominator *= k->stamp_s - m->stamp_s;
      }
      weight = numerator / denominator;
    }
    slope += weight * k->values;
  }
  return slope;
}

/// The slope of channel values at the reading `knot` of time-ordered `samples` for a cubic
/// Hermite interpolant on an interval of length h: the derivative of the polynomial through the
/// readings centred on it, two on each side (fourth order) where both are there, else one on
/// each side (exact for a quadratic), a neighbour further than kCubicNeighbourSpan h from the
/// next reading inwards ending the stencil (a gap). `fallback` (the interval's chord) where no
/// reading on one side is close enough.
template <class Samples>
Eigen::VectorXd centredKnotSlope(const Samples& samples, typename Samples::const_iterator knot,
                                 double h, const Eigen::VectorXd& fallback)
{
  int reach = 0;  // readings on each side that the stencil takes
  for (int side = 1; side <= 2; ++side) {
    const auto offset = static_cast<std::ptrdiff_t>(side);
    if (std::distance(samples.begin(), knot) < offset ||
        std::distance(knot, samples.end()) <= offset)
      break;
    const auto left = std::prev(knot, offset), right = std::next(knot, offset);
    if (std::next(left)->stamp_s - left->stamp_s > kCubicNeighbourSpan * h ||
        right->stamp_s - std::prev(right)->stamp_s > kCubicNeighbourSpan * h)
      break;
    reach = side;
  }
  if (reach == 0)
    return fallback;
  return lagrangeDerivativeAt(std::prev(knot, reach), std::next(knot, reach), knot);
}

/// Fritsch and Carlson's (1980) limit of a Hermite slope on an interval with the given chord
/// d, per channel: a slope of the chord's opposite sign (or any slope on a flat chord: a wheel
/// at rest) is 0, and each is at most 3 d, so that the cubic stays between the two readings and
/// does not invent motion.
inline void limitToMonotone(const Eigen::VectorXd& chord, Eigen::VectorXd* slope)
{
  for (Eigen::Index k = 0; k < chord.size(); ++k) {
    double& value = (*slope)(k);
    if (chord(k) == 0.0 || value * chord(k) <= 0.0)
      value = 0.0;
    else if (std::abs(value) > 3.0 * std::abs(chord(k)))
      value = 3.0 * chord(k);
  }
}

/// Decoded values at `stamp_s` in time-ordered `samples` (a vector or a deque), with `mode`:
/// kCubic the cubic Hermite p(u) = h00 v0 + h10 h m0 + h01 v1 + h11 h m1 (u = (t - t0) / h,
/// h00 = 2u³ - 3u² + 1, h10 = u³ - 2u² + u, h01 = -2u³ + 3u², h11 = u³ - u²) with the slopes of
/// monotoneHermiteSlopes; kLinear the chord; kNearest the nearest reading's values (stamped
/// `stamp_s`). Requires samples.front().stamp_s <= stamp_s <= samples.back().stamp_s.
template <class Samples>
EncoderSample interpolateEncoderSample(const Samples& samples, double stamp_s,
                                       EncoderInterpolation mode = EncoderInterpolation::kCubic)
{
  const auto after =
      std::lower_bound(samples.begin(), samples.end(), stamp_s,
                       [](const EncoderSample& sample, double t) { return sample.stamp_s < t; });
  if (after->stamp_s == stamp_s || after == samples.begin())
    return *after;
  const auto before = std::prev(after);
  if (mode == EncoderInterpolation::kNearest) {
    const bool before_nearer = stamp_s - before->stamp_s <= after->stamp_s - stamp_s;
    return {stamp_s, before_nearer ? before->values : after->values};
  }
  const double h = after->stamp_s - before->stamp_s;
  const double u = (stamp_s - before->stamp_s) / h;
  if (mode == EncoderInterpolation::kLinear)
    return {stamp_s, before->values + u * (after->values - before->values)};
  const Eigen::VectorXd chord = (after->values - before->values) / h;
  Eigen::VectorXd m0 = centredKnotSlope(samples, before, h, chord);
  Eigen::VectorXd m1 = centredKnotSlope(samples, after, h, chord);
  limitToMonotone(chord, &m0);
  limitToMonotone(chord, &m1);
  const double u2 = u * u, u3 = u2 * u;
  return {stamp_s, (2.0 * u3 - 3.0 * u2 + 1.0) * before->values + (u3 - 2.0 * u2 + u) * h * m0 +
                       (3.0 * u2 - 2.0 * u3) * after->values + (u3 - u2) * h * m1};
}

}  // namespace odometry_calibration
