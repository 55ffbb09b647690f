// `~calibrate` options that no robot has (issue 32: a start radius or sensor x of 1e308 crashed
// the node in the fit's covariance) are refused before any fit, naming the key and the value.
#include <gtest/gtest.h>

#include "odometry_calibration/session/calibration_session.h"
#include "support/files.h"

namespace odometry_calibration {
namespace {

TEST(AbsurdOptions, AreRefusedNamingTheKeyBeforeAnyFit)
{
  const std::string text =
      test_support::readFile(std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/diff_drive.yaml");
  SessionOptions options;
  options.load_saved_calibration = options.resume_pairs = options.assistant = false;
  CalibrationSession session(parseCalibrationConfig(text, "diff_drive.yaml"), text,
                             "diff_drive.yaml", options);
  const std::pair<const char*, const char*> cases[] = {
      {"{diff_drive: {wheel_radius_m: 1e308}}", "diff_drive.wheel_radius_m: 1e308 is out of range"},
      {"{diff_drive: {wheel_radius_m: 77}}", "diff_drive.wheel_radius_m: 77 is out of range"},
      {"{diff_drive: {sensor_pose: [1e308, 0, 0]}}", "diff_drive.sensor_pose[0]: 1e308"},
      {"{diff_drive: {wheel_separation_m: .nan}}", "diff_drive.wheel_separation_m"},
      {"{gp: {starts: 2000000000}}", "gp.starts: 2000000000 is out of range"}};
  for (const auto& [call_options, expected] : cases) {
    CalibrationRequest request;
    request.options = call_options;
    if (std::string(call_options).find("gp") != std::string::npos)
      request.model = "gp";
    const CalibrateOutcome outcome = session.calibrate(request);
    EXPECT_FALSE(outcome.success);
    EXPECT_FALSE(outcome.fit);  // refused before the fit
    EXPECT_NE(outcome.message.find(expected), std::string::npos)
        << call_options << ": " << outcome.message;
  }
}

}  // namespace
}  // namespace odometry_calibration
