#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/models/tricycle_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

/// The tricycle of the seed's real log (roughly), driving at random for 3 minutes.
sim::GeneratedPairs tricyclePairs(unsigned seed = 4, double encoder_rate_hz = 50.0)
{
  sim::PairGeneratorOptions options;
  options.robot = {"tricycle",
                   {{"steering_scale", 0.56},
                    {"traction_scale_m_per_turn", 0.0106},
                    {"axis_length_m", 1.54},
                    {"steering_offset_rad", -0.064}}};
  options.T_base_sensor = Pose2(1.80, -0.015, -0.008);
  options.motion.max_speed_mps = 0.8;
  options.motion.max_turn_rate_radps = 0.5;
  options.duration_s = 180.0;
  options.interval_s = 0.5;
  options.seed = seed;
  options.encoder_rate_hz = encoder_rate_hz;
  return sim::generatePairs(options);
}

const char* kConfig =
    "joints:\n"
    "  - {name: steering, kind: absolute, units_per_turn: 8192}\n"
    "  - {name: traction_wheel, kind: incremental, units_per_turn: 5000, counter_bits: 32}\n"
    "model: tricycle\n"
    "prior_model: tricycle\n"
    "tricycle: {steering_scale: 0.5, traction_scale_m_per_turn: 0.01, axis_length_m: 1.4,\n"
    "           steering_offset_rad: 0.0, sensor_pose: [1.5, 0.0, 0.0]}\n";

TEST(TricycleModel, FitThroughTheFactoryRecoversTheTruth)
{
  const sim::GeneratedPairs data = tricyclePairs();
  CalibrationConfig config = parseCalibrationConfig(kConfig, "tricycle.yaml");
  ASSERT_EQ(config.models.joints.names, data.joints.names);
  auto model = makeModel("tricycle", config.models);
  const ModelReport report = model->fit(data.pairs);
  ASSERT_TRUE(report.converged) << report.termination;
  std::map<std::string, double> value;
  for (const ParameterEstimate& p : report.parameters)
    value[p.name] = p.value;
  ASSERT_EQ(report.parameters.size(), 7u);
  EXPECT_NEAR(report.parameters[0].value, 0.56, 0.01);      // Ks
  EXPECT_NEAR(report.parameters[1].value, 0.0106, 0.0001);  // Kt
  EXPECT_NEAR(report.parameters[2].value, 1.54, 0.03);      // axis length
  EXPECT_NEAR(report.parameters[3].value, -0.064, 0.005);   // steering offset
  ASSERT_TRUE(report.has_extrinsic);
  EXPECT_NEAR(report.T_base_sensor.x(), 1.80, 0.03);
  EXPECT_NEAR(report.T_base_sensor.y(), -0.015, 0.02);
  EXPECT_NEAR(report.T_base_sensor.theta(), -0.008, 0.01);
  EXPECT_LT(report.after.translation_m, 0.5 * report.before.translation_m);

  // Saved and loaded, it predicts the same motions; its covariance is the residual spread.
  const auto loaded = loadModel(model->toYaml());
  for (std::size_t i = 0; i < data.pairs.size(); i += 23) {
    const MotionPrediction a = model->predict(data.pairs[i].encoder_samples);
    const MotionPrediction b = loaded->predict(data.pairs[i].encoder_samples);
    EXPECT_NEAR(a.mean.x(), b.mean.x(), 1e-12);
    EXPECT_NEAR(a.mean.theta(), b.mean.theta(), 1e-12);
    EXPECT_NEAR(a.covariance(0, 0), b.covariance(0, 0), 1e-15);
    EXPECT_GT(a.covariance(0, 0), 0.0);
  }
}

/// Every encoder sample of the run once: the pairs' samples in time order (consecutive pairs
/// share their end samples).
std::vector<EncoderSample> encoderHistory(const std::vector<MotionPair>& pairs)
{
  std::vector<EncoderSample> history;
  for (const MotionPair& pair : pairs) {
    for (const EncoderSample& sample : pair.encoder_samples) {
      if (history.empty() || sample.stamp_s > history.back().stamp_s)
        history.push_back(sample);
    }
  }
  return history;
}

TEST(TricycleModel, TheSavedModelKeepsHowAStepsSteeringIsRead)
{
  // Three 25 Hz samples of a steering turning while the wheel drives: the end reading and the
  // mean of the two readings give different steps, so the flag must survive a save.
  std::vector<EncoderSample> samples;
  for (int k = 0; k < 3; ++k)
    samples.push_back({0.04 * k, Eigen::Vector2d(300.0 * k, 4000.0 * k)});
  TricycleModelOptions options;
  options.initial = TricycleParameters::fromVectors(Eigen::Vector4d(0.56, 0.0106, 1.54, -0.064),
                                                    Eigen::Vector3d(1.8, -0.015, -0.008));
  for (const bool at_end : {true, false}) {
    options.layout.steering_at_step_end = at_end;
    const TricycleModel model(options);
    const std::string yaml = model.toYaml();
    EXPECT_NE(yaml.find(std::string("steering_at_step_end: ") + (at_end ? "true" : "false")),
              std::string::npos)
        << yaml;
    const TricycleModel loaded = TricycleModel::fromYaml(yaml);
    EXPECT_EQ(loaded.predict(samples).mean.vector(), model.predict(samples).mean.vector()) << yaml;
  }
  // The two conventions differ here (by more than the 1e-12 a reload keeps).
  options.layout.steering_at_step_end = true;
  const Pose2 end = TricycleModel(options).predict(samples).mean;
  options.layout.steering_at_step_end = false;
  const Pose2 mean = TricycleModel(options).predict(samples).mean;
  EXPECT_GT(std::abs(end.theta() - mean.theta()), 1e-4);
  // A model saved before the key existed: the mean of the two readings (the layout's default).
  options.layout.steering_at_step_end = true;
  std::string old_yaml = TricycleModel(options).toYaml();
  const std::size_t key = old_yaml.find("steering_at_step_end: true\n");
  ASSERT_NE(key, std::string::npos);
  old_yaml.erase(key, std::string("steering_at_step_end: true\n").size());
  EXPECT_EQ(TricycleModel::fromYaml(old_yaml).predict(samples).mean.vector(), mean.vector());
}

TEST(TricycleModel, TimeOffsetSearchIsUnbiasedWithSlowEncoders)
{
  // Issue 35: with 25 Hz encoders the steering reading of a step's end sample (instead of the
  // step's mean steering) made the search find -5 ms where the simulation has none.
  const CalibrationConfig config = parseCalibrationConfig(kConfig, "tricycle.yaml");
  TimeOffsetOptions search;
  search.min_s = -0.2;
  search.max_s = 0.2;
  for (unsigned seed : {4117u, 4118u}) {
    const sim::GeneratedPairs data = tricyclePairs(seed, 25.0);
    const std::vector<EncoderSample> history = encoderHistory(data.pairs);
    ASSERT_GT(history.size(), 4000u);
    auto make = [&]() { return makeModel("tricycle", config.models); };
    const TimeOffsetResult at_zero = estimateTimeOffset(data.pairs, history, make, search);
    std::cout << "seed " << seed << ": tau " << at_zero.offset_s << " +- " << at_zero.sigma_s
              << " s\n";
    EXPECT_NEAR(at_zero.offset_s, 0.0, 0.0015);
    // The laser's clock 0.05 s behind the encoders': its pairs stamped 0.05 s early.
    std::vector<MotionPair> late = data.pairs;
    for (MotionPair& pair : late) {
      pair.start_stamp_s -= 0.05;
      pair.end_stamp_s -= 0.05;
    }
    late = rewindowPairs(late, history, 0.0, search.interpolation);
    ASSERT_GT(late.size(), data.pairs.size() - 3);
    const TimeOffsetResult shifted = estimateTimeOffset(late, history, make, search);
    std::cout << "seed " << seed << ", 0.05 s: tau " << shifted.offset_s << " s\n";
    EXPECT_NEAR(shifted.offset_s, 0.05, 0.002);
    EXPECT_FALSE(shifted.at_boundary);
  }
}

TEST(TricycleModel, NominalPriorPredictsWithTheStartValues)
{
  const CalibrationConfig config = parseCalibrationConfig(kConfig, "tricycle.yaml");
  const auto prior = priorModel(config);
  ASSERT_TRUE(prior);
  EXPECT_EQ(prior->name(), "tricycle");
  ASSERT_TRUE(priorSensorPose(config));
  EXPECT_DOUBLE_EQ(priorSensorPose(config)->x(), 1.5);
  // Straight ahead (steering reading 0, offset 0): Kt metres per traction turn, sensor on the
  // axis, so the sensor moves as far.
  const std::vector<EncoderSample> samples = {{0.0, Eigen::Vector2d(0, 0)},
                                              {1.0, Eigen::Vector2d(0, 5000)}};
  const MotionPrediction p = prior->predict(samples);
  EXPECT_NEAR(p.mean.x(), 0.01, 1e-9);
  EXPECT_NEAR(p.mean.y(), 0.0, 1e-9);
  EXPECT_NEAR(priorPredictor(config)(samples).x(), 0.01, 1e-9);
}

TEST(TricycleModel, ConfigurationErrorsNameTheKey)
{
  const std::string swapped =
      "joints:\n"
      "  - {name: steering, kind: incremental, units_per_turn: 8192}\n"
      "  - {name: traction_wheel, kind: incremental, units_per_turn: 5000}\n"
      "model: tricycle\n";
  try {
    parseCalibrationConfig(swapped, "t.yaml");
    FAIL() << "an incremental steering joint was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("steering joint must be kind: absolute"),
              std::string::npos)
        << error.what();
  }
  std::string zero_axis = kConfig;
  zero_axis.replace(zero_axis.find("axis_length_m: 1.4"), 18, "axis_length_m: 0.0");
  EXPECT_THROW(parseCalibrationConfig(zero_axis, "t.yaml"), std::runtime_error);
}

}  // namespace
}  // namespace odometry_calibration
