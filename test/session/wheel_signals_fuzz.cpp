// Fuzz target: the wheels' signals other than JointState positions (session/wheel_signals.h) as
// bytes, through the tick unwrapping and alignment or the velocity integration into the pair
// collector (its glitch filter and the diff_drive prior's guesses) of config/diff_drive.yaml. The
// first byte picks the source (even: ticks, odd: joint velocities) and the counters' width (8, 16
// or 0 bits); then records of 11 bytes: the wheel (a byte), the step to the previous stamp (int16,
// 0.1 ms: negative is time going backwards) and the value (a double's raw bits: NaN, 1e308 and the
// like included). The joint samples that come out must be finite and never go back in time
// without a problem said.
#include <cmath>
#include <cstdint>
#include <cstring>
#include <stdexcept>

#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/session/wheel_signals.h"

#include "support/fuzz_config.h"

using namespace odometry_calibration;

namespace {

constexpr std::size_t kRecordBytes = 11;

/// The configuration of the first byte: diff_drive.yaml with its wheels from ticks of `bits`
/// bits or from joint velocities.
CalibrationConfig wheelConfig(std::uint8_t first)
{
  CalibrationConfig config = test::diffDriveFuzzConfig();
  const int widths[] = {8, 16, 0};
  if (first % 2 == 0) {
    config.wheels.source = WheelSource::kTicks;
    config.wheels.topics = {"/lwheel", "/rwheel"};
    config.wheels.message_type = "std_msgs/Int64";
    for (JointConfig& joint : config.joints)
      joint.counter_bits = widths[(first / 2) % 3];
  } else {
    config.wheels.source = WheelSource::kJointVelocity;
  }
  return config;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  if (size < 1)
    return 0;
  const CalibrationConfig config = wheelConfig(data[0]);
  WheelSignals signals(config);
  PairCollector collector(encoderChannels(config), config.collector, priorPredictor(config));
  double stamp_s = 100.0, last_out_s = -INFINITY;
  for (std::size_t at = 1; at + kRecordBytes <= size; at += kRecordBytes) {
    const std::size_t wheel = data[at] % 3;  // 2: a wheel beyond the joints
    std::int16_t step = 0;
    double value = 0.0;
    std::memcpy(&step, data + at + 1, sizeof(step));
    std::memcpy(&value, data + at + 3, sizeof(value));
    stamp_s += 1e-4 * step;
    const WheelSignalOutput output =
        config.wheels.source == WheelSource::kTicks
            ? signals.addTick(wheel, stamp_s, value)
            : signals.addVelocities(stamp_s, Eigen::Vector2d(value, 0.5 * value));
    if (!output.problem.empty())
      last_out_s = -INFINITY;  // a restart may have been said
    for (const EncoderSample& sample : output.samples) {
      if (!sample.values.allFinite() || !std::isfinite(sample.stamp_s))
        __builtin_trap();  // a wheel signal made a number that is not one
      if (sample.stamp_s < last_out_s && output.problem.empty())
        __builtin_trap();  // back in time without a restart said
      last_out_s = sample.stamp_s;
      try {
        collector.addEncoders(sample.stamp_s, sample.values);
      } catch (const std::invalid_argument&) {
        // the collector's own refusals (time going backwards after a restart) are fine
      }
    }
  }
  return 0;
}
