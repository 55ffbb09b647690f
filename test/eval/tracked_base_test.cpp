// A simulated tracked base whose effective separation is 20 % wider on the spot than driving
// straight: the tracked model recovers b(nu) = b0 + b1 nu, the held-out comparison ranks it
// ahead of the differential drive, and its TUM trajectory (read back from the file text) is
// closer to the simulator's truth than the differential drive's.
#include <algorithm>
#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/eval/metrics.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/eval/tum_trajectory.h"
#include "odometry_calibration/models/tracked_model.h"
#include "odometry_calibration/sim/pair_generator.h"

#include "support/diff_drive_start.h"

namespace odometry_calibration {
namespace {

constexpr double kSeparationM = 0.32, kGrowth = 0.2;

sim::GeneratedPairs trackedPairs(unsigned seed, double duration_s)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", kSeparationM},
                    {"separation_growth", kGrowth}}};
  options.interval_s = 0.5;
  options.duration_s = duration_s;
  options.seed = seed;
  return sim::generatePairs(options);
}

/// The planar poses of a TUM text (x, y and the yaw of its quaternion about z).
std::vector<Pose2> readTumPoses(const std::string& text)
{
  std::istringstream lines(text);
  std::vector<Pose2> poses;
  double t, x, y, z, qx, qy, qz, qw;
  while (lines >> t >> x >> y >> z >> qx >> qy >> qz >> qw)
    poses.emplace_back(x, y, 2.0 * std::atan2(qz, qw));
  return poses;
}

TEST(TrackedBase, TheCurvatureModelRecoversTheGrowingSeparation)
{
  const sim::GeneratedPairs training = trackedPairs(1, 180.0);
  TrackedModel model(test::nominalDiffDriveOptions());
  const ModelReport report = model.fit(training.pairs);
  ASSERT_TRUE(report.converged) << report.termination;
  EXPECT_NEAR(model.separationAt(0.0), kSeparationM, 0.01 * kSeparationM);
  EXPECT_NEAR(model.separationAt(1.0), kSeparationM * (1.0 + kGrowth), 0.01 * kSeparationM);
  EXPECT_NEAR(model.intrinsics()(kTrackedLeftRadius), 0.0765, 0.005 * 0.0765);
  EXPECT_NEAR(model.T_base_sensor().x(), 0.15, 0.01);
  // Saved and loaded, it predicts the same.
  const TrackedModel loaded = TrackedModel::fromYaml(model.toYaml());
  const Pose2 a = model.predict(training.pairs[40].encoder_samples).mean;
  const Pose2 b = loaded.predict(training.pairs[40].encoder_samples).mean;
  EXPECT_NEAR(a.x(), b.x(), 1e-9);
  EXPECT_NEAR(a.theta(), b.theta(), 1e-9);
}

TEST(TrackedBase, HeldOutTheCurvatureModelBeatsTheDiffDriveAndIsCloserToTheTruth)
{
  const sim::GeneratedPairs training = trackedPairs(1, 180.0), testing = trackedPairs(2, 120.0);
  ModelFactoryOptions options;
  options.joints = training.joints;
  options.diff_drive = test::nominalDiffDriveOptions();
  const std::vector<ModelScore> scores = compareModels({"diff_drive", "tracked", "linear", "gp"},
                                                       options, training.pairs, testing.pairs);
  const std::vector<std::string> ranking = rankByAte(scores);
  auto place = [&](const std::string& name) {
    return std::find(ranking.begin(), ranking.end(), name) - ranking.begin();
  };
  EXPECT_LT(place("tracked"), place("diff_drive")) << formatComparisonTable(scores);
  // The truth: the noise-free sensor motions chained over the same keyframes.
  std::vector<Pose2> truth = {Pose2()};
  for (const Pose2& motion : testing.true_motions)
    truth.push_back(truth.back() * motion);
  double truth_ate[2] = {0.0, 0.0};
  for (const auto& [name, text] : tumTrajectoryFiles(scores)) {
    for (int k = 0; k < 2; ++k) {
      if (name == std::string(k == 0 ? "diff_drive" : "tracked") + ".sensor.tum")
        truth_ate[k] = absoluteTrajectoryError(readTumPoses(text), truth);
    }
  }
  EXPECT_GT(truth_ate[0], 0.0);
  EXPECT_LT(truth_ate[1], 0.5 * truth_ate[0])
      << "diff_drive " << truth_ate[0] << " m, tracked " << truth_ate[1] << " m\n"
      << formatComparisonTable(scores);
}

}  // namespace
}  // namespace odometry_calibration
