#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/models/mecanum_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

const double kRadii[4] = {0.0515, 0.0497, 0.0503, 0.0490};  // FL, FR, RL, RR [m]
const double kLxPlusLyTruth = 0.36;
const Pose2 kSensorTruth(0.2, -0.03, 0.04);

sim::RobotOptions truthRobot()
{
  return {"mecanum",
          {{"wheel_radius_fl_m", kRadii[0]},
           {"wheel_radius_fr_m", kRadii[1]},
           {"wheel_radius_rl_m", kRadii[2]},
           {"wheel_radius_rr_m", kRadii[3]},
           {"half_length_m", 0.16},
           {"half_width_m", 0.2},
           {"encoder_ticks_per_rev", 4096}}};
}

sim::PairGeneratorOptions truthOptions(unsigned seed)
{
  sim::PairGeneratorOptions options;
  options.robot = truthRobot();
  options.T_base_sensor = kSensorTruth;
  options.duration_s = 150.0;
  options.interval_s = 0.5;
  options.motion.max_speed_mps = 0.4;
  options.seed = seed;
  return options;
}

MecanumOptions nominal()
{
  MecanumOptions options;
  options.layout.ticks_per_turn = 4096;
  options.initial_radius_m = {0.05, 0.05, 0.05, 0.05};
  options.initial_lx_plus_ly_m = 0.35;
  options.initial_T_base_sensor = Pose2(0.15, 0.0, 0.0);
  return options;
}

TEST(MecanumKinematics, ForwardKinematicsInvertTheSimulatorsWheelCommands)
{
  // One step of the simulated robot at a constant twist: the model's step from the wheels'
  // ticks is the same arc.
  const auto robot = sim::makeRobot(truthRobot());
  Eigen::VectorXd joints = robot->initialJoints();
  const sim::Twist2 command{0.3, -0.2, 0.7};
  const sim::Twist2 realised = robot->step(command, 0.2, &joints);
  EXPECT_NEAR(realised.vy_mps, -0.2, 1e-12);
  const double ticks[4] = {joints(0) / (2 * M_PI) * 4096, joints(1) / (2 * M_PI) * 4096,
                           joints(2) / (2 * M_PI) * 4096, joints(3) / (2 * M_PI) * 4096};
  double intrinsic[5] = {kRadii[0], kRadii[1], kRadii[2], kRadii[3], kLxPlusLyTruth};
  const Pose2 step = mecanumStep(intrinsic, ticks, 4096.0);
  const Pose2 truth = sim::integrateTwist(realised, 0.2);
  EXPECT_NEAR(step.x(), truth.x(), 1e-12);
  EXPECT_NEAR(step.y(), truth.y(), 1e-12);
  EXPECT_NEAR(step.theta(), 0.14, 1e-12);
  // Each wheel changes its own part: a larger front-left radius pushes forward, right, clockwise.
  intrinsic[kFrontLeftRadius] *= 1.1;
  const Pose2 bigger = mecanumStep(intrinsic, ticks, 4096.0);
  const double travel = 0.1 * kRadii[0] * joints(0);
  EXPECT_NEAR(bigger.theta() - step.theta(), -travel / (4 * kLxPlusLyTruth), 1e-9);
}

TEST(MecanumModel, RecoversRadiiLeverAndSensorPose)
{
  const auto data = sim::generatePairs(truthOptions(3));
  MecanumModel model(nominal());
  const ModelReport report = model.fit(data.pairs);
  ASSERT_TRUE(report.converged) << report.termination;
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(model.intrinsics()(i), kRadii[i], 0.01 * kRadii[i]) << report.parameters[i].name;
  EXPECT_NEAR(model.intrinsics()(kLxPlusLy), kLxPlusLyTruth, 0.02 * kLxPlusLyTruth);
  EXPECT_NEAR(model.T_base_sensor().x(), kSensorTruth.x(), 0.01);
  EXPECT_NEAR(model.T_base_sensor().y(), kSensorTruth.y(), 0.01);
  EXPECT_NEAR(model.T_base_sensor().theta(), kSensorTruth.theta(), M_PI / 180);
  // sigma honest: every estimate within 4 sigma of the truth.
  const double truth[] = {kRadii[0],      kRadii[1],        kRadii[2],        kRadii[3],
                          kLxPlusLyTruth, kSensorTruth.x(), kSensorTruth.y(), kSensorTruth.theta()};
  ASSERT_EQ(report.parameters.size(), 8u);
  for (int i = 0; i < 8; ++i) {
    EXPECT_LT(std::abs(report.parameters[i].value - truth[i]), 4.0 * report.parameters[i].sigma)
        << report.parameters[i].name;
  }
  EXPECT_EQ(report.parameters[0].name, "wheel_radius_front_left");
  EXPECT_EQ(report.parameters[4].name, "lx_plus_ly");
  EXPECT_TRUE(report.has_extrinsic);
  EXPECT_LT(report.after.translation_m, 0.3 * report.before.translation_m);
  // Fitted to 2 mm / 2 mrad pairs: the residuals are the noise.
  EXPECT_LT(report.residual_rms_xytheta.maxCoeff(), 0.0025);
  EXPECT_TRUE(report.warnings.empty()) << report.warnings.front();
  // The radii really differ (FL +3 %, RR -2 %): a note says so.
  bool noted = false;
  for (const std::string& note : report.notes)
    noted = noted || note.find("radii differ") != std::string::npos;
  EXPECT_TRUE(noted);
}

TEST(MecanumModel, EqualRadiiGiveNoDisagreementNote)
{
  sim::PairGeneratorOptions options = truthOptions(4);
  options.robot.parameters = {{"wheel_radius_m", 0.05}, {"encoder_ticks_per_rev", 4096}};
  const auto data = sim::generatePairs(options);
  MecanumModel model(nominal());
  const ModelReport report = model.fit(data.pairs);
  ASSERT_TRUE(report.converged);
  for (const std::string& note : report.notes)
    EXPECT_EQ(note.find("radii differ"), std::string::npos) << note;
}

TEST(MecanumModel, MirroredStartLandsOnThePhysicalSolution)
{
  const auto data = sim::generatePairs(truthOptions(5));
  MecanumOptions options = nominal();
  options.initial_radius_m = {-0.05, -0.05, -0.05, -0.05};
  options.initial_lx_plus_ly_m = -0.35;
  options.yaw_starts = 1;
  MecanumModel model(options);
  const ModelReport report = model.fit(data.pairs);
  ASSERT_TRUE(report.converged);
  EXPECT_NEAR(model.intrinsics()(kFrontLeftRadius), kRadii[0], 0.01 * kRadii[0]);
  EXPECT_NEAR(model.intrinsics()(kLxPlusLy), kLxPlusLyTruth, 0.02 * kLxPlusLyTruth);
  EXPECT_NEAR(model.T_base_sensor().x(), kSensorTruth.x(), 0.01);
  EXPECT_NEAR(model.T_base_sensor().theta(), kSensorTruth.theta(), M_PI / 180);
}

TEST(MecanumModel, SavedModelPredictsTheSameThroughTheFactory)
{
  const auto data = sim::generatePairs(truthOptions(6));
  ModelFactoryOptions options;
  options.joints = data.joints;
  options.mecanum = nominal();
  options.mecanum.layout = mecanumLayoutForJoints(data.joints, {"", "", "", ""}, 4096);
  auto model = makeModel("mecanum", options);
  model->fit(data.pairs);
  const auto loaded = loadModel(model->toYaml());
  EXPECT_EQ(loaded->name(), "mecanum");
  for (std::size_t i = 0; i < data.pairs.size(); i += 37) {
    const MotionPrediction a = model->predict(data.pairs[i].encoder_samples);
    const MotionPrediction b = loaded->predict(data.pairs[i].encoder_samples);
    EXPECT_NEAR(a.mean.x(), b.mean.x(), 1e-12);
    EXPECT_NEAR(a.mean.y(), b.mean.y(), 1e-12);
    EXPECT_NEAR(a.mean.theta(), b.mean.theta(), 1e-12);
    EXPECT_NEAR(a.covariance(1, 1), b.covariance(1, 1), 1e-15);
    EXPECT_GT(a.covariance(1, 1), 0.0);
  }
  // The unfitted model predicts the nominal robot.
  const auto unfitted = makeModel("mecanum", options);
  const Pose2 nominal_motion = unfitted->predict(data.pairs[10].encoder_samples).mean;
  const double intrinsic[5] = {0.05, 0.05, 0.05, 0.05, 0.35};
  const Pose2 expected = sensorMotionFromBodyMotion(
      Pose2(0.15, 0.0, 0.0),
      integrateMecanumMotion(intrinsic, options.mecanum.layout, data.pairs[10].encoder_samples));
  EXPECT_NEAR(nominal_motion.x(), expected.x(), 1e-15);
  EXPECT_NEAR(nominal_motion.y(), expected.y(), 1e-15);
}

TEST(MecanumModel, JointsByNameAndBadLayoutsAreNamed)
{
  JointLayout joints;
  joints.names = {"steer", "rr", "fl", "fr", "rl"};
  joints.kinds = {EncoderKind::kAbsolute, EncoderKind::kIncremental, EncoderKind::kIncremental,
                  EncoderKind::kIncremental, EncoderKind::kIncremental};
  const MecanumEncoderLayout named = mecanumLayoutForJoints(joints, {"fl", "fr", "rl", "rr"}, 1);
  EXPECT_EQ(named.front_left_index, 2);
  EXPECT_EQ(named.front_right_index, 3);
  EXPECT_EQ(named.rear_left_index, 4);
  EXPECT_EQ(named.rear_right_index, 1);
  const MecanumEncoderLayout first = mecanumLayoutForJoints(joints, {"", "", "", ""}, 1);
  EXPECT_EQ(first.front_left_index, 1);  // the absolute joint is skipped
  EXPECT_EQ(first.rear_right_index, 4);
  try {
    mecanumLayoutForJoints(joints, {"fl", "fr", "rl", "back_right"}, 1);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("'back_right'"), std::string::npos);
  }
  joints.names.resize(3);
  joints.kinds.resize(3);
  try {
    mecanumLayoutForJoints(joints, {"", "", "", ""}, 1);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("four incremental joints"), std::string::npos);
  }
  MecanumOptions twice = nominal();
  twice.layout.rear_right_index = 0;
  EXPECT_THROW(MecanumModel{twice}, std::invalid_argument);
  ModelFactoryOptions options;
  options.joints = joints;  // three joints: the wheels at 0..3 are not all there
  EXPECT_THROW(makeModel("mecanum", options), std::invalid_argument);
}

/// Pairs of a scripted drive: `twists` repeated (each 3 s) for 60 s.
std::vector<MotionPair> scriptedPairs(const std::vector<sim::Twist2>& twists)
{
  sim::PairGeneratorOptions options = truthOptions(7);
  options.duration_s = 60.0;
  options.motion.type = "scripted";
  for (int k = 0; k < 20; ++k)
    options.motion.script.push_back({3.0, twists[static_cast<std::size_t>(k) % twists.size()]});
  return sim::generatePairs(options).pairs;
}

bool mentions(const std::vector<std::string>& warnings, const std::string& text)
{
  for (const std::string& warning : warnings) {
    if (warning.find(text) != std::string::npos)
      return true;
  }
  return false;
}

TEST(MecanumModel, WarningsNameTheMissingMotion)
{
  MecanumOptions one_start = nominal();
  one_start.yaw_starts = 1;
  // Forward, backward and turning on the spot both ways, never sideways.
  {
    MecanumModel model(one_start);
    const ModelReport report =
        model.fit(scriptedPairs({{0.3, 0, 0}, {0, 0, 0.8}, {-0.3, 0, 0}, {0, 0, -0.8}}));
    EXPECT_TRUE(mentions(report.warnings, "no strafing")) << report.warnings.size();
    EXPECT_FALSE(mentions(report.warnings, "no turning"));
    EXPECT_FALSE(mentions(report.warnings, "no driving straight"));
  }
  // Straight and sideways, never turning: one warning names turning on the spot (not twice).
  {
    MecanumModel model(one_start);
    const ModelReport report =
        model.fit(scriptedPairs({{0.3, 0, 0}, {0, 0.3, 0}, {-0.3, 0, 0}, {0, -0.3, 0}}));
    EXPECT_TRUE(mentions(report.warnings, "no turning on the spot"));
    int turning = 0;
    for (const std::string& warning : report.warnings)
      turning += warning.rfind("no turning", 0) == 0;
    EXPECT_EQ(turning, 1);
    EXPECT_FALSE(mentions(report.warnings, "no strafing"));
  }
  // Sideways and turning only.
  {
    MecanumModel model(one_start);
    const ModelReport report =
        model.fit(scriptedPairs({{0, 0.3, 0}, {0, 0, 0.8}, {0, -0.3, 0}, {0, 0, -0.8}}));
    EXPECT_TRUE(mentions(report.warnings, "no driving straight"));
    EXPECT_FALSE(mentions(report.warnings, "no strafing"));
  }
}

TEST(MecanumModel, TooFewPairsOrJointsAreExplained)
{
  const auto data = sim::generatePairs(truthOptions(8));
  MecanumModel model(nominal());
  const std::vector<MotionPair> few(data.pairs.begin(), data.pairs.begin() + 5);
  EXPECT_THROW(model.fit(few), std::invalid_argument);
  std::vector<EncoderSample> samples = data.pairs[0].encoder_samples;
  for (EncoderSample& sample : samples)
    sample.values.conservativeResize(3);
  try {
    model.predict(samples);
    ADD_FAILURE() << "no throw";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("mecanum"), std::string::npos);
  }
  EXPECT_THROW(MecanumModel::fromYaml("model: mecanum\nwheel_indices: [0, 1]\n"),
               std::runtime_error);
}

}  // namespace
}  // namespace odometry_calibration
