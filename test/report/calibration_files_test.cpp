// The calibration's files, as the node's ~save and calibrate_bag make them: result.yaml with the
// interval the fit used, controller.yaml or its removal, the URDF joint with a known pose; and a
// set written into a directory as one.
#include "odometry_calibration/report/calibration_files.h"

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/factory/model_factory.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// A report of `model`'s fit with one parameter and the sensor's pose.
ModelReport fittedReport(const std::string& model)
{
  ModelReport report;
  report.model = model;
  report.converged = true;
  report.pairs_used = 120;
  report.parameters = {{"left_wheel_radius", "m", 0.0765, 0.0766, 0.0001},
                       {"right_wheel_radius", "m", 0.0775, 0.0774, 0.0001},
                       {"wheel_separation", "m", 0.33, 0.321, 0.001}};
  report.has_extrinsic = true;
  report.T_base_sensor = Pose2(0.145, 0.01, 0.02);
  return report;
}

TEST(CalibrationFiles, ResultYamlHoldsTheIntervalTheFitUsedAndTheUrdfTheSensorsPose)
{
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  const auto model = makeModel("diff_drive", config.models);
  const ModelReport report = fittedReport("diff_drive");
  CalibrationFilesInput input;
  input.report = &report;
  input.model = model.get();
  input.source = "drive.bag";
  input.time_offset_s = -0.1004;
  input.joints = {"left_wheel", "right_wheel"};
  input.fit_interval_s = 0.75;
  input.T_base_sensor = report.T_base_sensor;
  input.sensor_frame = "front_laser";
  const FileSet set = calibrationFiles(input);
  ASSERT_EQ(set.written.size(), 3u);
  EXPECT_EQ(set.written[0].first, "result.yaml");
  EXPECT_EQ(set.written[1].first, "controller.yaml");
  EXPECT_EQ(set.written[2].first, "laser_joint.urdf");
  EXPECT_TRUE(set.removed.empty());
  const CalibrationResult saved = parseCalibrationResult(set.content("result.yaml"), "test");
  EXPECT_DOUBLE_EQ(saved.fit_interval_s, 0.75);
  EXPECT_NEAR(saved.time_offset_s, -0.1004, 1e-9);
  EXPECT_EQ(saved.joints, input.joints);
  const std::string urdf = set.content("laser_joint.urdf");
  EXPECT_NE(urdf.find("front_laser"), std::string::npos) << urdf;
  EXPECT_NE(urdf.find("<origin xyz=\"0.145000 0.010000 0\" rpy=\"0 0 0.020000\"/>"),
            std::string::npos)
      << urdf;
  // Without a known pose, no URDF; without a controller form, an earlier controller.yaml goes.
  input.T_base_sensor.reset();
  const FileSet without_pose = calibrationFiles(input);
  EXPECT_EQ(without_pose.written.size(), 2u);
  EXPECT_EQ(without_pose.removed, std::vector<std::string>{"laser_joint.urdf"});
  const auto linear = makeModel("linear", config.models);
  ModelReport linear_report = fittedReport("linear");
  linear_report.parameters.clear();  // a model-free fit has no wheel parameters
  input.report = &linear_report;
  input.model = linear.get();
  const FileSet model_free = calibrationFiles(input);
  ASSERT_EQ(model_free.written.size(), 1u);
  EXPECT_EQ(model_free.removed, (std::vector<std::string>{"controller.yaml", "laser_joint.urdf"}));
  input.model = nullptr;
  EXPECT_THROW(calibrationFiles(input), std::invalid_argument);
}

TEST(CalibrationFiles, ASetIsWrittenWholeWithItsSubfoldersAndRemovals)
{
  char pattern[] = "/tmp/calibration_files_test.XXXXXX";
  const std::string directory = mkdtemp(pattern);
  std::ofstream(directory + "/controller.yaml") << "an earlier calibration\n";
  FileSet source;
  source.written = {{"result.yaml", "sensor 0\n"}};
  FileSet set;
  set.addUnder("source_0", source);
  set.written.emplace_back("result.yaml", "joint\n");
  set.removed.push_back("controller.yaml");
  EXPECT_EQ(set.content("source_0/result.yaml"), "sensor 0\n");
  EXPECT_EQ(set.content("absent.yaml"), "");
  writeFileSet(directory, set);
  EXPECT_EQ(test_support::readFile(directory + "/source_0/result.yaml"), "sensor 0\n");
  EXPECT_EQ(test_support::readFile(directory + "/result.yaml"), "joint\n");
  EXPECT_FALSE(fs::exists(directory + "/controller.yaml"));
  for (const auto& entry : fs::directory_iterator(directory))  // no staging left
    EXPECT_EQ(entry.path().filename().string().rfind(".result_set", 0), std::string::npos);
  // A directory that is a file: refused, naming it.
  try {
    writeFileSet(directory + "/result.yaml", set);
    ADD_FAILURE() << "a file taken for the output directory";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("result.yaml"), std::string::npos) << error.what();
  }
  fs::remove_all(directory);
}

}  // namespace
}  // namespace odometry_calibration
