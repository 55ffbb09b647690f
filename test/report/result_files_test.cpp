// calibrate_bag's output set on a full disk (issue 32): a file that cannot be written leaves
// the previous run's set whole and no file of the new one.
#include "odometry_calibration/report/result_files.h"

#include <filesystem>

#include <gtest/gtest.h>

#include "support/file_size_limit.h"
#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// A small set: `pairs` pairs, a result and a controller form naming `run`.
ResultFiles resultSet(const std::string& run, std::size_t pairs)
{
  ResultFiles files;
  files.pairs.joints.names = {"left_wheel", "right_wheel"};
  files.pairs.joints.kinds = {EncoderKind::kIncremental, EncoderKind::kIncremental};
  for (std::size_t i = 0; i < pairs; ++i) {
    MotionPair pair;
    pair.start_stamp_s = static_cast<double>(i);
    pair.end_stamp_s = i + 0.5;
    pair.sensor_motion = Pose2(0.1, 0.0, 0.01);
    pair.covariance = Eigen::Matrix3d::Identity() * 1e-4;
    pair.encoder_samples = {{pair.start_stamp_s, Eigen::Vector2d(0.0, 0.0)},
                            {pair.end_stamp_s, Eigen::Vector2d(1.0, 1.0)}};
    files.pairs.pairs.push_back(pair);
  }
  files.calibration.written = {{"result.yaml", "source: " + run + "\n"},
                               {"controller.yaml", "wheel_radius: 0.0765 # " + run + "\n"}};
  files.text_report = "report of " + run + "\n";
  files.markdown.bags = {run + ".bag"};
  files.markdown.trajectories.matched = {Pose2(), Pose2(1.0, 0.0, 0.0)};
  files.markdown.trajectories.calibrated = files.markdown.trajectories.matched;
  files.markdown.report.model = "diff_drive";
  files.markdown.report.pairs_used = pairs;
  files.markdown.report.after = {0.0025, 0.0008, pairs};
  files.gnuplot.program = "/nonexistent/gnuplot";  // no images: the plots' data only
  return files;
}

TEST(ResultFiles, AFullDiskLeavesThePreviousSetWhole)
{
  char pattern[] = "/tmp/result_files_test.XXXXXX";
  const std::string directory = mkdtemp(pattern);
  writeResultFiles(directory, resultSet("first run", 5));
  const std::string pairs = test_support::readFile(directory + "/pairs.csv");
  ASSERT_NE(pairs.find("left_wheel"), std::string::npos);
  const auto before = std::distance(fs::directory_iterator(directory), {});
  {
    // The second run's pairs file (4000 pairs) does not fit; the small files would.
    const test::FileSizeLimit full_disk(20000);
    EXPECT_THROW(writeResultFiles(directory, resultSet("second run", 4000)), std::runtime_error);
  }
  EXPECT_EQ(test_support::readFile(directory + "/pairs.csv"), pairs);
  EXPECT_EQ(test_support::readFile(directory + "/result.yaml"), "source: first run\n");
  EXPECT_EQ(test_support::readFile(directory + "/controller.yaml"),
            "wheel_radius: 0.0765 # first run\n");
  EXPECT_EQ(test_support::readFile(directory + "/report.txt"), "report of first run\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(directory), {}), before);  // nothing new
  // With the space back, the second set replaces the first whole.
  writeResultFiles(directory, resultSet("second run", 4000));
  EXPECT_EQ(test_support::readFile(directory + "/result.yaml"), "source: second run\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(directory), {}), before);
  fs::remove_all(directory);
}

}  // namespace
}  // namespace odometry_calibration
