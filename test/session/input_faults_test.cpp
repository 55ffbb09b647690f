// Inputs a faulty driver sends the session, without ROS: every JointState at one stamp, and a
// reading of 0 between the real ones (the glitch filter rejects those; no pair, no row of the
// pairs file and no resumed fit may carry them).
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <functional>

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

/// The largest step between two successive encoder samples of any pair, in ticks.
double largestStep(const std::vector<MotionPair>& pairs)
{
  double largest = 0.0;
  for (const MotionPair& pair : pairs) {
    for (std::size_t k = 1; k < pair.encoder_samples.size(); ++k) {
      const Eigen::VectorXd step =
          pair.encoder_samples[k].values - pair.encoder_samples[k - 1].values;
      largest = std::max(largest, step.cwiseAbs().maxCoeff());
    }
  }
  return largest;
}

TEST_F(InputFaults, EveryJointStateAtOneStampIsSaidAsSuch)
{
  auto session = makeSession();
  feed(*session, [](double) { return 12.3; });
  const CalibrateOutcome outcome = session->calibrate({});
  EXPECT_FALSE(outcome.success);
  EXPECT_EQ(outcome.message,
            "cannot calibrate: all " + std::to_string(officeDrive().joints.size()) +
                " JointState samples on /joint_states carry the same stamp 12.3 s: the publisher "
                "does not stamp its messages (header.stamp); stamp each with the time of its "
                "measurement");
}

TEST_F(InputFaults, EveryScanAtOneStampIsSaidAsSuch)
{
  auto session = makeSession();
  const Recording& drive = officeDrive();
  for (const Recording::Message& message : drive.inOrder()) {
    clock_s_ = message.stamp_s;
    if (message.joints) {
      const auto& positions = drive.joints[message.index].positions;
      session->addJointPositions(
          message.stamp_s, Eigen::Map<const Eigen::VectorXd>(positions.data(), positions.size()));
    } else {
      session->addScan(0.0, test::toScan(drive.scans[message.index]), "laser");
    }
  }
  session->flush();
  const CalibrateOutcome outcome = session->calibrate({});
  EXPECT_FALSE(outcome.success);
  EXPECT_EQ(outcome.message.rfind("cannot calibrate: all " + std::to_string(drive.scans.size()) +
                                      " LaserScan samples on /scan carry the same stamp 0 s",
                                  0),
            0u)
      << outcome.message;
  EXPECT_NE(outcome.message.find("carry the same stamp 0 s: the publisher does not stamp"),
            std::string::npos)
      << outcome.message;
}

TEST_F(InputFaults, ZerosBetweenTheReadingsReachNoPairAndNoResumedFit)
{
  // The clean drive's fit.
  auto clean = makeSession();
  feed(*clean, [](double t) { return t; });
  const CalibrateOutcome clean_outcome = clean->calibrate({});
  ASSERT_TRUE(clean_outcome.success) << clean_outcome.message;
  const std::vector<MotionPair> clean_pairs = clean->pairs();
  EXPECT_TRUE(clean->counts().statistics.glitches.empty());  // no real reading taken for one
  clean.reset();
  fs::remove_all(options_.output_directory);

  // A driver that sends a reading of 0 10 ms after each real one for 22 s (50 Hz), while the
  // wheels are within a few turns of 0: steps within max_turns_per_s, yet no motion.
  std::size_t pairs_written = 0;
  {
    auto zeros = makeSession();
    feed(
        *zeros, [](double t) { return t; }, 10.0, 32.0);
    const std::vector<MotionPair> pairs = zeros->pairs();
    pairs_written = pairs.size();
    // Every zero skipped as a glitch, and none in a pair: the pairs are the clean drive's.
    std::size_t glitches = 0;
    for (const auto& [joint, count] : zeros->counts().statistics.glitches)
      glitches += count;
    EXPECT_GE(glitches, 1000u);
    EXPECT_LT(largestStep(pairs), 100.0);  // ticks between samples 20 ms apart
    ASSERT_EQ(pairs.size(), clean_pairs.size());
    for (std::size_t k = 0; k < pairs.size(); ++k) {
      ASSERT_EQ(pairs[k].encoder_samples.size(), clean_pairs[k].encoder_samples.size()) << k;
      EXPECT_EQ(pairs[k].start_stamp_s, clean_pairs[k].start_stamp_s) << k;
    }
  }
  // A restarted session resumes the pairs file written meanwhile and fits as the clean run.
  auto resumed = makeSession();
  ASSERT_EQ(resumed->counts().pairs_resumed, pairs_written);
  EXPECT_LT(largestStep(resumed->pairs()), 100.0);
  const CalibrateOutcome outcome = resumed->calibrate({});
  ASSERT_TRUE(outcome.success) << outcome.message;
  const auto& expected = clean_outcome.fit->job.report.parameters;
  const auto& fitted = outcome.fit->job.report.parameters;
  ASSERT_EQ(fitted.size(), expected.size());
  for (std::size_t i = 0; i < fitted.size(); ++i) {
    EXPECT_NEAR(fitted[i].value, expected[i].value, 5e-4 * std::abs(expected[i].value))
        << fitted[i].name;
  }
}

}  // namespace
}  // namespace odometry_calibration
