// Inputs a faulty driver sends the session, without ROS: every JointState at one stamp, and a
// reading of 0 between the real ones (the glitch filter rejects those; no pair, no row of the
// pairs file and no resumed fit may carry them).
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/session/calibration_session.h"
#include "support/office_drive.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

using test::officeDrive;
using test::Recording;

namespace fs = std::filesystem;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

class InputFaults : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/input_faults_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    config_text_ = readFile(kConfig + "/diff_drive.yaml");
    config_ = parseCalibrationConfig(config_text_, "diff_drive.yaml");
    options_.output_directory = directory_ + "/out";
    options_.wall_clock = [this] { return clock_s_; };
    options_.log = [this](SessionLogLevel, const std::string& text) { log_.push_back(text); };
  }
  void TearDown() override { fs::remove_all(directory_); }

  std::unique_ptr<CalibrationSession> makeSession()
  {
    return std::make_unique<CalibrationSession>(config_, config_text_, "diff_drive.yaml", options_,
                                                SessionListener{});
  }

  /// Feeds the office drive. `joint_stamp` maps a JointState's stamp to the one it is sent
  /// with; `zeros_from_s` .. `zeros_to_s`: a reading of 0 follows each real one 10 ms later.
  void feed(CalibrationSession& session, const std::function<double(double)>& joint_stamp,
            double zeros_from_s = 0.0, double zeros_to_s = 0.0)
  {
    const Recording& drive = officeDrive();
    for (const Recording::Message& message : drive.inOrder()) {
      clock_s_ = message.stamp_s;
      if (!message.joints) {
        session.addScan(message.stamp_s, test::toScan(drive.scans[message.index]), "laser");
        continue;
      }
      const auto& positions = drive.joints[message.index].positions;
      const Eigen::VectorXd reading =
          Eigen::Map<const Eigen::VectorXd>(positions.data(), positions.size());
      session.addJointPositions(joint_stamp(message.stamp_s), reading);
      if (message.stamp_s >= zeros_from_s && message.stamp_s < zeros_to_s)
        session.addJointPositions(joint_stamp(message.stamp_s + 0.01),
                                  Eigen::VectorXd::Zero(reading.size()));
    }
    session.flush();
  }

  std::string directory_, config_text_;
  CalibrationConfig config_;
  SessionOptions options_;
  double clock_s_ = 0.0;
  std::vector<std::string> log_;
};

TEST_F(InputFaults, Explore)
{
  {
    auto session = makeSession();
    feed(*session, [](double) { return 12.3; });
    const CalibrateOutcome outcome = session->calibrate({});
    std::cout << "ONE STAMP: pairs " << session->pairs().size() << ": " << outcome.message << "\n";
  }
  fs::remove_all(options_.output_directory);
  {
    auto session = makeSession();
    feed(
        *session, [](double t) { return t; }, 10.0, 32.0);
    const CalibrateOutcome outcome = session->calibrate({});
    std::cout << "ZEROS: pairs " << session->pairs().size() << ": " << outcome.message << "\n";
    std::size_t zero_pairs = 0;
    for (const MotionPair& pair : session->pairs()) {
      for (std::size_t i = 1; i < pair.encoder_samples.size(); ++i)
        if ((pair.encoder_samples[i].values - pair.encoder_samples[i - 1].values).norm() > 1.0) {
          ++zero_pairs;
          break;
        }
    }
    std::cout << "pairs with zero samples " << zero_pairs << "\n";
    for (const std::string& line : log_)
      std::cout << "LOG " << line << "\n";
  }
}

}  // namespace
}  // namespace odometry_calibration
