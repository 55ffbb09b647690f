// The spacing of a stream's stamps as the data shows it, for the limits that must follow the
// data's rate (the encoder gap a keyframe tolerates, the shortest useful keyframe interval).
#pragma once

#include <cstddef>
#include <vector>

namespace odometry_calibration {

/// The median of the last `capacity` positive differences between consecutive stamps. A
/// stamp at or before the previous one adds no spacing (a repeated stamp, or time going
/// backwards: the next difference starts from it).
class StreamSpacing
{
public:
  explicit StreamSpacing(std::size_t capacity = 101);

  void add(double stamp_s);
  /// How many spacings the median is over (at most the capacity).
  std::size_t count() const { return spacings_s_.size(); }
  /// The median spacing [s]; NaN before the second stamp.
  double median_s() const;
  void clear();

private:
  std::size_t capacity_;
  std::vector<double> spacings_s_;  ///< a ring once full
  std::size_t next_ = 0;            ///< where the next spacing goes once full
  double last_stamp_s_;
  mutable double median_s_;  ///< cached; NaN: to compute
};

}  // namespace odometry_calibration
