// ~odom's heading from the calibrated gyro (gyro_heading_odometry.h): exact on an arc whose
// wheels over-read the turn, the readings' gaps and bad input, no jump when the wheels'
// odometry is swapped; and on a held-out simulated 5-minute drive with wheel slip in turns
// (the wheels and the gyro calibrated on another drive), its heading error after 5 min below
// the wheels-only odometry's.
#include <cmath>
#include <cstdio>
#include <memory>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/session/gyro_heading_odometry.h"
#include "odometry_calibration/sim/pair_generator.h"
#include "support/acceptance_imu.h"
#include "support/diff_drive_start.h"

namespace odometry_calibration {
namespace {

/// A fitted gyro: reading = scale w + bias, its stamps `shift_s` after the laser's.
GyroFit gyroFit(double scale, double bias, double shift_s)
{
  GyroFit fit;
  fit.fitted = true;
  fit.scale.value = scale;
  fit.scale.sigma = 1e-4;
  fit.bias.value = bias;
  fit.bias.sigma = 1e-5;
  fit.shift_s = shift_s;
  return fit;
}

OdometryState wheelState(double stamp_s, const Pose2& pose, std::size_t continuity = 0)
{
  OdometryState state;
  state.stamp_s = stamp_s;
  state.pose = pose;
  state.covariance = Eigen::Matrix3d::Identity() * 1e-4;
  state.continuity = continuity;
  return state;
}

/// An arc of speed v [m/s] and turn rate w [rad/s] from the origin after t seconds.
Pose2 arc(double v, double w, double t)
{
  return Pose2(v / w * std::sin(w * t), v / w * (1.0 - std::cos(w * t)), normalizeAngle(w * t));
}

TEST(GyroHeadingOdometry, FollowsTheTrueArcWhereTheWheelsOverReadTheTurn)
{
  const double v = 0.5, w = 0.4, scale = 1.015, bias = 0.01, shift = 0.02;
  GyroHeadingOdometry odometry(0.1);
  EXPECT_EQ(odometry.setCalibration(gyroFit(scale, bias, shift)), "");
  OdometryState out;
  int reading = 0;                  // 100 Hz on the gyro's clock, read as they come
  for (int i = 0; i <= 750; ++i) {  // 50 Hz wheels over 15 s turning 10 % too much
    const double t = 0.02 * i;
    for (; 0.01 * reading + shift <= t + shift + 1e-9; ++reading)
      ASSERT_EQ(odometry.addReading(0.01 * reading + shift, scale * w + bias), "");
    out = odometry.apply(wheelState(t, arc(v, 1.1 * w, t)));
  }
  const Pose2 truth = arc(v, w, 15.0);
  EXPECT_NEAR(out.pose.x(), truth.x(), 1e-3);
  EXPECT_NEAR(out.pose.y(), truth.y(), 1e-3);
  EXPECT_NEAR(normalizeAngle(out.pose.theta() - truth.theta()), 0.0, 1e-9);
  EXPECT_NEAR(out.velocity(2), w, 1e-9);
  EXPECT_EQ(odometry.gyroSteps(), 750u);
  EXPECT_EQ(odometry.wheelSteps(), 0u);
  // The heading's sigma: the scale's over 6 rad turned, the bias's over 15 s.
  EXPECT_NEAR(std::sqrt(out.covariance(2, 2)), std::hypot(6.0 * 1e-4 / scale, 15.0 * 1e-5 / scale),
              1e-9);
  EXPECT_EQ(out.covariance(0, 2), 0.0);
}

TEST(GyroHeadingOdometry, TurnsWithTheWheelsWhereTheReadingsAreMissing)
{
  GyroHeadingOdometry odometry(0.1);
  // Before a fit: the wheels' state as it is.
  const OdometryState before = odometry.apply(wheelState(0.0, Pose2(1.0, 2.0, 0.3)));
  EXPECT_EQ(before.pose.x(), 1.0);
  EXPECT_EQ(before.pose.theta(), 0.3);
  ASSERT_EQ(odometry.setCalibration(gyroFit(1.0, 0.0, 0.0)), "");
  // Readings of 0.2 rad/s up to 1 s, none from 1 s to 2 s (a gap), then again to 3 s, each
  // read by the first wheel state after it.
  OdometryState out;
  int reading = 0;
  for (int i = 0; i < 150; ++i) {  // the wheels turn at 0.1 rad/s, 5 ms after the readings
    const double t = 0.005 + 0.02 * i;
    for (; reading <= 300 && 0.01 * reading <= t; ++reading) {
      if (reading <= 100 || reading >= 200) {
        ASSERT_EQ(odometry.addReading(0.01 * reading, 0.2), "");
      }
    }
    out = odometry.apply(wheelState(t, Pose2(0.0, 0.0, 0.1 * t), 1));
  }
  // From the start at 0.0005 rad: the steps to 1.085 s by the gyro (54; the newest reading at
  // 1 s extrapolated up to gyro.max_gap_s), from 1.085 s to 2.005 s by the wheels (46: the
  // silence and the step out of it), then the gyro's (49).
  EXPECT_NEAR(out.pose.theta(), 0.0005 + 54 * 0.02 * 0.2 + 46 * 0.02 * 0.1 + 49 * 0.02 * 0.2, 1e-9);
  EXPECT_EQ(odometry.gyroSteps(), 103u);
  EXPECT_EQ(odometry.wheelSteps(), 46u);
  // Silent for longer than max_gap_s: the newest reading (3 s) is not extrapolated to 3.2 s.
  out = odometry.apply(wheelState(3.2, Pose2(0.0, 0.0, 0.32), 1));
  EXPECT_EQ(odometry.wheelSteps(), 47u);
  // A reading 2.5 s later: the step to 3.22 s lies in the silence before it.
  ASSERT_EQ(odometry.addReading(5.5, 0.2), "");
  odometry.apply(wheelState(3.22, Pose2(0.0, 0.0, 0.322), 1));
  EXPECT_EQ(odometry.wheelSteps(), 48u);
}

TEST(GyroHeadingOdometry, DoesNotJumpWhenTheWheelsOdometryIsSwappedOrRestarted)
{
  GyroHeadingOdometry odometry(0.1);
  ASSERT_EQ(odometry.setCalibration(gyroFit(1.0, 0.0, 0.0)), "");
  for (int i = 0; i <= 400; ++i)
    ASSERT_EQ(odometry.addReading(0.01 * i, 0.0), "");
  odometry.apply(wheelState(0.0, Pose2()));
  const OdometryState moved = odometry.apply(wheelState(1.0, Pose2(1.0, 0.0, 0.0)));
  // Another model's odometry: its pose 5 m away; the output goes on from where it was.
  const OdometryState swapped = odometry.apply(wheelState(1.02, Pose2(6.0, 0.0, 0.0), 1));
  EXPECT_EQ(swapped.pose.x(), moved.pose.x());
  const OdometryState after = odometry.apply(wheelState(1.04, Pose2(6.1, 0.0, 0.0), 1));
  EXPECT_NEAR(after.pose.x(), 1.1, 1e-12);
  // A new fit: no jump either.
  ASSERT_EQ(odometry.setCalibration(gyroFit(1.01, 0.0, 0.0)), "");
  EXPECT_NEAR(odometry.apply(wheelState(1.06, Pose2(9.0, 0.0, 0.0), 1)).pose.x(), 1.1, 1e-12);
  // Time going backwards: the wheels' pose again.
  EXPECT_EQ(odometry.apply(wheelState(0.5, Pose2(0.2, 0.0, 0.0), 2)).pose.x(), 0.2);
}

TEST(GyroHeadingOdometry, RefusesBadReadingsAndFits)
{
  EXPECT_THROW(GyroHeadingOdometry(0.0), std::invalid_argument);
  EXPECT_THROW(GyroHeadingOdometry(NAN), std::invalid_argument);
  GyroHeadingOdometry odometry(0.1);
  EXPECT_NE(odometry.addReading(1.0, NAN).find("not a number"), std::string::npos);
  EXPECT_NE(odometry.addReading(NAN, 0.1).find("not a number"), std::string::npos);
  EXPECT_EQ(odometry.addReading(1.0, 0.1), "");
  EXPECT_NE(odometry.addReading(0.5, 0.1).find("not after the last"), std::string::npos);
  EXPECT_NE(odometry.addReading(1.0, 0.1).find("not after the last"), std::string::npos);
  GyroFit unfitted;
  unfitted.problem = "too few pairs";
  EXPECT_NE(odometry.setCalibration(unfitted).find("too few pairs"), std::string::npos);
  EXPECT_NE(odometry.setCalibration(gyroFit(0.0, 0.0, 0.0)).find("scale 0"), std::string::npos);
  EXPECT_NE(odometry.setCalibration(gyroFit(1.0, 1e308 * 10, 0.0)).find("not a number"),
            std::string::npos);
  EXPECT_FALSE(odometry.calibrated());
}

// The acceptance: a diff drive whose base turns 5 % less per rad/s of yaw rate than its wheels
// say (turn_slip_per_radps 0.05), a gyro 1.5 % high with a 0.01 rad/s bias walking
// 1e-6 rad/s/sqrt(s), 2 mrad/s of noise and its clock 20 ms late. The wheels (diff_drive) and
// the gyro (fitGyro) are calibrated on the pairs of a 240 s drive (0.3 s apart, 2 mm and
// 0.5 mrad of noise); on a held-out 300 s drive the wheels-only
// odometry (OdometryIntegrator, as ~odom without gyro.odom_heading) and the gyro-heading one are
// compared with the true heading after 5 min.
sim::PairGeneratorOptions slippingDrive(unsigned seed, double duration_s)
{
  sim::PairGeneratorOptions options;
  options.robot.parameters["turn_slip_per_radps"] = 0.05;
  options.duration_s = duration_s;
  options.seed = seed;
  options.rotation_noise_rad = 5e-4;  // a scan matcher's
  options.imu = test::acceptanceImu();
  return options;
}

TEST(GyroHeadingOdometry, HeadingAfterFiveMinutesOfSlippingTurnsBeatsTheWheels)
{
  const sim::GeneratedPairs calibration = sim::generatePairs(slippingDrive(4801, 240.0));
  auto wheels = std::make_shared<DiffDriveModel>(test::nominalDiffDriveOptions());
  const ModelReport report = wheels->fit(calibration.pairs);
  ASSERT_TRUE(report.converged);
  const GyroFit gyro =
      fitGyro(calibration.pairs, 0.0, test::yawRates(calibration.imu, 0.0, 0.0), {});
  ASSERT_TRUE(gyro.fitted) << gyro.problem;
  std::printf("%s\n", gyroFitText(gyro).c_str());

  const sim::GeneratedPairs held_out = sim::generatePairs(slippingDrive(4802, 300.0));
  const Pose2 T_base_sensor = report.T_base_sensor;
  OdometryIntegrator wheel_odometry(wheels, T_base_sensor, 0.3);
  GyroHeadingOdometry gyro_odometry(0.1);
  ASSERT_EQ(gyro_odometry.setCalibration(gyro), "");
  std::size_t next_reading = 0;
  double true_heading = 0.0;
  OdometryState wheels_only, with_gyro;
  for (std::size_t k = 0; k < held_out.pairs.size(); ++k) {
    const MotionPair& pair = held_out.pairs[k];
    if (k > 0) {
      ASSERT_EQ(pair.start_stamp_s, held_out.pairs[k - 1].end_stamp_s);
    }
    for (const EncoderSample& sample : pair.encoder_samples) {
      if (!wheel_odometry.add(sample))
        continue;
      // The readings the IMU has sent by now (its stamps 20 ms late, read as they come).
      for (; next_reading < held_out.imu.size() &&
             held_out.imu[next_reading].stamp_s <= sample.stamp_s;
           ++next_reading) {
        const sim::ImuSample& reading = held_out.imu[next_reading];
        ASSERT_EQ(gyro_odometry.addReading(reading.stamp_s, reading.angular_velocity.z()), "");
      }
      wheels_only = wheelState(sample.stamp_s, wheel_odometry.pose());
      with_gyro = gyro_odometry.apply(wheels_only);
    }
    true_heading += held_out.true_motions[k].theta();
  }
  ASSERT_GT(wheels_only.stamp_s, 299.0);
  const double wheels_error = std::abs(normalizeAngle(wheels_only.pose.theta() - true_heading));
  const double gyro_error = std::abs(normalizeAngle(with_gyro.pose.theta() - true_heading));
  std::printf(
      "heading error after %.0f s: wheels only %.4f rad, gyro heading %.4f rad "
      "(its sigma %.4f rad)\n",
      wheels_only.stamp_s, wheels_error, gyro_error, std::sqrt(with_gyro.covariance(2, 2)));
  EXPECT_LT(gyro_error, wheels_error);
  // Measured: wheels only 0.4207 rad, gyro heading 0.0053 rad, within 3 sigma of the gyro's
  // fit (0.0178 rad).
  EXPECT_LT(gyro_error, 3.0 * std::sqrt(with_gyro.covariance(2, 2)));
  EXPECT_GT(gyro_odometry.gyroSteps(), 14900u);
  // The first step only: the first reading (20 ms late) was not there at the first state.
  EXPECT_EQ(gyro_odometry.wheelSteps(), 1u);
}

}  // namespace
}  // namespace odometry_calibration
