#include "odometry_calibration/scan/point_times.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {

double secondsPer(PointTimeUnit unit)
{
  switch (unit) {
    case PointTimeUnit::kMilliseconds:
      return 1e-3;
    case PointTimeUnit::kMicroseconds:
      return 1e-6;
    case PointTimeUnit::kNanoseconds:
      return 1e-9;
    default:
      return 1.0;
  }
}

}  // namespace

void validate(const PointTimeOptions& options)
{
  if (!(std::isfinite(options.limit_s) && options.limit_s > 0.0))
    throw std::invalid_argument("cloud point_time_limit_s must be > 0 s");
}

const char* toString(PointTimeUnit unit)
{
  switch (unit) {
    case PointTimeUnit::kSeconds:
      return "s";
    case PointTimeUnit::kMilliseconds:
      return "ms";
    case PointTimeUnit::kMicroseconds:
      return "us";
    case PointTimeUnit::kNanoseconds:
      return "ns";
    default:
      return "auto";
  }
}

const char* toString(PointTimeReference reference)
{
  switch (reference) {
    case PointTimeReference::kRelative:
      return "relative";
    case PointTimeReference::kAbsolute:
      return "absolute";
    default:
      return "auto";
  }
}

PointTimeUnit pointTimeUnitName(const std::string& name)
{
  for (PointTimeUnit unit :
       {PointTimeUnit::kAuto, PointTimeUnit::kSeconds, PointTimeUnit::kMilliseconds,
        PointTimeUnit::kMicroseconds, PointTimeUnit::kNanoseconds}) {
    if (name == toString(unit))
      return unit;
  }
  throw std::invalid_argument("cloud point_time_unit must be auto, s, ms, us or ns, got '" + name +
                              "'");
}

PointTimeReference pointTimeReferenceName(const std::string& name)
{
  for (PointTimeReference reference :
       {PointTimeReference::kAuto, PointTimeReference::kRelative, PointTimeReference::kAbsolute}) {
    if (name == toString(reference))
      return reference;
  }
  throw std::invalid_argument(
      "cloud point_time_reference must be auto, relative or absolute, got '" + name + "'");
}

const std::vector<std::string>& defaultPointTimeFields()
{
  static const std::vector<std::string> names = {"time", "t", "timestamp"};
  return names;
}

PointTimeConversion toTimesAfterStamp(std::vector<double>& values, bool integer_field,
                                      double stamp_s, const PointTimeOptions& options)
{
  PointTimeConversion result;
  result.unit = options.unit;
  result.reference = options.reference;
  if (result.unit == PointTimeUnit::kAuto || result.reference == PointTimeReference::kAuto) {
    // The median of the finite values decides (robust to a few bad points).
    std::vector<double> finite;
    finite.reserve(values.size());
    for (const double v : values) {
      if (std::isfinite(v))
        finite.push_back(v);
    }
    const double median = finite.empty() ? 0.0 : [&] {
      auto middle = finite.begin() + static_cast<std::ptrdiff_t>(finite.size() / 2);
      std::nth_element(finite.begin(), middle, finite.end());
      return *middle;
    }();
    if (result.unit == PointTimeUnit::kAuto) {
      // Floating absolute nanoseconds since the epoch (Livox) are ~1.7e18; seconds ~1.7e9.
      result.unit = integer_field || std::abs(median) > 1e12 ? PointTimeUnit::kNanoseconds
                                                             : PointTimeUnit::kSeconds;
    }
    if (result.reference == PointTimeReference::kAuto) {
      const double median_s = median * secondsPer(result.unit);
      result.reference = std::abs(median_s - stamp_s) < std::abs(median_s)
                             ? PointTimeReference::kAbsolute
                             : PointTimeReference::kRelative;
    }
  }
  const double scale = secondsPer(result.unit);
  const double offset_s = result.reference == PointTimeReference::kAbsolute ? stamp_s : 0.0;
  for (std::size_t i = 0; i < values.size(); ++i) {
    const double t = values[i] * scale - offset_s;
    if (!(std::abs(t) <= options.limit_s)) {
      std::ostringstream text;
      text << "point " << i << "'s time ";
      if (std::isfinite(values[i])) {
        text << "is " << t << " s from the stamp, beyond the " << options.limit_s
             << " s a sweep can last";
      } else {
        text << "is " << values[i];
      }
      text << " (read as " << toString(result.reference) << " " << toString(result.unit) << ")";
      result.problem = text.str();
      return result;
    }
    values[i] = t;
  }
  return result;
}

}  // namespace odometry_calibration
