// Per-point time stamps of a 3D lidar's cloud, as drivers write them, turned into the seconds
// after the cloud's stamp that the sweep compensation uses.
//
// Drivers differ: Velodyne's `time` is FLOAT32 seconds after the cloud's stamp, Ouster's `t`
// UINT32 nanoseconds after it, Hesai's `timestamp` FLOAT64 absolute seconds (epoch), Livox's
// `timestamp` FLOAT64 absolute nanoseconds. By default the unit and the reference are told from
// the field's type and values; both can be set (config ego_motion.cloud.point_time_*). Times
// that cannot be right (not finite, or farther from the stamp than any sweep lasts) make the
// whole cloud's times unusable: the cloud is then matched without sweep compensation and the
// caller counts and names the problem, rather than compensating with wrong times.
#pragma once

#include <string>
#include <vector>

namespace odometry_calibration {

/// Unit of the raw values of the time field.
enum class PointTimeUnit
{
  kAuto,  ///< integer fields: ns; floating fields: s, or ns for absolute values beyond 1e12
  kSeconds,
  kMilliseconds,
  kMicroseconds,
  kNanoseconds,
};

/// What the raw values count from.
enum class PointTimeReference
{
  kAuto,      ///< absolute when the values' median lies nearer the stamp than zero
  kRelative,  ///< after the cloud's header stamp
  kAbsolute,  ///< the same clock as the header stamp (e.g. seconds since the epoch)
};

/// Config keys ego_motion.cloud.point_time_field, point_time_unit, point_time_reference,
/// point_time_limit_s.
struct PointTimeOptions
{
  /// The field holding the times; empty: the first of `time`, `t`, `timestamp` the cloud has.
  std::string field;
  PointTimeUnit unit = PointTimeUnit::kAuto;
  PointTimeReference reference = PointTimeReference::kAuto;
  /// A time farther than this from the stamp (either side) is wrong: no lidar sweep lasts that
  /// long [s].
  double limit_s = 0.5;
};

/// Throws std::invalid_argument naming the offending option.
void validate(const PointTimeOptions& options);

const char* toString(PointTimeUnit unit);            ///< auto | s | ms | us | ns
const char* toString(PointTimeReference reference);  ///< auto | relative | absolute
/// Parse the names above; throw std::invalid_argument listing the choices otherwise.
PointTimeUnit pointTimeUnitName(const std::string& name);
PointTimeReference pointTimeReferenceName(const std::string& name);

/// The field names tried, in order, when PointTimeOptions::field is empty.
const std::vector<std::string>& defaultPointTimeFields();

/// What toTimesAfterStamp made of the values.
struct PointTimeConversion
{
  PointTimeUnit unit = PointTimeUnit::kAuto;                 ///< the unit used (never kAuto)
  PointTimeReference reference = PointTimeReference::kAuto;  ///< the reference used
  /// Empty when every time is usable; else why the cloud's times are not (e.g. "point 12's
  /// time is NaN"), naming the interpretation.
  std::string problem;

  bool usable() const { return problem.empty(); }
};

/// Turns the raw values of a time field (as read, in the field's unit; `integer_field` for the
/// INT/UINT types) into seconds after `stamp_s` in place: t = v * unit - (absolute ? stamp : 0).
/// The unit and the reference come from `options`, or from the field's type and the median of
/// the values when kAuto (see the enums). Every converted time must be finite and within
/// +-limit_s of the stamp; otherwise `problem` says which point failed (the values are then
/// left half converted: do not use them). An empty `values` is usable.
PointTimeConversion toTimesAfterStamp(std::vector<double>& values, bool integer_field,
                                      double stamp_s, const PointTimeOptions& options);

}  // namespace odometry_calibration
