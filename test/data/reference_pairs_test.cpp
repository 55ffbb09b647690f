#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/data/keyframes.h"
#include "odometry_calibration/data/reference_pairs.h"

namespace odometry_calibration {
namespace {

/// 0.1 s samples; the reference drives along x at 1 m/s, turning at 0.1 rad/s.
void makeDrive(std::size_t count, std::vector<EncoderSample>* samples, std::vector<Pose2>* poses)
{
  for (std::size_t i = 0; i < count; ++i) {
    const double t = 0.1 * static_cast<double>(i);
    Eigen::VectorXd values(1);
    values << static_cast<double>(i);
    samples->push_back({t, values});
    poses->push_back(Pose2(t, 0.05 * t * t, 0.1 * t));
  }
}

TEST(ReferencePairs, EndToEndWindowsAreTheKeyframeWindows)
{
  std::vector<EncoderSample> samples;
  std::vector<Pose2> poses;
  makeDrive(31, &samples, &poses);
  const Eigen::Matrix3d covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-6).asDiagonal();
  const std::vector<MotionPair> pairs = referencePairs(samples, poses, 1.0, covariance);
  ASSERT_EQ(pairs.size(), 3u);  // [0, 10], [10, 20], [20, 30]
  for (std::size_t p = 0; p < pairs.size(); ++p) {
    const std::size_t first = 10 * p;
    EXPECT_DOUBLE_EQ(pairs[p].start_stamp_s, samples[first].stamp_s);
    EXPECT_DOUBLE_EQ(pairs[p].end_stamp_s, samples[first + 10].stamp_s);
    ASSERT_EQ(pairs[p].encoder_samples.size(), 11u);
    EXPECT_EQ(pairs[p].encoder_samples.front().values(0), static_cast<double>(first));
    EXPECT_TRUE(pairs[p].sensor_motion.vector().isApprox(
        between(poses[first], poses[first + 10]).vector()));
    EXPECT_TRUE(pairs[p].covariance.isApprox(covariance));
  }
}

TEST(ReferencePairs, RefusesMismatchedInput)
{
  std::vector<EncoderSample> samples;
  std::vector<Pose2> poses;
  makeDrive(10, &samples, &poses);
  poses.pop_back();
  EXPECT_THROW(referencePairs(samples, poses, 0.5, Eigen::Matrix3d::Identity()),
               std::invalid_argument);
  poses.push_back(Pose2());
  EXPECT_THROW(referencePairs(samples, poses, 0.0, Eigen::Matrix3d::Identity()),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
