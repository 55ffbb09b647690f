// Two publishers of one input (issue 32): a second node publishing the wheel joints (at zero,
// as joint_state_publisher does beside the driver) interleaved with the driver's readings. The
// session refuses the input naming both nodes, or, with joint_state_publisher set, ignores and
// counts the other's messages and calibrates as on the clean drive. The same for a second node
// publishing the scans (a stale laser beside the driver) and ego_motion.publisher.
#include <algorithm>

#include <gtest/gtest.h>

#include "odometry_calibration/session/calibration_session.h"
#include "odometry_calibration/session/input_publishers.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/files.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// 40 s of the simulated office drive (truth: r_L 0.0765, r_R 0.0775, b 0.32 m).
struct Drive : sim::SimulationSink
{
  std::vector<sim::JointStateSample> joints;
  std::vector<sim::ScanSample> scans;
  void onJointState(const sim::JointStateSample& s) override { joints.push_back(s); }
  void onScan(const sim::ScanSample& s) override { scans.push_back(s); }
  void onTruth(const sim::TruthSample&) override {}
};

const Drive& officeDrive()
{
  static const Drive drive = [] {
    Drive d;
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 40.0;
    const sim::World world = sim::loadWorldYaml(scenario.world_path);
    const auto robot = sim::makeRobot(scenario.robot);
    sim::simulate(scenario, world, *robot, d);
    return d;
  }();
  return drive;
}

/// Feeds the drive in stamp order from '/driver' (scans from '/laser_driver'); with
/// `intruder`, a JointState of zeros from '/joint_state_publisher' after each reading; with
/// `scan_intruder`, after each scan the one of ten scans earlier from '/laser_replay' (a stale
/// laser, e.g. a bag played beside the driver), stamped now.
void feed(CalibrationSession& session, bool intruder, bool scan_intruder = false)
{
  const Drive& drive = officeDrive();
  std::size_t scan = 0;
  for (const sim::JointStateSample& joints : drive.joints) {
    for (; scan < drive.scans.size() && drive.scans[scan].stamp_s <= joints.stamp_s; ++scan) {
      const double stamp_s = drive.scans[scan].stamp_s;
      session.addScan(stamp_s, test::toScan(drive.scans[scan]), "laser", "/laser_driver");
      if (scan_intruder)
        session.addScan(stamp_s + 1e-3, test::toScan(drive.scans[scan >= 10 ? scan - 10 : 0]),
                        "laser", "/laser_replay");
    }
    const Eigen::VectorXd positions =
        Eigen::Map<const Eigen::VectorXd>(joints.positions.data(), joints.positions.size());
    session.addJointPositions(joints.stamp_s, positions, "/driver");
    if (intruder)
      session.addJointPositions(joints.stamp_s + 1e-4, Eigen::VectorXd::Zero(positions.size()),
                                "/joint_state_publisher");
  }
  session.flush();
}

class Publishers : public ::testing::Test
{
protected:
  void SetUp() override
  {
    config_text_ = test_support::readFile(kConfig + "/diff_drive.yaml");
    config_ = parseCalibrationConfig(config_text_, "diff_drive.yaml");
    options_.load_saved_calibration = false;
    options_.resume_pairs = false;
    options_.assistant = false;
    options_.topics = {"/joint_states", "/scan"};
    options_.log = [this](SessionLogLevel level, const std::string& text) {
      if (level == SessionLogLevel::kError)
        errors_.push_back(text);
    };
  }
  std::unique_ptr<CalibrationSession> makeSession()
  {
    return std::make_unique<CalibrationSession>(config_, config_text_, "diff_drive.yaml", options_);
  }

  std::string config_text_;
  CalibrationConfig config_;
  SessionOptions options_;
  std::vector<std::string> errors_;
};

TEST_F(Publishers, ASecondJointStatePublisherIsRefusedNamingBoth)
{
  auto session = makeSession();
  feed(*session, true);
  const SessionCounts counts = session->counts();
  ASSERT_FALSE(counts.publisher_conflict.empty());
  for (const char* part : {"'/driver'", "'/joint_state_publisher'",
                           "joint_state_publisher:", "/joint_states", "remap"})
    EXPECT_NE(counts.publisher_conflict.find(part), std::string::npos)
        << part << " in: " << counts.publisher_conflict;
  EXPECT_EQ(errors_.size(), 1u);  // said once
  // Every JointState after the second publisher's first is refused (both publishers').
  EXPECT_EQ(counts.ignored_encoder_messages, 2 * officeDrive().joints.size() - 1);
  const CalibrateOutcome outcome = session->calibrate({});
  EXPECT_FALSE(outcome.success);
  EXPECT_NE(outcome.message.find("'/joint_state_publisher'"), std::string::npos) << outcome.message;
  const auto statuses = session->statusReports(1.0);
  EXPECT_EQ(statuses.front().level, SessionStatusReport::Level::kError);
}

TEST_F(Publishers, TheChosenPublisherCalibratesAsTheCleanDrive)
{
  auto clean = makeSession();
  feed(*clean, false);
  const CalibrateOutcome clean_fit = clean->calibrate({});
  ASSERT_TRUE(clean_fit.success) << clean_fit.message;
  EXPECT_TRUE(clean->counts().publisher_conflict.empty());

  config_.joint_state_publisher = "/driver";
  auto chosen = makeSession();
  feed(*chosen, true);
  const SessionCounts counts = chosen->counts();
  EXPECT_TRUE(counts.publisher_conflict.empty());
  EXPECT_EQ(counts.ignored_encoder_messages, officeDrive().joints.size());
  EXPECT_EQ(counts.ignored_encoder_publisher, "/joint_state_publisher");
  EXPECT_EQ(counts.encoder_publisher, "/driver");
  EXPECT_EQ(chosen->pairs().size(), clean->pairs().size());
  const CalibrateOutcome outcome = chosen->calibrate({});
  ASSERT_TRUE(outcome.success) << outcome.message;
  const auto& expected = clean_fit.fit->job.report.parameters;
  const auto& fitted = outcome.fit->job.report.parameters;
  ASSERT_EQ(fitted.size(), expected.size());
  for (std::size_t p = 0; p < 3; ++p)  // r_L, r_R, b
    EXPECT_NEAR(fitted[p].value, expected[p].value, 1e-3 * std::abs(expected[p].value));
}

TEST_F(Publishers, ASecondScanPublisherIsRefusedNamingBoth)
{
  auto session = makeSession();
  feed(*session, false, true);
  const SessionCounts counts = session->counts();
  ASSERT_FALSE(counts.publisher_conflict.empty());
  for (const char* part :
       {"'/laser_driver'", "'/laser_replay'", "ego_motion.publisher:", "on /scan", "remap"})
    EXPECT_NE(counts.publisher_conflict.find(part), std::string::npos)
        << part << " in: " << counts.publisher_conflict;
  EXPECT_EQ(errors_.size(), 1u);
  EXPECT_EQ(counts.ignored_ego_messages, 2 * officeDrive().scans.size() - 1);
  EXPECT_EQ(counts.ignored_encoder_messages, 0u);
  const CalibrateOutcome outcome = session->calibrate({});
  EXPECT_FALSE(outcome.success);
  EXPECT_NE(outcome.message.find("'/laser_replay'"), std::string::npos) << outcome.message;
}

TEST_F(Publishers, TheChosenScanPublisherCalibratesAsTheCleanDrive)
{
  auto clean = makeSession();
  feed(*clean, false);
  const CalibrateOutcome clean_fit = clean->calibrate({});
  ASSERT_TRUE(clean_fit.success) << clean_fit.message;

  config_.ego_motion_publisher = "/laser_driver";
  std::vector<std::string> warnings;
  options_.log = [&](SessionLogLevel level, const std::string& text) {
    if (level == SessionLogLevel::kWarn && text.rfind("ignoring", 0) == 0)
      warnings.push_back(text);
  };
  auto chosen = makeSession();
  feed(*chosen, false, true);
  const SessionCounts counts = chosen->counts();
  EXPECT_TRUE(counts.publisher_conflict.empty()) << counts.publisher_conflict;
  EXPECT_EQ(counts.ignored_ego_messages, officeDrive().scans.size());
  EXPECT_EQ(counts.ignored_ego_publisher, "/laser_replay");
  EXPECT_EQ(counts.ego_publisher, "/laser_driver");
  ASSERT_FALSE(warnings.empty());
  EXPECT_NE(warnings.front().find("(ego_motion.publisher: '/laser_driver'; 1 ignored so far)"),
            std::string::npos)
      << warnings.front();
  EXPECT_EQ(chosen->pairs().size(), clean->pairs().size());
  const CalibrateOutcome outcome = chosen->calibrate({});
  ASSERT_TRUE(outcome.success) << outcome.message;
  const auto& expected = clean_fit.fit->job.report.parameters;
  const auto& fitted = outcome.fit->job.report.parameters;
  ASSERT_EQ(fitted.size(), expected.size());
  for (std::size_t p = 0; p < 3; ++p)  // r_L, r_R, b
    EXPECT_NEAR(fitted[p].value, expected[p].value, 1e-3 * std::abs(expected[p].value));
}

TEST(InputPublishers, AReadingThatCarriesNoJointsStartsNoConflict)
{
  InputPublishers publishers({"/joint_states", "/scan"}, {"", ""});
  EXPECT_EQ(publishers.check(SessionInput::kEncoders, "/driver"), PublisherVerdict::kUse);
  // Another node's JointState of other joints (unreadable for the wheels): not a conflict.
  EXPECT_EQ(publishers.check(SessionInput::kEncoders, "/arm", false), PublisherVerdict::kUse);
  EXPECT_EQ(publishers.check(SessionInput::kEgoMotion, "/laser"), PublisherVerdict::kUse);
  EXPECT_TRUE(publishers.conflict().empty());
  EXPECT_EQ(publishers.check(SessionInput::kEgoMotion, ""), PublisherVerdict::kConflict);
  EXPECT_NE(publishers.conflict().find("'/laser' and (unnamed)"), std::string::npos)
      << publishers.conflict();
  EXPECT_EQ(publishers.check(SessionInput::kEgoMotion, "/laser"), PublisherVerdict::kConflict);
  EXPECT_EQ(publishers.ignored(SessionInput::kEgoMotion), 2u);
  EXPECT_EQ(publishers.check(SessionInput::kEncoders, "/driver"), PublisherVerdict::kUse);
}

TEST(InputPublishers, ASecondPublisherOfOneOfSeveralSourcesNamesThatSourcesKey)
{
  // With ego_motion.sources the key is the source's: ego_motion.publisher is refused there.
  const CalibrationConfig config = loadCalibrationConfig(kConfig + "/diff_drive_front_rear.yaml");
  const CalibrationConfig rear = configForSource(config, 1);
  EXPECT_EQ(rear.ego_motion_publisher_key, "ego_motion.sources[1].publisher");
  EXPECT_EQ(configForSource(config, 0).ego_motion_publisher_key, "ego_motion.sources[0].publisher");
  InputPublishers publishers({"/joint_states", rear.scan_topic}, {"", ""},
                             {"joint_state_publisher", rear.ego_motion_publisher_key});
  EXPECT_EQ(publishers.check(SessionInput::kEgoMotion, "/rear_driver"), PublisherVerdict::kUse);
  EXPECT_EQ(publishers.check(SessionInput::kEgoMotion, "/stale"), PublisherVerdict::kConflict);
  EXPECT_NE(publishers.conflict().find("on /scan_rear: '/rear_driver' and '/stale'"),
            std::string::npos)
      << publishers.conflict();
  EXPECT_NE(publishers.conflict().find("Set ego_motion.sources[1].publisher: <node>"),
            std::string::npos)
      << publishers.conflict();
  // One source without a list: the key of today.
  EXPECT_EQ(CalibrationConfig().ego_motion_publisher_key, "ego_motion.publisher");
}

}  // namespace
}  // namespace odometry_calibration
