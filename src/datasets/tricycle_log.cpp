#include "odometry_calibration/datasets/tricycle_log.h"

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/data/reference_pairs.h"

namespace odometry_calibration {
namespace {

/// Throws std::invalid_argument "header '#<line>': <name> = <value> is outside [min, max]
/// <unit> ..." for a header value no tricycle has (the same ranges as the configuration's
/// tricycle section): a start value of 1e308 would only make a fit that cannot be trusted.
void requireHeaderValue(const std::string& line, const std::string& name, double value, double min,
                        double max, const std::string& unit)
{
  if (value >= min && value <= max)  // false for NaN
    return;
  std::ostringstream message;
  message << "header '#" << line << "': " << name << " = " << value << " is outside [" << min
          << ", " << max << "]" << (unit.empty() ? "" : " " + unit)
          << ", the range of a real tricycle: correct the log's header";
  throw std::invalid_argument(message.str());
}

}  // namespace

TricycleEncoderLayout tricycleLayoutFromHeader(const TricycleDatasetHeader& header)
{
  if (header.joint_max_values.size() != 2) {
    throw std::invalid_argument(
        "header line '#joints_max_enc_values: <steering> <traction>' with two values is missing");
  }
  TricycleEncoderLayout layout;
  layout.steering_index = 0;
  layout.traction_index = 1;
  if (header.joint_names.size() == 2 &&
      header.joint_names[0].find("traction") != std::string::npos) {
    std::swap(layout.steering_index, layout.traction_index);
  }
  layout.steering_ticks_per_turn = header.joint_max_values[layout.steering_index];
  layout.traction_ticks_per_turn = header.joint_max_values[layout.traction_index];
  layout.steering_at_step_end = true;  // the seed robot's odometry convention
  // Ticks per turn: from a 1-tick switch to a 32-bit counter's full range.
  requireHeaderValue("joints_max_enc_values", "steering ticks per turn",
                     layout.steering_ticks_per_turn, 1.0, 4294967296.0, "ticks");
  requireHeaderValue("joints_max_enc_values", "traction ticks per turn",
                     layout.traction_ticks_per_turn, 1.0, 4294967296.0, "ticks");
  return layout;
}

TricycleParameters tricycleNominalFromHeader(const TricycleDatasetHeader& header)
{
  if (header.parameter_values.size() != 4) {
    throw std::invalid_argument(
        "header line '#parameter_values: <Ksteer> <Ktraction> <axis_length> <steer_offset>' "
        "with four values is missing");
  }
  static const char* kNames[] = {"Ksteer", "Ktraction", "axis_length", "steer_offset"};
  const double kMin[] = {1e-4, 1e-6, 0.01, -M_PI};
  const double kMax[] = {100.0, 100.0, 50.0, M_PI};
  const char* kUnits[] = {"", "", "m", "rad"};
  for (std::size_t i = 0; i < 4; ++i) {
    // By position, as the format defines them (the '#parameters' names are not checked).
    requireHeaderValue("parameter_values", kNames[i], header.parameter_values[i], kMin[i], kMax[i],
                       kUnits[i]);
  }
  TricycleParameters nominal = TricycleParameters::fromVectors(
      Eigen::Vector4d(header.parameter_values.data()), Eigen::Vector3d::Zero());
  if (!header.has_sensor_pose) {
    throw std::invalid_argument(
        "header lines '#laser wrt base_link' / translation / rotation are missing");
  }
  // Where the laser sits: within 100 m of the base, as the configuration's sensor_pose.
  requireHeaderValue("laser wrt base_link", "translation x", header.T_base_sensor.x(), -100.0,
                     100.0, "m");
  requireHeaderValue("laser wrt base_link", "translation y", header.T_base_sensor.y(), -100.0,
                     100.0, "m");
  nominal.T_base_sensor = header.T_base_sensor;
  return nominal;
}

std::vector<EncoderSample> decodeTricycleEncoders(const TricycleDataset& dataset,
                                                  const TricycleEncoderLayout& layout)
{
  std::vector<EncoderChannelOptions> channels(2);
  channels[layout.steering_index] = {"steering", EncoderKind::kAbsolute, 0.0,
                                     layout.steering_ticks_per_turn};
  channels[layout.traction_index] = {"traction", EncoderKind::kIncremental, 4294967296.0, 0.0};
  EncoderDecoder decoder(channels);
  std::vector<EncoderSample> samples;
  samples.reserve(dataset.rows.size());
  for (const TricycleDatasetRow& row : dataset.rows) {
    Eigen::VectorXd raw(2);
    raw(layout.steering_index) = row.steering_ticks;
    raw(layout.traction_index) = row.traction_ticks;
    samples.push_back({row.stamp_s, decoder.decode(raw)});
  }
  return samples;
}

std::vector<MotionPair> tricyclePairs(const TricycleDataset& dataset,
                                      const std::vector<EncoderSample>& samples, double interval_s,
                                      const Eigen::Matrix3d& covariance)
{
  if (samples.size() != dataset.rows.size()) {
    throw std::invalid_argument("tricyclePairs: one decoded sample per dataset row expected");
  }
  return referencePairs(samples, tricycleTrackerPoses(dataset), interval_s, covariance);
}

std::vector<Pose2> tricycleTrackerPoses(const TricycleDataset& dataset)
{
  std::vector<Pose2> poses;
  poses.reserve(dataset.rows.size());
  for (const TricycleDatasetRow& row : dataset.rows) {
    poses.push_back(row.T_world_sensor);
  }
  return poses;
}

}  // namespace odometry_calibration
