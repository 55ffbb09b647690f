#include "odometry_calibration/eval/metrics.h"

#include <cmath>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

// Poses obtained by chaining relative steps from the origin.
std::vector<Pose2> chain(const std::vector<Pose2>& steps)
{
  std::vector<Pose2> poses{Pose2()};
  for (const Pose2& step : steps)
    poses.push_back(poses.back() * step);
  return poses;
}

const std::vector<Pose2> kReference =
    chain({Pose2(1.0, 0.0, M_PI / 2), Pose2(1.0, 0.0, 0.0), Pose2(0.5, 0.2, -0.3)});

TEST(MetricsTest, AteOfIdenticalTrajectoriesIsZero)
{
  EXPECT_NEAR(absoluteTrajectoryError(kReference, kReference), 0.0, 1e-12);
  EXPECT_NEAR(relativePoseError(kReference, kReference), 0.0, 1e-12);
}

TEST(MetricsTest, AteOfConstantOffsetEqualsOffset)
{
  std::vector<Pose2> estimated;
  for (const Pose2& pose : kReference) {
    estimated.emplace_back(pose.x() + 0.3, pose.y(), pose.theta());
  }
  EXPECT_NEAR(absoluteTrajectoryError(estimated, kReference), 0.3, 1e-12);
}

TEST(MetricsTest, AteMatchesHandComputedRms)
{
  const std::vector<Pose2> reference{Pose2(0.0, 0.0, 0.0), Pose2(1.0, 0.0, 0.5),
                                     Pose2(2.0, 1.0, 1.0)};
  // Translation errors 0.1, 0.2 and 0.5 (3-4-5); headings differ, which eq. 11 ignores.
  const std::vector<Pose2> estimated{Pose2(0.1, 0.0, 0.2), Pose2(1.0, -0.2, 0.4),
                                     Pose2(2.3, 1.4, -2.0)};
  const double expected = std::sqrt((0.01 + 0.04 + 0.25) / 3.0);
  EXPECT_NEAR(absoluteTrajectoryError(estimated, reference), expected, 1e-12);
  EXPECT_NEAR(absoluteTrajectoryError(reference, estimated), expected, 1e-12);
}

TEST(MetricsTest, RpeIgnoresRigidTransformWhileAteDoesNot)
{
  const Pose2 offset(2.0, -1.0, 0.8);
  std::vector<Pose2> moved;
  for (const Pose2& pose : kReference)
    moved.push_back(offset * pose);
  EXPECT_NEAR(relativePoseError(moved, kReference), 0.0, 1e-12);
  // The first pose alone is off by |(2, -1)|, so the RMS is at least that over sqrt(4).
  EXPECT_GT(absoluteTrajectoryError(moved, kReference), std::sqrt(5.0) / 2.0);
}

TEST(MetricsTest, RpeOfStraightLineWithOneLongStep)
{
  const std::vector<Pose2> reference{Pose2(0.0, 0.0, 0.0), Pose2(1.0, 0.0, 0.0),
                                     Pose2(2.0, 0.0, 0.0), Pose2(3.0, 0.0, 0.0)};
  const std::vector<Pose2> estimated{Pose2(0.0, 0.0, 0.0), Pose2(1.0, 0.0, 0.0),
                                     Pose2(2.1, 0.0, 0.0), Pose2(3.1, 0.0, 0.0)};
  // Errors 0, 0.1, 0 over three steps (divides by N - 1 = 3, not N = 4).
  EXPECT_NEAR(relativePoseError(estimated, reference), 0.1 / std::sqrt(3.0), 1e-12);
}

TEST(MetricsTest, RpeOfTurningPathWithOneLongStep)
{
  const std::vector<Pose2> estimated =
      chain({Pose2(1.0, 0.0, M_PI / 2), Pose2(1.1, 0.0, 0.0), Pose2(0.5, 0.2, -0.3)});
  EXPECT_NEAR(relativePoseError(estimated, kReference), 0.1 / std::sqrt(3.0), 1e-12);
  // The long step shifts the last two poses by 0.1 in world y: ATE = 0.1 * sqrt(2 / 4).
  EXPECT_NEAR(absoluteTrajectoryError(estimated, kReference), 0.1 * std::sqrt(0.5), 1e-12);
}

TEST(MetricsTest, RpeOfTwoPosesIsTheStepError)
{
  const std::vector<Pose2> reference{Pose2(0.0, 0.0, 0.0), Pose2(1.0, 0.0, 0.3)};
  const std::vector<Pose2> estimated{Pose2(5.0, 5.0, 1.0),
                                     Pose2(5.0, 5.0, 1.0) * Pose2(1.0, 0.2, 0.3)};
  EXPECT_NEAR(relativePoseError(estimated, reference), 0.2, 1e-12);
}

TEST(MetricsTest, InvalidSizesThrow)
{
  const std::vector<Pose2> empty;
  const std::vector<Pose2> one{Pose2()};
  const std::vector<Pose2> two{Pose2(), Pose2(1.0, 0.0, 0.0)};
  EXPECT_THROW(absoluteTrajectoryError(one, two), std::invalid_argument);
  EXPECT_THROW(absoluteTrajectoryError(empty, empty), std::invalid_argument);
  EXPECT_THROW(relativePoseError(one, two), std::invalid_argument);
  EXPECT_THROW(relativePoseError(empty, empty), std::invalid_argument);
  EXPECT_THROW(relativePoseError(one, one), std::invalid_argument);
  EXPECT_NO_THROW(absoluteTrajectoryError(one, one));
  EXPECT_NO_THROW(relativePoseError(two, two));
}

}  // namespace
}  // namespace odometry_calibration
