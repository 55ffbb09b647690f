#include "odometry_calibration/models/skid_steer_model.h"

#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

#include "odometry_calibration/models/model_checks.h"
#include "odometry_calibration/models/model_yaml.h"

namespace odometry_calibration {

void validate(const SkidSteerOptions& o)
{
  if (o.left_indices.empty() || o.right_indices.empty()) {
    throw std::invalid_argument("skid_steer needs at least one wheel joint on each side");
  }
  for (int left : o.left_indices) {
    if (left < 0)
      throw std::invalid_argument("skid_steer: negative joint index");
    for (int right : o.right_indices) {
      if (right < 0 || right == left) {
        throw std::invalid_argument("skid_steer: a joint cannot be on both sides");
      }
    }
  }
  requirePositiveOption(o.ticks_per_turn, "skid_steer", "ticks_per_turn");
  requirePositiveOption(o.wheel_radius_m, "skid_steer", "wheel_radius_m");
  requirePositiveOption(o.wheel_separation_m, "skid_steer", "wheel_separation_m");
  requirePositiveOption(o.huber_threshold, "skid_steer", "huber_threshold");
  requireSolverLimits(o.max_iterations, o.yaw_starts, "skid_steer");
}

std::vector<EncoderSample> averageSides(const std::vector<EncoderSample>& samples,
                                        const std::vector<int>& left_indices,
                                        const std::vector<int>& right_indices)
{
  std::vector<int> all = left_indices;
  all.insert(all.end(), right_indices.begin(), right_indices.end());
  requireJointIndices(samples, all, "skid_steer", "wheel joints");
  auto mean = [](const Eigen::VectorXd& values, const std::vector<int>& indices) {
    double sum = 0.0;
    for (int index : indices)
      sum += values(index);
    return sum / static_cast<double>(indices.size());
  };
  std::vector<EncoderSample> sides;
  sides.reserve(samples.size());
  for (const EncoderSample& sample : samples) {
    sides.push_back({sample.stamp_s, Eigen::Vector2d(mean(sample.values, left_indices),
                                                     mean(sample.values, right_indices))});
  }
  return sides;
}

std::vector<MotionPair> averageSidesOfPairs(const std::vector<MotionPair>& pairs,
                                            const SkidSteerOptions& options)
{
  std::vector<MotionPair> sides = pairs;
  for (MotionPair& pair : sides) {
    if (pair.encoder_samples.size() < 2) {
      throw std::invalid_argument("skid_steer: every pair needs two or more encoder samples");
    }
    pair.encoder_samples =
        averageSides(pair.encoder_samples, options.left_indices, options.right_indices);
  }
  return sides;
}

std::vector<ParameterEstimate> skidSteerMultipliers(const std::vector<ParameterEstimate>& effective,
                                                    const SkidSteerOptions& options)
{
  if (effective.size() < 3)
    throw std::invalid_argument("skidSteerMultipliers: needs the radii and the separation");
  const double geometric[3] = {options.wheel_radius_m, options.wheel_radius_m,
                               options.wheel_separation_m};
  const char* names[3] = {"left_wheel_radius_multiplier", "right_wheel_radius_multiplier",
                          "wheel_separation_multiplier"};
  std::vector<ParameterEstimate> multipliers;
  for (int i : {2, 0, 1}) {
    multipliers.push_back({names[i], "-", effective[i].initial / geometric[i],
                           effective[i].value / geometric[i], effective[i].sigma / geometric[i]});
  }
  return multipliers;
}

DiffDriveOptions skidSteerVirtualWheels(const SkidSteerOptions& o)
{
  validate(o);
  DiffDriveOptions wheels;
  wheels.layout = {0, 1, o.ticks_per_turn};
  wheels.initial_left_radius_m = wheels.initial_right_radius_m = o.wheel_radius_m;
  wheels.initial_separation_m = o.wheel_separation_m;
  wheels.initial_T_base_sensor = o.initial_T_base_sensor;
  wheels.huber_threshold = o.huber_threshold;
  wheels.max_iterations = o.max_iterations;
  wheels.yaw_starts = o.yaw_starts;
  return wheels;
}

SkidSteerModel::SkidSteerModel(SkidSteerOptions options)
    : options_(std::move(options)), wheels_(skidSteerVirtualWheels(options_))
{
}

SkidSteerModel::SkidSteerModel(SkidSteerOptions options, DiffDriveModel wheels)
    : options_(std::move(options)), wheels_(std::move(wheels))
{
  validate(options_);
}

ModelReport SkidSteerModel::fit(const std::vector<MotionPair>& pairs)
{
  ModelReport report = wheels_.fit(averageSidesOfPairs(pairs, options_));
  report.model = name();
  // The multipliers a diff_drive_controller applies to its geometric values.
  const std::vector<ParameterEstimate> multipliers =
      skidSteerMultipliers(report.parameters, options_);
  report.parameters.insert(report.parameters.end(), multipliers.begin(), multipliers.end());
  return report;
}

MotionPrediction SkidSteerModel::predict(const std::vector<EncoderSample>& samples) const
{
  if (samples.size() < 2) {
    throw std::invalid_argument("skid_steer prediction needs at least two encoder samples");
  }
  return wheels_.predict(averageSides(samples, options_.left_indices, options_.right_indices));
}

namespace {

/// The values a skid_steer model saves besides its sides' differential drive, each key once:
/// the joints of each side and the geometric values its multipliers refer to.
template <class Options, class Visit>
void visitSkidSteerYaml(Options& options, const Visit& visit)
{
  visit("left_indices", options.left_indices);
  visit("right_indices", options.right_indices);
  visit("geometric_wheel_radius_m", options.wheel_radius_m);
  visit("geometric_wheel_separation_m", options.wheel_separation_m);
}

}  // namespace

std::string SkidSteerModel::toYaml() const
{
  return writeModelYaml(name(), [this](YAML::Emitter& out) {
    visitSkidSteerYaml(options_, YamlKeyWriter(out));
    out << YAML::Key << "sides" << YAML::Value << YAML::Load(wheels_.toYaml());
  });
}

SkidSteerModel SkidSteerModel::fromYaml(const std::string& text)
{
  try {
    return readModelYaml(text, "skid_steer", [](const YAML::Node& node) {
      std::ostringstream sides;
      sides << node["sides"];
      DiffDriveModel wheels = DiffDriveModel::fromYaml(sides.str());
      SkidSteerOptions options;
      visitSkidSteerYaml(options, YamlKeyReader(node));
      options.ticks_per_turn = YAML::Load(sides.str())["ticks_per_turn"].as<double>();
      options.initial_T_base_sensor = wheels.T_base_sensor();
      return SkidSteerModel(options, std::move(wheels));
    });
  } catch (const std::invalid_argument& error) {
    throw std::runtime_error(std::string("skid_steer model YAML: ") + error.what());
  }
}

}  // namespace odometry_calibration
