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

/// The slopes of channel values at the readings `before` (time t0) and `after` (t1) for a cubic
/// Hermite interpolant: centred differences (v_after - v_prev) / (t_after - t_prev) and
/// (v_next - v_before) / (t_next - t_before), with `prev` / `next` null (or beyond
/// kCubicNeighbourSpan intervals) giving the chord d = (v1 - v0) / (t1 - t0). Limited as in
/// Fritsch and Carlson (1980), "Monotone piecewise cubic interpolation": a slope of the
/// chord's opposite sign (or any slope on a flat chord: a wheel at rest) is 0, and each is at
/// most 3 d, so that the cubic stays between the two readings and does not invent motion.
inline void monotoneHermiteSlopes(const EncoderSample* prev, const EncoderSample& before,
                                  const EncoderSample& after, const EncoderSample* next,
                                  Eigen::VectorXd* slope_before, Eigen::VectorXd* slope_after)
{
  const double h = after.stamp_s - before.stamp_s;
  const Eigen::VectorXd chord = (after.values - before.values) / h;
  *slope_before = chord;
  *slope_after = chord;
  if (prev && before.stamp_s - prev->stamp_s <= kCubicNeighbourSpan * h)
    *slope_before = (after.values - prev->values) / (after.stamp_s - prev->stamp_s);
  if (next && next->stamp_s - after.stamp_s <= kCubicNeighbourSpan * h)
    *slope_after = (next->values - before.values) / (next->stamp_s - before.stamp_s);
  for (Eigen::Index k = 0; k < chord.size(); ++k) {
    for (double* slope : {&(*slope_before)(k), &(*slope_after)(k)}) {
      if (chord(k) == 0.0 || *slope * chord(k) <= 0.0)
        *slope = 0.0;
      else if (std::abs(*slope) > 3.0 * std::abs(chord(k)))
        *slope = 3.0 * chord(k);
    }
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
  const EncoderSample* prev = before == samples.begin() ? nullptr : &*std::prev(before);
  const EncoderSample* next = std::next(after) == samples.end() ? nullptr : &*std::next(after);
  Eigen::VectorXd m0, m1;
  monotoneHermiteSlopes(prev, *before, *after, next, &m0, &m1);
  const double u2 = u * u, u3 = u2 * u;
  return {stamp_s, (2.0 * u3 - 3.0 * u2 + 1.0) * before->values + (u3 - 2.0 * u2 + u) * h * m0 +
                       (3.0 * u2 - 2.0 * u3) * after->values + (u3 - u2) * h * m1};
}

}  // namespace odometry_calibration
