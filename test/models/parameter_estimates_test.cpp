#include "odometry_calibration/models/parameter_estimates.h"

#include <cmath>
#include <stdexcept>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

TEST(ParameterEstimates, SigmaIsTheRootOfTheCovarianceDiagonalAndNanWhereUndetermined)
{
  Eigen::Vector3d initial(0.077, 0.33, 0.0), value(0.075, 0.30, 0.01);
  Eigen::Matrix3d covariance;
  covariance << 4e-8, 1e-9, 0.0,  //
      1e-9, 9e-6, 0.0,            //
      0.0, 0.0, -1e-12;           // numerically negative: not determined
  const auto rows =
      parameterEstimates({"r", "b", "yaw"}, {"m", "m", "rad"}, initial, value, covariance, true);
  ASSERT_EQ(rows.size(), 3u);
  EXPECT_EQ(rows[1].name, "b");
  EXPECT_EQ(rows[2].unit, "rad");
  EXPECT_DOUBLE_EQ(rows[0].initial, 0.077);
  EXPECT_DOUBLE_EQ(rows[1].value, 0.30);
  EXPECT_NEAR(rows[0].sigma, 2e-4, 1e-12);
  EXPECT_NEAR(rows[1].sigma, 3e-3, 1e-12);
  EXPECT_TRUE(std::isnan(rows[2].sigma));

  const auto unavailable =
      parameterEstimates({"r", "b", "yaw"}, {"m", "m", "rad"}, initial, value, covariance, false);
  for (const auto& row : unavailable)
    EXPECT_TRUE(std::isnan(row.sigma)) << row.name;
}

TEST(ParameterEstimates, MismatchedSizesAreRejected)
{
  const Eigen::Vector2d two(1.0, 2.0);
  EXPECT_THROW(parameterEstimates({"a"}, {"m", "m"}, two, two, Eigen::Matrix2d::Identity(), true),
               std::invalid_argument);
  EXPECT_THROW(parameterEstimates({"a", "b"}, {"m", "m"}, Eigen::Vector3d::Zero(), two,
                                  Eigen::Matrix2d::Identity(), true),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
