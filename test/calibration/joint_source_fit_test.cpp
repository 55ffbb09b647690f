// The joint fit of several ego-motion sources as the node's session and calibrate_bag call it
// (issue 35), for the skid-steer and tricycle configurations shipped in config/: simulated
// pairs of a front and a rear laser, each sensor's view as a model, the joint result.yaml.
#include "odometry_calibration/calibration/joint_source_fit.h"

#include <cmath>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const Pose2 kFront(0.30, 0.0, 0.0);
const Pose2 kRear(-0.30, 0.02, M_PI + 0.03);

/// Source `name`'s input: the pairs of a sensor at `T_base_sensor` on `robot` (seed `seed`, 2 mm
/// / 2 mrad noise), fitted at 0.5 s, started at `start`.
JointSourceInput source(const std::string& name, const sim::RobotOptions& robot,
                        const Pose2& T_base_sensor, unsigned seed, const Pose2& start,
                        sim::GeneratedPairs* generated)
{
  sim::PairGeneratorOptions options;
  options.robot = robot;
  options.T_base_sensor = T_base_sensor;
  options.duration_s = 120.0;
  options.interval_s = 0.5;
  options.motion.max_speed_mps = 0.6;
  options.motion.max_turn_rate_radps = 0.5;
  options.seed = seed;
  *generated = sim::generatePairs(options);
  return {"/scan_" + name, "laser_" + name, generated->pairs, start, 0.01, 0.5};
}

/// The largest translation error of `model`'s predictions against the noise-free motions [m].
double largestPredictionError(const MotionModel& model, const sim::GeneratedPairs& data)
{
  double largest = 0.0;
  for (std::size_t i = 0; i < data.pairs.size(); ++i) {
    const Pose2 predicted = model.predict(data.pairs[i].encoder_samples).mean;
    largest = std::max(largest, boxMinus(predicted, data.true_motions[i]).head<2>().norm());
  }
  return largest;
}

TEST(JointSourceFit, SkidSteerSourcesGiveEachSensorsModelAndTheJointResult)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/skid_steer.yaml");
  ASSERT_EQ(config.model, "skid_steer");
  EXPECT_EQ(jointFitModelProblem("skid_steer"), "");
  const sim::RobotOptions robot{"skid_steer",
                                {{"wheel_radius_left_m", 0.1},
                                 {"wheel_radius_right_m", 0.101},
                                 {"effective_separation_factor", 1.5}}};
  sim::GeneratedPairs front, rear;
  const std::vector<JointSourceInput> sources = {
      source("front", robot, kFront, 371, Pose2(0.25, 0.0, 0.0), &front),
      source("rear", robot, kRear, 372, Pose2(-0.25, 0.0, M_PI), &rear)};
  const JointFitReport joint = fitSourcesJointly(config, sources);
  ASSERT_TRUE(joint.converged) << joint.termination;
  EXPECT_EQ(joint.model, "skid_steer");
  EXPECT_NEAR(joint.intrinsics[2].value, 0.75, 0.002 * 0.75);
  // Each sensor's view is a skid_steer model with the joint sides and its own pose: it predicts
  // its own sensor's motions within a few mm.
  const auto rear_model = jointSensorModel(config, joint, 1);
  EXPECT_EQ(rear_model->name(), "skid_steer");
  EXPECT_LT(largestPredictionError(*rear_model, rear), 0.005);
  EXPECT_LT(largestPredictionError(*jointSensorModel(config, joint, 0), front), 0.005);
  // The front sensor's view predicts the rear's motions badly: the poses differ.
  EXPECT_GT(largestPredictionError(*jointSensorModel(config, joint, 0), rear), 0.05);

  // result.yaml: the first sensor's view loads as a one-source result with its fit interval;
  // every sensor is under `sensors:` with its own.
  const std::string text = jointResultYaml(config, joint, sources, "test.bag");
  const CalibrationResult loaded = parseCalibrationResult(text, "result.yaml");
  ASSERT_TRUE(loaded.model);
  EXPECT_EQ(loaded.model->name(), "skid_steer");
  EXPECT_DOUBLE_EQ(loaded.fit_interval_s, 0.5);
  EXPECT_NEAR(loaded.T_base_sensor.x(), joint.sensors[0].T_base_sensor.x(), 1e-9);
  EXPECT_NE(text.find("wheel_separation_multiplier"), std::string::npos);
  const YAML::Node sensors = YAML::Load(text)["sensors"];
  ASSERT_EQ(sensors.size(), 2u);
  EXPECT_EQ(sensors[1]["frame"].as<std::string>(), "laser_rear");
  EXPECT_DOUBLE_EQ(sensors[1]["fit_interval_s"].as<double>(), 0.5);
  EXPECT_NEAR(sensors[1]["T_base_sensor"]["theta_rad"].as<double>(),
              joint.sensors[1].T_base_sensor.theta(), 1e-9);
}

TEST(JointSourceFit, TricycleSourcesGiveEachSensorsModel)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/tricycle.yaml");
  ASSERT_EQ(config.model, "tricycle");
  const sim::RobotOptions robot{"tricycle", {{"steering_offset_rad", -0.064}}};
  const Pose2 front_truth(1.80, -0.015, -0.008);
  sim::GeneratedPairs front, rear;
  const std::vector<JointSourceInput> sources = {
      source("front", robot, front_truth, 373, Pose2(1.5, 0.0, 0.0), &front),
      source("rear", robot, kRear, 374, Pose2(-0.2, 0.0, M_PI), &rear)};
  const JointFitReport joint = fitSourcesJointly(config, sources);
  ASSERT_TRUE(joint.converged) << joint.termination;
  EXPECT_NEAR(joint.intrinsics[2].value, 1.54, 0.005 * 1.54);  // the simulator's axis length
  const auto rear_model = jointSensorModel(config, joint, 1);
  EXPECT_EQ(rear_model->name(), "tricycle");
  // Within 1 cm at worst (the front laser is 1.8 m ahead of the rear axle: a small heading error
  // of the prediction moves it most).
  EXPECT_LT(largestPredictionError(*rear_model, rear), 0.01);
  EXPECT_LT(largestPredictionError(*jointSensorModel(config, joint, 0), front), 0.01);
  const CalibrationResult loaded =
      parseCalibrationResult(jointResultYaml(config, joint, sources, "test.bag"), "result.yaml");
  ASSERT_TRUE(loaded.model);
  EXPECT_EQ(loaded.model->name(), "tricycle");
  EXPECT_NEAR(loaded.T_base_sensor.x(), front_truth.x(), 0.005);
}

TEST(JointSourceFit, NamesTheSourceWhosePairsCannotBeFittedAndTheModelWithoutAJointFit)
{
  CalibrationConfig config = loadCalibrationConfig(kConfig + "/tricycle.yaml");
  sim::GeneratedPairs front, rear;
  std::vector<JointSourceInput> sources = {
      source("front", {"tricycle", {}}, Pose2(1.8, 0.0, 0.0), 375, Pose2(1.5, 0.0, 0.0), &front),
      source("rear", {"tricycle", {}}, kRear, 376, Pose2(-0.2, 0.0, M_PI), &rear)};
  sources[1].pairs.resize(3);
  try {
    fitSourcesJointly(config, sources);
    FAIL() << "3 pairs of the rear laser accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("sensor 1 ('/scan_rear') needs at least 7"),
              std::string::npos)
        << error.what();
  }
  config.model = "gp";
  try {
    fitSourcesJointly(config, sources);
    FAIL() << "a joint gp fit accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("model 'gp' has no joint fit"), std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace odometry_calibration
