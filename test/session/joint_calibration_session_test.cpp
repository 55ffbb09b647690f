// The session of several ego-motion sources (issue 35) without ROS: a simulated front/rear robot's
// messages fed in stamp order, each laser's scans to its own source, as the node feeds them. Its
// fits, a silent laser, one source, the health monitor, the skid-steer and tricycle robots.
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/pcl_support.h"
#include "support/joint_session_fixture.h"

namespace odometry_calibration {
namespace {

using namespace test;  // the fixture's drives and helpers

TEST_F(JointSession, FitsBothLasersAsSeparateSessionsAndTheSharedJointFitDo)
{
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, nullptr);
  ASSERT_EQ(session.sourceCount(), 2u);
  feedJoint(session);
  const JointCalibrateOutcome fit = session.calibrate({});
  ASSERT_TRUE(fit.outcome.success) << fit.outcome.message;
  ASSERT_TRUE(fit.joint);

  // calibrate_bag's path: one session per source (configForSource, nothing adopted), each
  // fitted alone, then fitSourcesJointly on their fits.
  std::vector<std::unique_ptr<CalibrationSession>> alone;
  SessionOptions options = options_;
  options.output_directory.clear();
  options.adopt_fits = false;
  for (std::size_t k = 0; k < 2; ++k)
    alone.push_back(std::make_unique<CalibrationSession>(configForSource(config_, k), config_text_,
                                                         "front_rear", options));
  feed(
      [&](double t, const Eigen::VectorXd& raw) {
        for (auto& one : alone)
          one->addJointPositions(t, raw);
      },
      [&](std::size_t k, double t, const Scan& scan) { alone[k]->addScan(t, scan, kFrames[k]); });
  std::vector<JointSourceInput> inputs;
  for (std::size_t k = 0; k < 2; ++k) {
    alone[k]->flush();
    const CalibrateOutcome outcome = alone[k]->calibrate({});
    ASSERT_TRUE(outcome.fit) << outcome.message;
    const CalibrationJobResult& job = outcome.fit->job;
    inputs.push_back(
        {kFrames[k], kFrames[k], job.pairs, job.report.T_base_sensor, job.time_offset_s});
  }
  const JointFitReport expected = fitSourcesJointly(config_, inputs);
  ASSERT_EQ(fit.joint->intrinsics.size(), 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_DOUBLE_EQ(fit.joint->intrinsics[i].value, expected.intrinsics[i].value) << i;
    EXPECT_DOUBLE_EQ(fit.joint->intrinsics[i].sigma, expected.intrinsics[i].sigma) << i;
  }
  const double truth[2][3] = {{0.30, 0.0, 0.0}, {-0.30, 0.02, M_PI + 0.03}};
  for (std::size_t k = 0; k < 2; ++k) {
    const Pose2& pose = fit.joint->sensors[k].T_base_sensor;
    EXPECT_EQ(fit.joint->sensors[k].pairs, expected.sensors[k].pairs);
    EXPECT_DOUBLE_EQ(pose.x(), expected.sensors[k].T_base_sensor.x()) << k;
    EXPECT_DOUBLE_EQ(pose.theta(), expected.sensors[k].T_base_sensor.theta()) << k;
    EXPECT_NEAR(pose.x(), truth[k][0], 0.005) << k;
    EXPECT_NEAR(pose.y(), truth[k][1], 0.005) << k;
    EXPECT_NEAR(normalizeAngle(pose.theta() - truth[k][2]), 0.0, 0.005) << k;
    // Each source's session now drives its sensor's pose from the joint fit.
    ASSERT_TRUE(session.source(k).sensorPose()) << k;
    EXPECT_DOUBLE_EQ(session.source(k).sensorPose()->x(), pose.x()) << k;
  }
  EXPECT_NEAR(fit.joint->intrinsics[0].value, 0.076, 0.005 * 0.076);
  EXPECT_NEAR(fit.joint->intrinsics[1].value, 0.078, 0.005 * 0.078);
  EXPECT_NEAR(fit.joint->intrinsics[2].value, 0.32, 0.005 * 0.32);
  EXPECT_NE(fit.outcome.message.find("[/scan_rear] pose"), std::string::npos)
      << fit.outcome.message;
  // One health monitor watches the joint fit (each source's view of it), not the sources'.
  EXPECT_TRUE(session.healthStatistic());
  EXPECT_FALSE(session.source(1).healthStatistic());
  ASSERT_EQ(session.jointStatusReports().size(), 1u);
  EXPECT_EQ(session.jointStatusReports()[0].name, "calibration health");

  // Saved: the joint result with both sensors, each source's own files, one URDF joint each.
  const auto [saved, message] = session.save();
  ASSERT_TRUE(saved) << message;
  const YAML::Node result = YAML::LoadFile(options_.output_directory + "/result.yaml");
  ASSERT_EQ(result["sensors"].size(), 2u);
  EXPECT_EQ(result["sensors"][1]["frame"].as<std::string>(), "laser_rear");
  EXPECT_NEAR(result["sensors"][1]["T_base_sensor"]["y_m"].as<double>(),
              fit.joint->sensors[1].T_base_sensor.y(), 1e-9);  // written to 10 digits
  EXPECT_NEAR(result["model"]["wheel_separation_m"].as<double>(), fit.joint->intrinsics[2].value,
              1e-9);
  const std::string urdf = readFile(options_.output_directory + "/laser_joints.urdf");
  EXPECT_NE(urdf.find("<child link=\"laser_front\"/>"), std::string::npos) << urdf;
  EXPECT_NE(urdf.find("<child link=\"laser_rear\"/>"), std::string::npos) << urdf;
  for (std::size_t k = 0; k < 2; ++k) {
    const std::string source = options_.output_directory + "/source_" + std::to_string(k);
    EXPECT_GT(readFile(source + "/pairs.csv").size(), 1000u) << k;
    // The next start loads the joint wheels and this sensor's pose.
    const CalibrationResult own = readCalibrationResult(source + "/result.yaml");
    EXPECT_NEAR(own.T_base_sensor.x(), fit.joint->sensors[k].T_base_sensor.x(), 1e-6) << k;
  }
  // A new session (the node started again) loads each sensor's saved pose, and each source's
  // log lines name its topic.
  std::vector<std::string> log;
  options_.log = [&](SessionLogLevel, const std::string& text) { log.push_back(text); };
  JointCalibrationSession restarted(config_, config_text_, "front_rear", options_, nullptr);
  for (std::size_t k = 0; k < 2; ++k) {
    ASSERT_TRUE(restarted.source(k).sensorPose()) << k;
    EXPECT_NEAR(restarted.source(k).sensorPose()->theta(),
                fit.joint->sensors[k].T_base_sensor.theta(), 1e-6)
        << k;
  }
  EXPECT_TRUE(restarted.healthStatistic());  // the joint monitor watches the saved poses
  ASSERT_EQ(log.size(), 4u);  // each source: its saved calibration, its pairs resumed
  EXPECT_EQ(log[2].rfind("[/scan_rear] loaded the saved calibration", 0), 0u) << log[2];
  EXPECT_NE(log[2].find("/out/source_1/result.yaml"), std::string::npos) << log[2];
}

TEST_F(JointSession, ASilentLaserIsNamedByItsTopic)
{
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, nullptr);
  feedJoint(session, {0});
  const JointCalibrateOutcome fit = session.calibrate({});
  EXPECT_FALSE(fit.outcome.success);
  EXPECT_FALSE(fit.joint);
  EXPECT_NE(fit.outcome.message.find("source 1 (/scan_rear): only 0 pairs collected"),
            std::string::npos)
      << fit.outcome.message;
  // The guidance marker: each laser's on its own line, not ready while the rear one is silent.
  const AssistantMarker marker = session.assistantMarker();
  EXPECT_FALSE(marker.ready);
  EXPECT_EQ(marker.text.rfind("/scan_front: ", 0), 0u) << marker.text;
  EXPECT_NE(marker.text.find("\n/scan_rear: "), std::string::npos) << marker.text;
  EXPECT_FALSE(session.healthStatistic());  // nothing fitted: nothing watched
  const auto [saved, message] = session.save();
  EXPECT_FALSE(saved);
  EXPECT_NE(message.find("no successful joint"), std::string::npos) << message;
}

TEST_F(JointSession, OneSourceIsItsSessionUnchanged)
{
  // The front laser alone, as a one-entry list: the session of today, its files where they were.
  std::string text = config_text_;
  const std::size_t rear = text.find("    - topic: /scan_rear");
  text.erase(rear, text.find("keyframes:") - rear);
  const CalibrationConfig one = parseCalibrationConfig(text, "front.yaml");
  SessionOptions options = options_;
  JointCalibrationSession session(one, text, "front.yaml", options, nullptr);
  ASSERT_EQ(session.sourceCount(), 1u);
  options.output_directory = directory_ + "/plain";
  CalibrationSession plain(one, text, "front.yaml", options);
  feed(
      [&](double t, const Eigen::VectorXd& raw) {
        session.addJointPositions(t, raw);
        plain.addJointPositions(t, raw);
      },
      [&](std::size_t, double t, const Scan& scan) {
        session.source(0).addScan(t, scan, "laser_front");
        plain.addScan(t, scan, "laser_front");
      },
      {0});
  session.flush();
  plain.flush();
  const JointCalibrateOutcome fit = session.calibrate({});
  const CalibrateOutcome expected = plain.calibrate({});
  ASSERT_TRUE(fit.outcome.success) << fit.outcome.message;
  EXPECT_FALSE(fit.joint);
  EXPECT_EQ(fit.outcome.message, expected.message);
  EXPECT_EQ(readFile(options_.output_directory + "/pairs.csv"),
            readFile(options.output_directory + "/pairs.csv"));
  EXPECT_FALSE(fs::exists(options_.output_directory + "/source_0"));
}

TEST_F(JointSession, ACloudSourceNeedsABuildWithPcl)
{
  // The rear sensor a 3D lidar: a build without PCL refuses it by its key and topic, saying how
  // to get PCL; a build with PCL starts the session.
  std::string text = config_text_;
  const std::string rear = "    - topic: /scan_rear\n";
  text.replace(text.find(rear), rear.size(), "    - topic: /points\n      type: cloud\n");
  const CalibrationConfig config = parseCalibrationConfig(text, "front_lidar.yaml");
  if (kHavePcl) {
    JointCalibrationSession session(config, text, "front_lidar.yaml", options_, nullptr);
    EXPECT_EQ(session.sourceCount(), 2u);
    return;
  }
  try {
    JointCalibrationSession session(config, text, "front_lidar.yaml", options_, nullptr);
    FAIL() << "a cloud source was accepted without PCL";
  } catch (const std::runtime_error& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("ego_motion.sources[1].type: cloud (sensor_msgs/PointCloud2 on "
                           "'/points') needs PCL"),
              std::string::npos)
        << message;
    EXPECT_NE(message.find("run scripts/setup"), std::string::npos) << message;
  }
}

TEST_F(JointSession, TheHealthMonitorNamesTheRearLaserThatTurned)
{
  // Issue 35's acceptance in the session the node runs: fitted on the first 124 s, the
  // monitor's charts learn their noise on the next pairs; the rear laser turns +2 deg at 200 s.
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, nullptr);
  const Recording& drive = rearLaserTurnedDrive();
  feedJointSpan(session, drive, 0.0, 124.0);
  const JointCalibrateOutcome fit = session.calibrate({});
  ASSERT_TRUE(fit.outcome.success) << fit.outcome.message;
  feedJointSpan(session, drive, 124.0, 199.5);
  ASSERT_TRUE(session.healthStatistic());
  EXPECT_LT(*session.healthStatistic(), 1.0);  // no alarm before the turn
  EXPECT_FALSE(session.assistantMarker().alarm);
  feedJointSpan(session, drive, 199.5, 231.0);
  EXPECT_GE(*session.healthStatistic(), 1.0);
  EXPECT_TRUE(session.assistantMarker().alarm);
  const std::vector<SessionStatusReport> health = session.jointStatusReports();
  ASSERT_EQ(health.size(), 1u);
  EXPECT_NE(health[0].level, SessionStatusReport::Level::kOk) << health[0].message;
  EXPECT_NE(health[0].message.find("cause: a mounting change, the laser_rear mounting yaw"),
            std::string::npos)
      << health[0].message;
  EXPECT_EQ(health[0].message.find("laser_front"), std::string::npos) << health[0].message;
  std::printf("health: %s (statistic %.2f)\n", health[0].message.c_str(),
              *session.healthStatistic());
}

// The node's session with a skid-steer and a tricycle robot carrying a front and a rear laser
// (config/<model>_front_rear.yaml, the simulator's scenarios of those names): the joint fit of
// that model is adopted by both sources and ~save writes its files (controller.yaml for
// skid_steer with the multipliers of the geometric values; none for tricycle).
TEST_F(JointSession, SkidSteerAndTricycleLasersAreFittedJointlyAndSaved)
{
  const struct
  {
    const char* name;
    unsigned seed;
    double truth_x[2];
  } robots[] = {{"skid_steer_front_rear", 382, {0.35, -0.35}},
                {"tricycle_front_rear", 383, {1.80, -0.30}}};
  for (const auto& robot : robots) {
    SCOPED_TRACE(robot.name);
    std::string text = readFile(kConfig + "/" + std::string(robot.name) + ".yaml");
    text.replace(text.find("estimate_time_offset: true"), 26, "estimate_time_offset: false");
    const CalibrationConfig config = parseCalibrationConfig(text, robot.name);
    SessionOptions options = options_;
    options.output_directory = directory_ + "/" + robot.name;
    JointCalibrationSession session(config, text, robot.name, options, nullptr);
    feedJointSpan(session, simulateScenario(robot.name, 60.0, robot.seed), 0.0,
                  std::numeric_limits<double>::infinity());
    const JointCalibrateOutcome fit = session.calibrate({});
    ASSERT_TRUE(fit.outcome.success) << fit.outcome.message;
    EXPECT_EQ(fit.joint->model, config.model);
    for (std::size_t k = 0; k < 2; ++k) {
      EXPECT_NEAR(fit.joint->sensors[k].T_base_sensor.x(), robot.truth_x[k], 0.01) << k;
      ASSERT_TRUE(session.source(k).sensorPose()) << k;
      EXPECT_DOUBLE_EQ(session.source(k).sensorPose()->x(),
                       fit.joint->sensors[k].T_base_sensor.x());
    }
    const auto [saved, message] = session.save();
    ASSERT_TRUE(saved) << message;
    const std::string directory = options.output_directory;
    const CalibrationResult result = readCalibrationResult(directory + "/result.yaml");
    EXPECT_EQ(result.model->name(), config.model);
    EXPECT_DOUBLE_EQ(result.fit_interval_s, 0.5);
    EXPECT_NE(readFile(directory + "/laser_joints.urdf").find("laser_rear"), std::string::npos);
    const bool controller = config.model == "skid_steer";
    EXPECT_EQ(fs::exists(directory + "/controller.yaml"), controller);
    EXPECT_EQ(message.find("controller.yaml") != std::string::npos, controller) << message;
    if (controller) {
      EXPECT_NE(readFile(directory + "/controller.yaml").find("wheel_separation: 0.5 "),
                std::string::npos);
    }
  }
}

}  // namespace
}  // namespace odometry_calibration
