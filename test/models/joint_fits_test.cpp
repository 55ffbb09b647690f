// The joint fit of several sensors (issue 35) on simulated pairs: a front and a rear sensor on
// the same differential drive, mecanum base, skid-steer base and tricycle.
#include "odometry_calibration/models/joint_fits.h"

#include <cmath>
#include <functional>
#include <iostream>

#include <gtest/gtest.h>

#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

const Pose2 kFront(0.30, 0.0, 0.0);
const Pose2 kRear(-0.30, 0.02, M_PI + 0.03);

sim::GeneratedPairs sensorPairs(const Pose2& T_base_sensor, unsigned seed, double noise)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.T_base_sensor = T_base_sensor;
  options.duration_s = 120.0;
  options.interval_s = 0.5;
  options.translation_noise_m = noise;
  options.rotation_noise_rad = noise;
  options.seed = seed;
  return sim::generatePairs(options);
}

DiffDriveOptions nominal()
{
  DiffDriveOptions options;
  options.initial_left_radius_m = 0.077;
  options.initial_right_radius_m = 0.077;
  options.initial_separation_m = 0.33;
  return options;
}

double angleError(double a, double b)
{
  return std::abs(normalizeAngle(a - b));
}

TEST(JointFits, FrontAndRearSensorsShareTheWheelsAndKeepTheirPoses)
{
  const std::vector<std::vector<MotionPair>> pairs = {sensorPairs(kFront, 31, 0.002).pairs,
                                                      sensorPairs(kRear, 32, 0.004).pairs};
  const JointFitReport report = fitJointDiffDrive(nominal(), pairs, {Pose2(), Pose2()});
  ASSERT_TRUE(report.converged) << report.termination;
  ASSERT_TRUE(report.covariance_available);
  ASSERT_EQ(report.sensors.size(), 2u);
  ASSERT_EQ(report.intrinsics.size(), 3u);
  const double truth[] = {0.0765, 0.0775, 0.32};
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(report.intrinsics[i].value, truth[i], 0.002 * truth[i]);
    EXPECT_LT(std::abs(report.intrinsics[i].value - truth[i]), 4.0 * report.intrinsics[i].sigma);
  }
  const Pose2 truths[] = {kFront, kRear};
  for (std::size_t s = 0; s < 2; ++s) {
    const Pose2& fitted = report.sensors[s].T_base_sensor;
    EXPECT_NEAR(fitted.x(), truths[s].x(), 0.005) << s;
    EXPECT_NEAR(fitted.y(), truths[s].y(), 0.005) << s;
    EXPECT_LT(angleError(fitted.theta(), truths[s].theta()), 0.3 * M_PI / 180) << s;
    ASSERT_EQ(report.sensors[s].pose.size(), 3u);
    EXPECT_EQ(report.sensors[s].pose[2].name, "sensor_theta");
    EXPECT_GT(report.sensors[s].pose[0].sigma, 0.0);
    EXPECT_EQ(report.sensors[s].pairs, pairs[s].size());
    EXPECT_TRUE(report.sensors[s].warnings.empty()) << report.sensors[s].warnings.front();
  }
  // Each sensor's view as a one-sensor report: its pose after the intrinsics, its residuals.
  const ModelReport rear = sensorModelReport(report, 1);
  ASSERT_EQ(rear.parameters.size(), 6u);
  EXPECT_EQ(rear.parameters[3].value, report.sensors[1].pose[0].value);
  EXPECT_GT(rear.residual_rms_xytheta(0), 0.0);
  EXPECT_LT(rear.after.translation_m, rear.before.translation_m);
  // Two sensors determine the wheels better than the better one alone.
  ASSERT_EQ(report.alone.size(), 2u);
  for (int i = 0; i < 3; ++i) {
    const double best_alone =
        std::min(report.alone[0].parameters[i].sigma, report.alone[1].parameters[i].sigma);
    EXPECT_LT(report.intrinsics[i].sigma, best_alone) << report.intrinsics[i].name;
  }
  // The sensors alone imply the same wheels within a few of their sigmas.
  const double spread = aloneIntrinsicsSpread(report);
  EXPECT_GT(spread, 0.0);
  EXPECT_LT(spread, 0.01);
}

TEST(JointFits, EachSensorsCovariancesAreRescaledByItsOwnNoiseScale)
{
  std::vector<std::vector<MotionPair>> pairs = {sensorPairs(kFront, 35, 0.002).pairs,
                                                sensorPairs(kRear, 36, 0.002).pairs};
  const JointFitReport honest = fitJointDiffDrive(nominal(), pairs, {Pose2(), Pose2()});
  // The rear matcher claims twice the precision it has (covariance a quarter of the truth):
  // its noise scale doubles (within the few % the solution moves by as the weights change), the
  // front's stays, and so do the fitted values.
  for (MotionPair& pair : pairs[1])
    pair.covariance *= 0.25;
  const JointFitReport overconfident = fitJointDiffDrive(nominal(), pairs, {Pose2(), Pose2()});
  EXPECT_NEAR(overconfident.sensors[1].noise_scale, 2.0 * honest.sensors[1].noise_scale,
              0.05 * honest.sensors[1].noise_scale);
  EXPECT_NEAR(overconfident.sensors[0].noise_scale, honest.sensors[0].noise_scale,
              0.05 * honest.sensors[0].noise_scale);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(overconfident.intrinsics[i].value, honest.intrinsics[i].value,
                0.1 * honest.intrinsics[i].sigma);
  }
}

TEST(JointFits, OneSensorGivesTheFitAlone)
{
  const std::vector<MotionPair> pairs = sensorPairs(kFront, 33, 0.002).pairs;
  DiffDriveOptions options = nominal();
  options.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  DiffDriveModel model(options);
  const ModelReport alone = model.fit(pairs);
  const JointFitReport joint = fitJointDiffDrive(options, {pairs}, {Pose2(0.1, 0.0, 0.0)});
  ASSERT_EQ(joint.alone.size(), 1u);
  EXPECT_EQ(joint.alone[0].parameters[0].value, alone.parameters[0].value);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(joint.intrinsics[i].value, alone.parameters[i].value, 1e-9);
    EXPECT_NEAR(joint.intrinsics[i].sigma, alone.parameters[i].sigma,
                1e-6 * alone.parameters[i].sigma);
  }
  EXPECT_NEAR(joint.sensors[0].T_base_sensor.x(), model.T_base_sensor().x(), 1e-9);
  EXPECT_NEAR(joint.sensors[0].pose[2].sigma, alone.parameters[5].sigma,
              1e-6 * alone.parameters[5].sigma);
  EXPECT_EQ(aloneIntrinsicsSpread(joint), 0.0);
  const ModelReport view = sensorModelReport(joint, 0);
  for (int axis = 0; axis < 3; ++axis) {
    EXPECT_NEAR(view.residual_rms_xytheta(axis), alone.residual_rms_xytheta(axis),
                1e-6 * alone.residual_rms_xytheta(axis));
  }
  EXPECT_EQ(view.before.translation_m, alone.before.translation_m);
}

TEST(JointFits, MecanumFrontAndRearSensorsShareTheWheels)
{
  const double radii[4] = {0.0515, 0.0497, 0.0503, 0.0490};  // FL, FR, RL, RR [m]
  const std::vector<Pose2> truths = {Pose2(0.25, 0.0, 0.0), Pose2(-0.25, 0.02, M_PI + 0.03)};
  std::vector<std::vector<MotionPair>> pairs;
  for (std::size_t s = 0; s < 2; ++s) {
    sim::PairGeneratorOptions options;
    options.robot = {"mecanum",
                     {{"wheel_radius_fl_m", radii[0]},
                      {"wheel_radius_fr_m", radii[1]},
                      {"wheel_radius_rl_m", radii[2]},
                      {"wheel_radius_rr_m", radii[3]},
                      {"half_length_m", 0.16},
                      {"half_width_m", 0.2},
                      {"encoder_ticks_per_rev", 4096}}};
    options.T_base_sensor = truths[s];
    options.duration_s = 150.0;
    options.interval_s = 0.5;
    options.motion.max_speed_mps = 0.4;
    options.seed = 37 + static_cast<unsigned>(s);
    pairs.push_back(sim::generatePairs(options).pairs);
  }
  MecanumOptions nominal;
  nominal.layout.ticks_per_turn = 4096;
  nominal.initial_radius_m = {0.05, 0.05, 0.05, 0.05};
  nominal.initial_lx_plus_ly_m = 0.35;
  const JointFitReport report = fitJointMecanum(nominal, pairs, {Pose2(), Pose2()});
  ASSERT_TRUE(report.converged) << report.termination;
  ASSERT_EQ(report.intrinsics.size(), 5u);
  for (int i = 0; i < 4; ++i)
    EXPECT_NEAR(report.intrinsics[i].value, radii[i], 0.003 * radii[i]) << i;
  EXPECT_NEAR(report.intrinsics[4].value, 0.36, 0.003 * 0.36);
  for (std::size_t s = 0; s < 2; ++s) {
    EXPECT_NEAR(report.sensors[s].T_base_sensor.x(), truths[s].x(), 0.005) << s;
    EXPECT_NEAR(report.sensors[s].T_base_sensor.y(), truths[s].y(), 0.005) << s;
    EXPECT_LT(angleError(report.sensors[s].T_base_sensor.theta(), truths[s].theta()),
              0.3 * M_PI / 180)
        << s;
  }
  for (int i = 0; i < 5; ++i) {
    EXPECT_LT(report.intrinsics[i].sigma,
              std::min(report.alone[0].parameters[i].sigma, report.alone[1].parameters[i].sigma))
        << report.intrinsics[i].name;
  }
}

TEST(JointFits, RefusesMismatchedStartsAndTooFewPairs)
{
  const std::vector<MotionPair> pairs = sensorPairs(kFront, 34, 0.002).pairs;
  EXPECT_THROW(fitJointDiffDrive(nominal(), {pairs, pairs}, {Pose2()}), std::invalid_argument);
  EXPECT_THROW(fitJointDiffDrive(nominal(), {}, {}), std::invalid_argument);
  const std::vector<MotionPair> few(pairs.begin(), pairs.begin() + 3);
  try {
    fitJointDiffDrive(nominal(), {pairs, few}, {Pose2(), Pose2()});
    FAIL() << "three pairs of sensor 1 accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("sensor 1"), std::string::npos) << error.what();
  }
}

/// The pairs of a front and a rear sensor (poses `truths`) on the robot `robot`, seeds
/// `first_seed` and the next, `duration_s` each, noise 2 mm / 2 mrad.
std::vector<std::vector<MotionPair>> frontRearPairs(const sim::RobotOptions& robot,
                                                    const std::vector<Pose2>& truths,
                                                    unsigned first_seed, double duration_s,
                                                    const sim::DrivePlanOptions& motion = {})
{
  std::vector<std::vector<MotionPair>> pairs;
  for (std::size_t s = 0; s < truths.size(); ++s) {
    sim::PairGeneratorOptions options;
    options.robot = robot;
    options.T_base_sensor = truths[s];
    options.duration_s = duration_s;
    options.interval_s = 0.5;
    options.motion = motion;
    options.seed = first_seed + static_cast<unsigned>(s);
    pairs.push_back(sim::generatePairs(options).pairs);
  }
  return pairs;
}

/// Each sensor's pose within 5 mm and 0.3 deg of `truths`; each intrinsic within its
/// `tolerances` entry and 4 σ of `intrinsics`, its joint σ below the better fit alone's.
void expectFrontRearTruth(const JointFitReport& report, const std::vector<double>& intrinsics,
                          const std::vector<Pose2>& truths, const std::vector<double>& tolerances)
{
  ASSERT_TRUE(report.converged) << report.termination;
  ASSERT_TRUE(report.covariance_available);
  ASSERT_EQ(report.intrinsics.size(), intrinsics.size());
  ASSERT_EQ(report.sensors.size(), truths.size());
  for (std::size_t i = 0; i < intrinsics.size(); ++i) {
    const ParameterEstimate& joint = report.intrinsics[i];
    std::cout << joint.name << " " << joint.value << " +- " << joint.sigma << " (truth "
              << intrinsics[i] << ")";
    for (const ModelReport& alone : report.alone)
      std::cout << "; alone " << alone.parameters[i].value << " +- " << alone.parameters[i].sigma;
    std::cout << "\n";
    EXPECT_NEAR(joint.value, intrinsics[i], tolerances.at(i)) << joint.name;
    EXPECT_LT(std::abs(joint.value - intrinsics[i]), 4.0 * joint.sigma) << joint.name;
    EXPECT_LT(joint.sigma,
              std::min(report.alone[0].parameters[i].sigma, report.alone[1].parameters[i].sigma))
        << joint.name;
  }
  for (std::size_t s = 0; s < truths.size(); ++s) {
    const Pose2& fitted = report.sensors[s].T_base_sensor;
    std::cout << "sensor " << s << ": " << fitted.x() << " " << fitted.y() << " " << fitted.theta()
              << "\n";
    EXPECT_NEAR(fitted.x(), truths[s].x(), 0.005) << s;
    EXPECT_NEAR(fitted.y(), truths[s].y(), 0.005) << s;
    EXPECT_LT(angleError(fitted.theta(), truths[s].theta()), 0.3 * M_PI / 180) << s;
  }
}

/// The refusal `fit` throws, or "" when it throws none.
template <class Fit>
std::string refusal(const Fit& fit)
{
  try {
    fit();
  } catch (const std::invalid_argument& error) {
    return error.what();
  }
  return "";
}

// A skid-steer base (four wheels, effective separation 1.45 times the 0.5 m track, right
// wheels 1 % larger) with a front and a rear laser: one set of effective radii and separation,
// the multipliers of the geometric values, one pose per laser.
TEST(JointFits, SkidSteerFrontAndRearSensorsShareTheSides)
{
  const std::vector<Pose2> truths = {Pose2(0.30, 0.0, 0.0), Pose2(-0.30, 0.02, M_PI + 0.03)};
  const sim::RobotOptions robot{"skid_steer",
                                {{"wheel_radius_left_m", 0.1},
                                 {"wheel_radius_right_m", 0.101},
                                 {"wheel_separation_m", 0.5},
                                 {"effective_separation_factor", 1.45}}};
  const std::vector<std::vector<MotionPair>> pairs = frontRearPairs(robot, truths, 363, 180.0);
  SkidSteerOptions options;
  options.left_indices = {0, 1};
  options.right_indices = {2, 3};
  options.wheel_radius_m = 0.1;
  options.wheel_separation_m = 0.5;
  const JointFitReport report = fitJointSkidSteer(options, pairs, {Pose2(), Pose2()});
  EXPECT_EQ(report.model, "skid_steer");
  // Within 0.1 %.
  expectFrontRearTruth(report, {0.1, 0.101, 1.45 * 0.5}, truths, {1e-4, 1.01e-4, 7.25e-4});
  // The multipliers of the geometric values, as a one-laser skid_steer fit lists them after the
  // pose; the fits alone list them too.
  ASSERT_EQ(report.derived.size(), 3u);
  EXPECT_EQ(report.derived[0].name, "wheel_separation_multiplier");
  EXPECT_NEAR(report.derived[0].value, 1.45, 0.001 * 1.45);
  EXPECT_NEAR(report.derived[0].sigma, report.intrinsics[2].sigma / 0.5, 1e-12);
  EXPECT_NEAR(report.derived[2].value, 1.01, 0.001);
  EXPECT_EQ(report.intrinsics[2].initial, 0.5);  // the geometric separation: the start value
  const ModelReport rear = sensorModelReport(report, 1);
  ASSERT_EQ(rear.parameters.size(), 9u);
  EXPECT_EQ(rear.parameters[5].name, "sensor_theta");
  EXPECT_EQ(rear.parameters[6].name, "wheel_separation_multiplier");
  ASSERT_EQ(report.alone[1].parameters.size(), 9u);
  EXPECT_EQ(report.alone[1].parameters[6].name, "wheel_separation_multiplier");
  EXPECT_LT(aloneIntrinsicsSpread(report), 0.01);
}

TEST(JointFits, SkidSteerNamesTheSensorOfEveryRefusal)
{
  // Every refusal of fitJointSkidSteer, each naming the sensor whose pairs it is about (and not
  // the other): a wheel missing, a pair with one encoder sample, too few pairs, on either
  // sensor; then the refusals of no sensor in particular.
  const std::vector<Pose2> truths = {Pose2(0.30, 0.0, 0.0), Pose2(-0.30, 0.02, M_PI + 0.03)};
  const std::vector<std::vector<MotionPair>> pairs =
      frontRearPairs({"skid_steer", {}}, truths, 365, 60.0);
  SkidSteerOptions options;
  options.left_indices = {0, 1};
  options.right_indices = {2, 3};
  const std::vector<Pose2> starts = {Pose2(), Pose2()};
  using Spoil = std::function<void(std::vector<MotionPair>&)>;
  const std::vector<std::pair<std::string, Spoil>> spoils = {
      {"a wheel missing",
       [](std::vector<MotionPair>& own) {
         for (EncoderSample& sample : own[4].encoder_samples)
           sample.values.conservativeResize(3);  // its right rear wheel
       }},
      {"one encoder sample",
       [](std::vector<MotionPair>& own) { own[2].encoder_samples.resize(1); }},
      {"too few pairs", [](std::vector<MotionPair>& own) { own.resize(4); }}};
  for (std::size_t s = 0; s < 2; ++s) {
    for (const auto& [what, spoil] : spoils) {
      std::vector<std::vector<MotionPair>> spoilt = pairs;
      spoil(spoilt[s]);
      const std::string message = refusal([&] { fitJointSkidSteer(options, spoilt, starts); });
      EXPECT_EQ(message.find("skid_steer joint fit, sensor " + std::to_string(s)), 0u)
          << what << ": " << message;
      EXPECT_EQ(message.find("sensor " + std::to_string(1 - s)), std::string::npos)
          << what << ": " << message;
    }
  }
  EXPECT_EQ(refusal([&] { fitJointSkidSteer(options, pairs, {Pose2()}); }),
            "skid_steer joint fit: 1 start poses for 2 sensors");
  EXPECT_EQ(refusal([&] { fitJointSkidSteer(options, {}, {}); }),
            "skid_steer joint fit: no sensor's pairs given");
  SkidSteerOptions one_sided = options;
  one_sided.right_indices.clear();
  EXPECT_EQ(refusal([&] { fitJointSkidSteer(one_sided, pairs, starts); }),
            "skid_steer needs at least one wheel joint on each side");
}

/// The seed's tricycle (true values near those calibrated on its real log).
sim::RobotOptions seedTricycle()
{
  return {"tricycle",
          {{"steering_scale", 0.56},
           {"traction_scale_m_per_turn", 0.0106},
           {"axis_length_m", 1.54},
           {"steering_offset_rad", -0.064}}};
}

TricycleModelOptions tricycleNominal()
{
  TricycleModelOptions options;
  options.layout.steering_ticks_per_turn = 8192;
  options.layout.traction_ticks_per_turn = 5000;
  options.initial.steering_scale = 0.5;
  options.initial.traction_scale_m_per_turn = 0.01;
  options.initial.axis_length_m = 1.4;
  return options;
}

// The tricycle with a laser over the steering wheel and one at the back turned round.
TEST(JointFits, TricycleFrontAndRearSensorsShareTheKinematics)
{
  const std::vector<Pose2> truths = {Pose2(1.80, -0.015, -0.008), Pose2(-0.30, 0.02, M_PI + 0.03)};
  sim::DrivePlanOptions motion;
  motion.max_speed_mps = 0.8;
  motion.max_turn_rate_radps = 0.5;
  const std::vector<std::vector<MotionPair>> pairs =
      frontRearPairs(seedTricycle(), truths, 367, 300.0, motion);
  // The configured poses (ego_motion.sources[].sensor_pose) start each fit alone.
  const std::vector<Pose2> starts = {Pose2(1.5, 0.0, 0.0), Pose2(-0.2, 0.0, M_PI)};
  const JointFitReport report = fitJointTricycle(tricycleNominal(), pairs, starts);
  EXPECT_EQ(report.model, "tricycle");
  // Ks, Kt and the axis length within 0.1 %; the steering offset, an angle near zero, within
  // 0.3 mrad (its σ from 300 s of pairs is 0.4 mrad: 0.1 % of it, 0.064 mrad, would take ~40
  // times the data).
  expectFrontRearTruth(report, {0.56, 0.0106, 1.54, -0.064}, truths,
                       {5.6e-4, 1.06e-5, 1.54e-3, 3e-4});
  EXPECT_EQ(report.intrinsics[2].initial, 1.4);  // the configured start value
  EXPECT_TRUE(report.derived.empty());
}

TEST(JointFits, TricycleNamesTheSensorWhosePairsCannotBeFitted)
{
  const std::vector<Pose2> truths = {Pose2(1.80, -0.015, -0.008), Pose2(-0.30, 0.02, M_PI)};
  std::vector<std::vector<MotionPair>> pairs = frontRearPairs(seedTricycle(), truths, 369, 30.0);
  pairs[1].resize(6);
  const std::vector<Pose2> starts = {Pose2(1.5, 0.0, 0.0), Pose2(-0.2, 0.0, M_PI)};
  const std::string few = refusal([&] { fitJointTricycle(tricycleNominal(), pairs, starts); });
  EXPECT_NE(few.find("tricycle joint fit, sensor 1"), std::string::npos) << few;
  pairs[1] = pairs[0];
  pairs[0][3].encoder_samples.resize(1);
  const std::string one = refusal([&] { fitJointTricycle(tricycleNominal(), pairs, starts); });
  EXPECT_NE(one.find("tricycle joint fit, sensor 0"), std::string::npos) << one;
}

}  // namespace
}  // namespace odometry_calibration
