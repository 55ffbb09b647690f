// The joint fit of several sensors (issue 35) on simulated pairs: a front and a rear sensor on
// the same differential drive.
#include "odometry_calibration/models/joint_fits.h"

#include <cmath>

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

}  // namespace
}  // namespace odometry_calibration
