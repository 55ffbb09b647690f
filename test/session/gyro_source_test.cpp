// The session's gyro readings (gyro_source.h): bad readings refused and counted with a reason
// naming the cause (a rate not finite or of 1e308, time going backwards, a repeated stamp, a
// message that could not be read), the mounting applied to the kept ones, and a reset.
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

#include "odometry_calibration/session/gyro_source.h"

namespace odometry_calibration {
namespace {

TEST(GyroSource, RefusesBadReadingsNamingTheCause)
{
  GyroSource gyro(GyroConfig{"/imu/data", 0.0, 0.0, 0.1}, -0.4, 0.4);
  EXPECT_EQ(gyro.add(1.0, Eigen::Vector3d(0.0, 0.0, 0.5)), "");
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_NE(gyro.add(1.01, Eigen::Vector3d(0.0, 0.0, nan)).find("not finite"), std::string::npos);
  EXPECT_NE(gyro.add(1.02, Eigen::Vector3d(0.0, 0.0, 1e308)).find("beyond 100 rad/s"),
            std::string::npos);
  EXPECT_NE(gyro.add(0.99, Eigen::Vector3d(0.0, 0.0, 0.5)).find("time going backwards"),
            std::string::npos);
  EXPECT_NE(gyro.add(1.0, Eigen::Vector3d(0.0, 0.0, 0.5)).find("repeated stamp"),
            std::string::npos);
  EXPECT_NE(gyro.add(nan, Eigen::Vector3d(0.0, 0.0, 0.5)).find("stamp that is not finite"),
            std::string::npos);
  EXPECT_EQ(gyro.refuse("cut short"), "cut short");
  EXPECT_EQ(gyro.readings(), 1u);
  EXPECT_EQ(gyro.refused(), 6u);
  EXPECT_NE(gyro.firstProblem().find("not finite"), std::string::npos);
  gyro.clear();
  EXPECT_EQ(gyro.readings(), 0u);
  EXPECT_EQ(gyro.refused(), 0u);
  EXPECT_EQ(gyro.firstProblem(), "");
}

TEST(GyroSource, ItsFitSaysWhyWithoutReadings)
{
  GyroSource gyro(GyroConfig{"/imu/data", 0.0, 0.0, 0.1}, -0.4, 0.4);
  MotionPair pair;
  pair.start_stamp_s = 1.0;
  pair.end_stamp_s = 1.5;
  const GyroFit fit = gyro.fit(std::vector<MotionPair>(20, pair), 0.0);
  EXPECT_FALSE(fit.fitted);
  EXPECT_NE(fit.problem.find("0 of 20 pairs lie inside the gyro's 0 readings"), std::string::npos)
      << fit.problem;
}

TEST(GyroYawRate, ATiltedReadingIsTurnedIntoBaseLink)
{
  // An IMU pitched by 0.3 rad sees the base's yaw rate w as (-sin 0.3 w, 0, cos 0.3 w).
  const double w = 0.7;
  EXPECT_NEAR(gyroYawRate(Eigen::Vector3d(-std::sin(0.3) * w, 0.0, std::cos(0.3) * w), 0.0, 0.3), w,
              1e-12);
  EXPECT_NEAR(gyroYawRate(Eigen::Vector3d(0.0, 0.0, w), 0.0, 0.0), w, 1e-12);
}

}  // namespace
}  // namespace odometry_calibration
