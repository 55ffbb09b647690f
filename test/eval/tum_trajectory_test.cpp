// The TUM trajectory text: evo's format (t x y z qx qy qz qw, unit quaternions about z), base_link
// poses from sensor poses, the files of a comparison, and the inputs it refuses.
#include "odometry_calibration/eval/tum_trajectory.h"

#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

TEST(TumTrajectory, OneLinePerPoseWithAUnitQuaternionAboutZ)
{
  const std::string text =
      tumTrajectoryText({10.0, 10.5}, {Pose2(), Pose2(1.0, -2.0, 2.0 * std::atan(0.5))});
  std::istringstream lines(text);
  double t, x, y, z, qx, qy, qz, qw;
  lines >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
  EXPECT_EQ(t, 10.0);
  EXPECT_EQ(qw, 1.0);
  lines >> t >> x >> y >> z >> qx >> qy >> qz >> qw;
  EXPECT_EQ(t, 10.5);
  EXPECT_EQ(x, 1.0);
  EXPECT_EQ(y, -2.0);
  EXPECT_EQ(z, 0.0);
  EXPECT_EQ(qx, 0.0);
  EXPECT_EQ(qy, 0.0);
  // theta = 2 atan(1/2): (qz, qw) = (1, 2) / sqrt(5).
  EXPECT_NEAR(qz, 1.0 / std::sqrt(5.0), 1e-12);
  EXPECT_NEAR(qw, 2.0 / std::sqrt(5.0), 1e-12);
}

TEST(TumTrajectory, RefusesStampsThatDoNotIncreaseAndValuesThatAreNotFinite)
{
  EXPECT_THROW(tumTrajectoryText({1.0, 1.0}, {Pose2(), Pose2()}), std::invalid_argument);
  EXPECT_THROW(tumTrajectoryText({2.0, 1.0}, {Pose2(), Pose2()}), std::invalid_argument);
  EXPECT_THROW(tumTrajectoryText({1.0, 2.0}, {Pose2(), Pose2(NAN, 0.0, 0.0)}),
               std::invalid_argument);
  EXPECT_THROW(tumTrajectoryText({1.0}, {Pose2(), Pose2()}), std::invalid_argument);
}

TEST(TumTrajectory, BaseLinkPosesAreTheSensorPosesSeenFromTheBase)
{
  const Pose2 T_base_sensor(0.3, -0.1, 0.4);
  const std::vector<Pose2> base = {Pose2(), Pose2(1.0, 0.2, 0.3), Pose2(1.5, 1.0, 1.2)};
  std::vector<Pose2> sensor;
  for (const Pose2& b : base)  // the sensor's motion in its own first frame
    sensor.push_back(T_base_sensor.inverse() * b * T_base_sensor);
  const std::vector<Pose2> back = baseTrajectory(sensor, T_base_sensor);
  ASSERT_EQ(back.size(), base.size());
  for (std::size_t k = 0; k < base.size(); ++k) {
    EXPECT_NEAR(back[k].x(), base[k].x(), 1e-12);
    EXPECT_NEAR(back[k].y(), base[k].y(), 1e-12);
    EXPECT_NEAR(back[k].theta(), base[k].theta(), 1e-12);
  }
  // A sensor off the turning centre moves differently from the base over a turn.
  EXPECT_GT(std::hypot(sensor[2].x() - base[2].x(), sensor[2].y() - base[2].y()), 0.05);
}

TEST(TumTrajectory, FilesOfAComparisonNameEachRowAndTheScanMatchesOnce)
{
  ModelScore fitted, free, skipped, nominal;
  fitted.model = "diff_drive";
  fitted.stamps_s = {0.0, 0.5};
  fitted.predicted = fitted.measured = {Pose2(), Pose2(0.1, 0.0, 0.0)};
  fitted.T_base_sensor = Pose2(0.2, 0.0, 0.0);
  free = fitted;
  free.model = "gp";
  free.T_base_sensor.reset();
  skipped.model = "linear";
  skipped.skipped = "cannot";
  nominal = fitted;
  nominal.model = "nominal";
  nominal.stamps_s = {0.0, 0.6};  // other keyframes: its own scan matches
  std::vector<std::string> names;
  for (const auto& [name, content] : tumTrajectoryFiles({fitted, free, skipped, nominal}))
    names.push_back(name);
  EXPECT_EQ(names,
            (std::vector<std::string>{"diff_drive.sensor.tum", "diff_drive.base_link.tum",
                                      "scan_matched.tum", "gp.sensor.tum", "nominal.sensor.tum",
                                      "nominal.base_link.tum", "nominal.scan_matched.tum"}));
}

}  // namespace
}  // namespace odometry_calibration
