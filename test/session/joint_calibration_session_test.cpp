// The session of several ego-motion sources (issue 35) without ROS: a simulated front/rear robot's
// messages fed in stamp order, each laser's scans to its own source, as the node feeds them.
#include <signal.h>
#include <sys/resource.h>

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <optional>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/odometry_integrator.h"
#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/session/joint_calibration_session.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// A simulated drive's encoder readings and both lasers' scans.
struct Recording : sim::SimulationSink
{
  std::vector<sim::JointStateSample> joints;
  std::vector<sim::ScanSample> scans;
  void onJointState(const sim::JointStateSample& s) override { joints.push_back(s); }
  void onScan(const sim::ScanSample& s) override { scans.push_back(s); }
  void onTruth(const sim::TruthSample&) override {}
};

/// `duration_s` of the front/rear robot (config/sim/scenarios/diff_drive_front_rear.yaml: radii
/// 0.076 / 0.078 m, separation 0.32 m, front laser (0.30, 0, 0), rear (-0.30, 0.02, pi + 0.03))
/// with `seed` and `changes`.
Recording simulateFrontRear(double duration_s, unsigned seed,
                            const std::vector<sim::ParameterChange>& changes = {})
{
  Recording r;
  sim::Scenario scenario = sim::loadScenarioYaml(
      kConfig + "/sim/scenarios/diff_drive_front_rear.yaml", kConfig + "/sim/worlds");
  scenario.duration_s = duration_s;
  scenario.seed = seed;
  scenario.changes = changes;
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  sim::simulate(scenario, world, *robot, r);
  return r;
}

/// 40 s of the front/rear robot, seed 36 (no other test's), recorded once for the suite.
const Recording& frontRearDrive()
{
  static const Recording recording = simulateFrontRear(40.0, 36);
  return recording;
}

std::string readFile(const std::string& path)
{
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

const char* const kFrames[2] = {"laser_front", "laser_rear"};

/// The front/rear robot driving 231 s, seed 37 (no other test's), its rear laser turned by
/// +2 deg at 200 s (a knock on the rear scanner); recorded once for the suite.
const Recording& rearLaserTurnedDrive()
{
  static const Recording recording = [] {
    sim::ParameterChange turn;
    turn.at_s = 200.0;
    turn.laser_index = 1;
    turn.laser_yaw_change_rad = 2.0 * M_PI / 180.0;
    return simulateFrontRear(231.0, 37, {turn});
  }();
  return recording;
}

/// Feeds `drive`'s samples from `begin_s` to before `end_s` (seconds after its first sample) in
/// stamp order: the encoders to `joints`, laser k's scans (those of `lasers`) to `scans(k)`.
template <typename Joints, typename Scans>
void feedSpan(const Recording& drive, double begin_s, double end_s, const Joints& joints,
              const Scans& scans, const std::vector<std::size_t>& lasers = {0, 1})
{
  const double t0 = std::min(drive.joints.front().stamp_s, drive.scans.front().stamp_s);
  const auto inSpan = [&](double stamp_s) {
    return stamp_s - t0 >= begin_s && stamp_s - t0 < end_s;
  };
  std::size_t j = 0, s = 0;
  while (j < drive.joints.size() || s < drive.scans.size()) {
    const bool joint =
        s == drive.scans.size() ||
        (j < drive.joints.size() && drive.joints[j].stamp_s <= drive.scans[s].stamp_s);
    if (joint) {
      const auto& positions = drive.joints[j].positions;
      if (inSpan(drive.joints[j].stamp_s))
        joints(drive.joints[j].stamp_s,
               Eigen::Map<const Eigen::VectorXd>(positions.data(), positions.size()));
      ++j;
      continue;
    }
    const sim::ScanSample& scan = drive.scans[s++];
    if (inSpan(scan.stamp_s) &&
        std::find(lasers.begin(), lasers.end(), scan.laser_index) != lasers.end())
      scans(scan.laser_index, scan.stamp_s, test::toScan(scan));
  }
}

/// Feeds the 40 s drive in stamp order (feedSpan over all of it).
template <typename Joints, typename Scans>
void feed(const Joints& joints, const Scans& scans, std::vector<std::size_t> lasers = {0, 1})
{
  feedSpan(frontRearDrive(), 0.0, std::numeric_limits<double>::infinity(), joints, scans, lasers);
}

class JointSession : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/joint_calibration_session_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    config_text_ = readFile(kConfig + "/diff_drive_front_rear.yaml");
    // Without the time-offset search: the suite stays short (the offset is the node's rostest's).
    config_text_.replace(config_text_.find("estimate_time_offset: true"), 26,
                         "estimate_time_offset: false");
    config_ = parseCalibrationConfig(config_text_, "diff_drive_front_rear.yaml");
    options_.output_directory = directory_ + "/out";
    options_.wall_clock = [] { return 0.0; };
  }
  void TearDown() override { fs::remove_all(directory_); }

  /// Feeds `session` the drive (the lasers listed).
  void feedJoint(JointCalibrationSession& session, std::vector<std::size_t> lasers = {0, 1})
  {
    feedJointSpan(session, frontRearDrive(), 0.0, std::numeric_limits<double>::infinity(), lasers);
  }

  /// Feeds `session` `drive`'s samples from `begin_s` to before `end_s` (feedSpan).
  void feedJointSpan(JointCalibrationSession& session, const Recording& drive, double begin_s,
                     double end_s, const std::vector<std::size_t>& lasers = {0, 1})
  {
    feedSpan(
        drive, begin_s, end_s,
        [&](double t, const Eigen::VectorXd& raw) { session.addJointPositions(t, raw); },
        [&](std::size_t k, double t, const Scan& scan) {
          session.source(k).addScan(t, scan, kFrames[k]);
        },
        lasers);
    session.flush();
  }

  std::string directory_, config_text_;
  CalibrationConfig config_;
  SessionOptions options_;
};

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

/// `duration_s` of scenario config/sim/scenarios/`name`.yaml with `seed`.
Recording simulateScenario(const std::string& name, double duration_s, unsigned seed)
{
  Recording r;
  sim::Scenario scenario =
      sim::loadScenarioYaml(kConfig + "/sim/scenarios/" + name + ".yaml", kConfig + "/sim/worlds");
  scenario.duration_s = duration_s;
  scenario.seed = seed;
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  sim::simulate(scenario, world, *robot, r);
  return r;
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

TEST_F(JointSession, AJointFitIsAdoptedByEverySourceOrByNone)
{
  // The rear laser's listener (the node's tf broadcaster) fails while `fail_rear` is set: the
  // rear source cannot adopt the joint fit after the front one has.
  bool fail_rear = false;
  std::optional<Pose2> front_told;  // the front sensor's pose last told to its listener
  const auto listener = [&](std::size_t k) {
    SessionListener own;
    own.sensor_pose = [&, k](const std::optional<Pose2>& pose, const std::string&) {
      if (k == 0)
        front_told = pose;
      else if (fail_rear)
        throw std::runtime_error("cannot broadcast base_link -> laser_rear");
    };
    return own;
  };
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, listener);
  feedJoint(session);
  fail_rear = true;
  // Before any fit: the front session drives ~odom with the nominal robot, the rear none.
  const auto active = [&](std::size_t k) { return session.source(k).activeModel(); };
  const decltype(active(0)) before[2] = {active(0), active(1)};
  ASSERT_EQ(before[0].second.rfind("nominal", 0), 0u) << before[0].second;
  JointCalibrateOutcome fit = session.calibrate({});
  EXPECT_FALSE(fit.outcome.success);
  EXPECT_NE(fit.outcome.message.find("not adopted: source 1 (/scan_rear): cannot broadcast "
                                     "base_link -> laser_rear; the previous calibration stays "
                                     "active in every source"),
            std::string::npos)
      << fit.outcome.message;
  for (std::size_t k = 0; k < 2; ++k) {  // as before, the front one too: no pose learnt
    EXPECT_EQ(active(k).first, before[k].first) << k;
    EXPECT_EQ(active(k).second, before[k].second) << k;
    EXPECT_FALSE(session.source(k).sensorPose()) << k;
  }
  EXPECT_FALSE(front_told);  // the front tf was told the joint pose, then none again
  EXPECT_FALSE(session.healthStatistic());
  EXPECT_FALSE(session.save().first);

  // Adopted by both, then a second fit (other options) that the rear laser fails to take.
  fail_rear = false;
  fit = session.calibrate({});
  ASSERT_TRUE(fit.outcome.success) << fit.outcome.message;
  const auto adopted = [&](std::size_t k) { return session.source(k).activeModel().first; };
  const std::shared_ptr<const MotionModel> models[2] = {adopted(0), adopted(1)};
  const Pose2 poses[2] = {*session.source(0).sensorPose(), *session.source(1).sensorPose()};
  fail_rear = true;
  CalibrationRequest request;
  request.options = "{diff_drive: {huber_threshold: 1.0}}";
  const JointCalibrateOutcome refused = session.calibrate(request);
  EXPECT_FALSE(refused.outcome.success);
  ASSERT_TRUE(refused.joint);
  EXPECT_NE(refused.joint->intrinsics[2].value, fit.joint->intrinsics[2].value);
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_EQ(adopted(k), models[k]) << k;
    EXPECT_DOUBLE_EQ(session.source(k).sensorPose()->theta(), poses[k].theta()) << k;
  }
  ASSERT_TRUE(front_told);
  EXPECT_DOUBLE_EQ(front_told->x(), poses[0].x());
}

TEST_F(JointSession, TheSavedFilesAreReplacedAsOneSet)
{
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, nullptr);
  feedJointSpan(session, frontRearDrive(), 0.0, 25.0);
  ASSERT_TRUE(session.calibrate({}).outcome.success);
  const auto [saved, message] = session.save();
  ASSERT_TRUE(saved) << message;
  const std::vector<std::string> names = {"result.yaml",
                                          "laser_joints.urdf",
                                          "controller.yaml",
                                          "joint_report.txt",
                                          "source_0/result.yaml",
                                          "source_0/controller.yaml",
                                          "source_0/laser_joint.urdf",
                                          "source_1/result.yaml",
                                          "source_1/controller.yaml",
                                          "source_1/laser_joint.urdf"};
  std::map<std::string, std::string> old;
  for (const std::string& name : names) {
    old[name] = readFile(options_.output_directory + "/" + name);
    EXPECT_FALSE(old[name].empty()) << name;
  }
  // A second fit on the whole drive, saved under a file-size limit that joint_report.txt (the
  // set's largest file, written last) exceeds: nothing of the new set may appear.
  feedJointSpan(session, frontRearDrive(), 25.0, std::numeric_limits<double>::infinity());
  ASSERT_TRUE(session.calibrate({}).outcome.success);
  std::size_t largest_other = 0;
  for (const std::string& name : names) {
    if (name != "joint_report.txt")
      largest_other = std::max(largest_other, old[name].size());
  }
  const rlim_t limit = (largest_other + old["joint_report.txt"].size()) / 2;
  ASSERT_LT(largest_other + 100, limit);  // the others fit under the limit, the report not
  ASSERT_GT(old["joint_report.txt"].size(), limit + 100);
  rlimit before{};
  getrlimit(RLIMIT_FSIZE, &before);
  const auto previous_handler = signal(SIGXFSZ, SIG_IGN);
  rlimit small = before;
  small.rlim_cur = limit;
  setrlimit(RLIMIT_FSIZE, &small);
  const auto [refused, why] = session.save();
  setrlimit(RLIMIT_FSIZE, &before);
  signal(SIGXFSZ, previous_handler);
  EXPECT_FALSE(refused);
  EXPECT_NE(why.find("the previous files are kept: cannot write joint_report.txt"),
            std::string::npos)
      << why;
  for (const std::string& name : names)
    EXPECT_EQ(readFile(options_.output_directory + "/" + name), old[name]) << name;
  for (const auto& entry : fs::directory_iterator(options_.output_directory))
    EXPECT_EQ(entry.path().filename().string().rfind(".result_set", 0), std::string::npos);
  // Without the limit the new set replaces the old one whole.
  const auto [resaved, text] = session.save();
  ASSERT_TRUE(resaved) << text;
  for (const std::string& name : names) {
    if (name.find("urdf") == std::string::npos) {  // a pose may print the same to 4 digits
      EXPECT_NE(readFile(options_.output_directory + "/" + name), old[name]) << name;
    }
  }
}

TEST_F(JointSession, CalibrateTakesTheModelAndItsOptionsAJointFitTakes)
{
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, nullptr);
  feedJoint(session);
  const auto refusal = [&](const std::string& model, const std::string& options) {
    CalibrationRequest request;
    request.model = model;
    request.options = options;
    const JointCalibrateOutcome outcome = session.calibrate(request);
    EXPECT_FALSE(outcome.outcome.success);
    EXPECT_FALSE(outcome.joint);
    return outcome.outcome.message;
  };
  EXPECT_NE(refusal("gp", "").find(
                "supports models diff_drive, skid_steer, mecanum and tricycle, not 'gp'"),
            std::string::npos);
  EXPECT_NE(refusal("", "{gp: {kernel: linear}}").find("option 'gp' does not apply"),
            std::string::npos);
  EXPECT_NE(refusal("", "{diff_drive: {sensor_pose: [0, 0, 0]}}")
                .find("option 'diff_drive.sensor_pose' does not apply"),
            std::string::npos);
  EXPECT_NE(refusal("mecanum", "").find("cannot fit mecanum jointly"), std::string::npos);
  EXPECT_NE(refusal("", "{diff_drive: {huber_threshold: -1}}").find("huber_threshold"),
            std::string::npos);
  EXPECT_FALSE(session.source(0).sensorPose());  // nothing adopted

  const JointCalibrateOutcome plain = session.calibrate({});
  ASSERT_TRUE(plain.outcome.success) << plain.outcome.message;
  CalibrationRequest request;
  request.model = "diff_drive";
  request.options = "{diff_drive: {huber_threshold: 1.0}}";
  const JointCalibrateOutcome tight = session.calibrate(request);
  ASSERT_TRUE(tight.outcome.success) << tight.outcome.message;
  // The tighter robust threshold counts more outliers in each sensor's pairs and moves the fit.
  for (std::size_t k = 0; k < 2; ++k) {
    EXPECT_GT(tight.joint->sensors[k].outliers, plain.joint->sensors[k].outliers) << k;
    EXPECT_GT(tight.joint->alone[k].outliers, plain.joint->alone[k].outliers) << k;
  }
  EXPECT_NE(tight.joint->intrinsics[0].value, plain.joint->intrinsics[0].value);
  EXPECT_NEAR(tight.joint->intrinsics[0].value, 0.076, 0.005 * 0.076);
  std::printf("outliers front %zu -> %zu, rear %zu -> %zu; r_L %.6f -> %.6f m\n",
              plain.joint->sensors[0].outliers, tight.joint->sensors[0].outliers,
              plain.joint->sensors[1].outliers, tight.joint->sensors[1].outliers,
              plain.joint->intrinsics[0].value, tight.joint->intrinsics[0].value);
}

TEST_F(JointSession, AnAdoptionRolledBackLeavesTheSessionAsItWas)
{
  // The steps of a joint adoption on one session: a fit of the front laser with another time
  // offset committed (model, pose, offset, odometry change), then put back.
  CalibrationSession session(configForSource(config_, 0), config_text_, "front_rear", options_);
  feedSpan(
      frontRearDrive(), 0.0, 30.0,
      [&](double t, const Eigen::VectorXd& raw) { session.addJointPositions(t, raw); },
      [&](std::size_t, double t, const Scan& scan) { session.addScan(t, scan, kFrames[0]); }, {0});
  session.flush();
  const std::string nominal_origin = session.activeModel().second;
  ASSERT_GT(session.paths().corrected.size(), 100u);
  CalibrateOutcome fitted = session.calibrate({});
  ASSERT_TRUE(fitted.success) << fitted.message;
  // As if the joint fit had estimated another offset: the pairing restarts at it.
  SessionFit fit = *fitted.fit;
  fit.job.time_offset_s = 0.03;
  const auto model = session.activeModel();
  ASSERT_NE(nominal_origin, model.second);
  const Pose2 pose = *session.sensorPose();
  fit.job.report.T_base_sensor = Pose2(0.31, 0.01, 0.02);
  fit.job.model = jointSensorModel(
      config_,
      [&] {
        JointFitReport joint;
        for (const ParameterEstimate& parameter : fit.job.report.parameters) {
          if (parameter.name.rfind("sensor_", 0) != 0)
            joint.intrinsics.push_back(parameter);
        }
        joint.sensors.resize(1);
        joint.sensors[0].T_base_sensor = fit.job.report.T_base_sensor;
        return joint;
      }(),
      0);
  PreparedAdoption adoption = session.prepareAdoption(fit, "diff_drive", config_.models);
  EXPECT_EQ(session.activeModel().first, model.first);  // prepared: nothing changed yet
  EXPECT_DOUBLE_EQ(session.timeOffset(), 0.0);
  session.commitAdoption(adoption);
  EXPECT_EQ(session.activeModel().first, fit.job.model);
  EXPECT_DOUBLE_EQ(session.timeOffset(), 0.03);
  EXPECT_DOUBLE_EQ(session.sensorPose()->x(), 0.31);
  session.rollBackAdoption(adoption);
  EXPECT_THROW(session.finishAdoption(adoption, 0), std::logic_error);  // not committed now
  PreparedAdoption none;
  EXPECT_THROW(session.commitAdoption(none), std::logic_error);
  EXPECT_EQ(session.activeModel().first, model.first);
  EXPECT_EQ(session.activeModel().second, model.second);
  EXPECT_DOUBLE_EQ(session.timeOffset(), 0.0);
  EXPECT_DOUBLE_EQ(session.sensorPose()->x(), pose.x());
  // The new offset restarted the odometry, and so does the old one put back; it runs on with
  // the previous model and pairs are made again.
  const std::size_t pairs = session.pairs().size();
  feedSpan(
      frontRearDrive(), 30.0, std::numeric_limits<double>::infinity(),
      [&](double t, const Eigen::VectorXd& raw) { session.addJointPositions(t, raw); },
      [&](std::size_t, double t, const Scan& scan) { session.addScan(t, scan, kFrames[0]); }, {0});
  session.flush();
  EXPECT_GT(session.pairs().size(), pairs + 10);
  EXPECT_GT(session.paths().corrected.size(), 50u);
  const auto [saved, message] = session.save();  // the previous fit's files
  ASSERT_TRUE(saved) << message;
  EXPECT_NEAR(readCalibrationResult(options_.output_directory + "/result.yaml").T_base_sensor.x(),
              pose.x(), 1e-9);
}

TEST_F(JointSession, TheWheelOdometryIsTheSameFromEverySensorsView)
{
  // ~odom is source 0's session's odometry; its base_link trajectory is the joint wheels'
  // integration, whichever sensor's view (wheels + that sensor's pose) drives it.
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, nullptr);
  feedJoint(session);
  ASSERT_TRUE(session.calibrate({}).outcome.success);
  std::vector<std::unique_ptr<OdometryIntegrator>> views;
  for (std::size_t k = 0; k < 2; ++k) {
    views.push_back(std::make_unique<OdometryIntegrator>(session.source(k).activeModel().first,
                                                         session.source(k).sensorPose(), 0.5));
  }
  EncoderDecoder decoder(encoderChannels(config_));
  for (const sim::JointStateSample& joints : frontRearDrive().joints) {
    const Eigen::VectorXd raw =
        Eigen::Map<const Eigen::VectorXd>(joints.positions.data(), joints.positions.size());
    const EncoderSample sample{joints.stamp_s, decoder.decode(raw)};
    for (auto& view : views)
      view->add(sample);
  }
  const Pose2 front = views[0]->pose(), rear = views[1]->pose();
  EXPECT_TRUE(views[0]->tracksBase());
  EXPECT_GT(std::hypot(front.x(), front.y()), 1.0);  // the robot went somewhere
  EXPECT_NEAR(front.x(), rear.x(), 1e-9);
  EXPECT_NEAR(front.y(), rear.y(), 1e-9);
  EXPECT_NEAR(normalizeAngle(front.theta() - rear.theta()), 0.0, 1e-9);
  // The sensors' own trajectories differ (they sit 0.6 m apart).
  const Pose2 front_sensor = views[0]->sensorPose(), rear_sensor = views[1]->sensorPose();
  EXPECT_GT(std::hypot(front_sensor.x() - rear_sensor.x(), front_sensor.y() - rear_sensor.y()),
            0.5);
}

}  // namespace
}  // namespace odometry_calibration
