#include "odometry_calibration/data/stream_spacing.h"

#include <cmath>
#include <limits>

#include "odometry_calibration/common/median.h"

namespace odometry_calibration {

namespace {
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
}  // namespace

StreamSpacing::StreamSpacing(std::size_t capacity)
    : capacity_(capacity > 0 ? capacity : 1), last_stamp_s_(kNaN), median_s_(kNaN)
{
}

void StreamSpacing::add(double stamp_s)
{
  if (!std::isfinite(stamp_s))
    return;
  const double spacing_s = stamp_s - last_stamp_s_;
  last_stamp_s_ = stamp_s;
  if (!(spacing_s > 0.0))
    return;  // the first stamp, a repeated one, or time going backwards
  if (spacings_s_.size() < capacity_) {
    spacings_s_.push_back(spacing_s);
  } else {
    spacings_s_[next_] = spacing_s;
    next_ = (next_ + 1) % capacity_;
  }
  median_s_ = kNaN;
}

double StreamSpacing::median_s() const
{
  if (spacings_s_.empty())
    return kNaN;
  if (std::isnan(median_s_))
    median_s_ = median(spacings_s_);
  return median_s_;
}

void StreamSpacing::clear()
{
  spacings_s_.clear();
  next_ = 0;
  last_stamp_s_ = median_s_ = kNaN;
}

}  // namespace odometry_calibration
