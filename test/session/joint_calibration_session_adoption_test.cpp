// The session of several ego-motion sources (issue 35): a joint fit adopted by every source or
// none, ~save as one set, ~calibrate's model and options, a rolled-back adoption, the wheel
// odometry through every sensor's view.
#include <algorithm>

#include <gtest/gtest.h>

#include "support/joint_session_fixture.h"

namespace odometry_calibration {
namespace {

using namespace test;  // the fixture's drives and helpers

/// base_link's pose after integrating the front/rear drive's encoder samples (stamps up to
/// `until_s`) with `model` seen from a sensor at `T_base_sensor`, in windows of `interval_s`, as
/// a session's odometry does.
Pose2 integrateDrive(const CalibrationConfig& config, std::shared_ptr<const MotionModel> model,
                     const std::optional<Pose2>& T_base_sensor, double interval_s, double until_s)
{
  OdometryIntegrator odometry(std::move(model), T_base_sensor, interval_s);
  EncoderDecoder decoder(encoderChannels(config));
  for (const sim::JointStateSample& joints : frontRearDrive().joints) {
    if (joints.stamp_s > until_s)
      break;
    const Eigen::VectorXd raw =
        Eigen::Map<const Eigen::VectorXd>(joints.positions.data(), joints.positions.size());
    odometry.add({joints.stamp_s, decoder.decode(raw)});
  }
  EXPECT_TRUE(odometry.tracksBase());
  return odometry.pose();
}

/// A status's name, level, message and values in one line each (to compare two).
std::string statusText(const std::vector<SessionStatusReport>& statuses)
{
  std::string text;
  for (const SessionStatusReport& status : statuses) {
    text += status.name + " [" + std::to_string(static_cast<int>(status.level)) + "] " +
            status.message + "\n";
    for (const auto& [key, value] : status.values)
      text += "  " + key + ": " + value + "\n";
  }
  return text;
}

/// The largest difference of position [m] and heading [rad] between two poses.
double poseDifference(const Pose2& a, const Pose2& b)
{
  return std::max(std::hypot(a.x() - b.x(), a.y() - b.y()),
                  std::abs(normalizeAngle(a.theta() - b.theta())));
}

TEST_F(JointSession, AJointFitIsAdoptedByEverySourceOrByNone)
{
  // The rear laser's listener (the node's tf broadcaster) fails while `fail_rear` is set: the
  // rear source cannot adopt the joint fit after the front one has.
  bool fail_rear = false;
  std::optional<Pose2> front_told;  // the front sensor's pose last told to its listener
  std::vector<OdometryState> odom;  // what ~odom publishes (the front source's odometry)
  const auto listener = [&](std::size_t k) {
    SessionListener own;
    own.sensor_pose = [&, k](const std::optional<Pose2>& pose, const std::string&) {
      if (k == 0)
        front_told = pose;
      else if (fail_rear)
        throw std::runtime_error("cannot broadcast base_link -> laser_rear");
    };
    if (k == 0)
      own.odometry = [&](const OdometryState& state) { odom.push_back(state); };
    return own;
  };
  options_.odometry_options.path_spacing_s = 0.0;  // a fit integrates every sample again
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, listener);
  feedJointSpan(session, frontRearDrive(), 0.0, 25.0);
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
  // The health monitor scores both lasers' pairs against the fit for a while.
  feedJointSpan(session, frontRearDrive(), 25.0, 32.0);
  const std::string health = statusText(session.jointStatusReports());
  ASSERT_NE(health.find("watching: joint fit of"), std::string::npos) << health;
  ASSERT_EQ(health.find("pairs scored: 0\n"), std::string::npos) << health;
  const std::optional<double> statistic = session.healthStatistic();
  ASSERT_TRUE(statistic);
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
  // The health monitor still watches the adopted fit, its charts as they were (not restarted,
  // not watching the refused fit).
  EXPECT_EQ(statusText(session.jointStatusReports()), health);
  EXPECT_EQ(session.healthStatistic(), statistic);
  // ~odom runs on with the adopted fit (the front laser had taken the refused one, then put
  // it back): from the start of the drive, the adopted wheels' odometry to 1e-9, not the
  // refused fit's.
  feedJointSpan(session, frontRearDrive(), 32.0, std::numeric_limits<double>::infinity());
  ASSERT_FALSE(odom.empty());
  const double interval_s = fit.outcome.fit->fit_interval_s;
  const double until_s = odom.back().stamp_s;
  const Pose2 adopted_odom = integrateDrive(config_, models[0], poses[0], interval_s, until_s);
  EXPECT_LT(poseDifference(odom.back().pose, adopted_odom), 1e-9);
  const Pose2 refused_odom =
      integrateDrive(config_, jointSensorModel(config_, *refused.joint, 0),
                     refused.joint->sensors[0].T_base_sensor, interval_s, until_s);
  EXPECT_GT(poseDifference(odom.back().pose, refused_odom), 1e-6);
  std::printf(
      "~odom after the refused fit: %.3g from the adopted fit's odometry, %.3g from the "
      "refused one's\n",
      poseDifference(odom.back().pose, adopted_odom),
      poseDifference(odom.back().pose, refused_odom));
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
  // A model without a joint fit is named as such (not as a problem of options, none given),
  // with the models that have one.
  EXPECT_EQ(refusal("gp", ""),
            "cannot fit gp jointly: model 'gp' has no joint fit of several sources "
            "(ego_motion.sources); the models that have one are diff_drive, skid_steer, mecanum "
            "and tricycle (or calibrate each source alone with a one-source configuration)");
  EXPECT_EQ(refusal("linear", "{linear: {}}").find("cannot fit linear jointly: model 'linear'"),
            0u);
  EXPECT_NE(refusal("", "{gp: {kernel: linear}}").find("option 'gp' does not apply"),
            std::string::npos);
  EXPECT_NE(refusal("", "{diff_drive: {sensor_pose: [0, 0, 0]}}")
                .find("option 'diff_drive.sensor_pose' does not apply"),
            std::string::npos);
  // The configuration has no mecanum wheels: no options given, none blamed.
  EXPECT_EQ(refusal("mecanum", "").find("cannot fit mecanum jointly with the configuration: "), 0u);
  const std::string bad_threshold = refusal("", "{diff_drive: {huber_threshold: -1}}");
  EXPECT_EQ(bad_threshold.find("cannot fit diff_drive jointly with the options {diff_drive: "
                               "{huber_threshold: -1}}: "),
            0u)
      << bad_threshold;
  EXPECT_NE(bad_threshold.find("huber_threshold"), std::string::npos);
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
  options_.odometry_options.path_spacing_s = 0.0;  // a fit integrates every sample again
  std::vector<OdometryState> odom;                 // what ~odom publishes
  SessionListener listener;
  listener.odometry = [&odom](const OdometryState& state) { odom.push_back(state); };
  CalibrationSession session(configForSource(config_, 0), config_text_, "front_rear", options_,
                             listener);
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
  const auto healthText = [&] {  // the monitor's status: what it watches, its charts
    std::vector<SessionStatusReport> statuses = session.statusReports(1.0);
    statuses.erase(std::remove_if(statuses.begin(), statuses.end(),
                                  [](const SessionStatusReport& status) {
                                    return status.name != "calibration health";
                                  }),
                   statuses.end());
    return statusText(statuses);
  };
  const std::string health = healthText();
  ASSERT_NE(health.find("watching: fit of"), std::string::npos) << health;
  const std::size_t corrected_poses = session.paths().corrected.size();
  const Pose2 odom_before = odom.back().pose;
  fit.job.report.pairs_used = 7;  // (a monitor watching this fit would say "fit of 7 pairs")
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
  // The health monitor watches the previous fit as before (its reference not moved).
  EXPECT_EQ(healthText(), health);
  // The new offset restarted the odometry; put back, it runs on from where it was (its path
  // kept), with the previous model, and pairs are made again.
  EXPECT_EQ(session.paths().corrected.size(), corrected_poses);
  const std::size_t pairs = session.pairs().size();
  const std::size_t published = odom.size();
  feedSpan(
      frontRearDrive(), 30.0, std::numeric_limits<double>::infinity(),
      [&](double t, const Eigen::VectorXd& raw) { session.addJointPositions(t, raw); },
      [&](std::size_t, double t, const Scan& scan) { session.addScan(t, scan, kFrames[0]); }, {0});
  session.flush();
  EXPECT_GT(session.pairs().size(), pairs + 10);
  EXPECT_GT(session.paths().corrected.size(), corrected_poses + 400);
  ASSERT_GT(odom.size(), published + 400);
  // The first pose after the roll-back continues the one before (a step of 20 ms, not a jump
  // back to the origin), and the last is the previous fit's odometry of the whole drive.
  EXPECT_LT(poseDifference(odom[published].pose, odom_before), 0.05);
  const Pose2 whole_drive =
      integrateDrive(config_, model.first, pose, fitted.fit->fit_interval_s, odom.back().stamp_s);
  EXPECT_LT(poseDifference(odom.back().pose, whole_drive), 1e-9);
  EXPECT_GT(std::hypot(odom_before.x(), odom_before.y()), 0.5);  // (the origin is far)
  // ~save writes the previous fit's files.
  const auto [saved, message] = session.save();
  ASSERT_TRUE(saved) << message;
  EXPECT_NEAR(readCalibrationResult(options_.output_directory + "/result.yaml").T_base_sensor.x(),
              pose.x(), 1e-9);
}

TEST_F(JointSession, OdomAfterAJointFitIsTheJointWheelsOdometry)
{
  // What ~odom publishes (the node sends the front source's odometry as it comes): after a
  // joint fit, base_link integrated with the joint wheels from the start of the drive, the same
  // through either sensor's view (the wheels with that sensor's pose); the rear source
  // publishes none.
  options_.odometry_options.path_spacing_s = 0.0;  // a fit integrates every sample again
  std::vector<OdometryState> published[2];
  const auto listener = [&](std::size_t k) {
    SessionListener own;
    own.odometry = [&published, k](const OdometryState& state) { published[k].push_back(state); };
    return own;
  };
  JointCalibrationSession session(config_, config_text_, "front_rear", options_, listener);
  feedJointSpan(session, frontRearDrive(), 0.0, 25.0);
  const JointCalibrateOutcome fit = session.calibrate({});
  ASSERT_TRUE(fit.outcome.success) << fit.outcome.message;
  const std::size_t at_fit = published[0].size();
  feedJointSpan(session, frontRearDrive(), 25.0, std::numeric_limits<double>::infinity());
  ASSERT_GT(published[0].size(), at_fit + 500);  // the last 15 s, 50 Hz encoders
  EXPECT_TRUE(published[1].empty());
  const OdometryState& last = published[0].back();
  EXPECT_TRUE(last.tracks_base);
  EXPECT_GT(std::hypot(last.pose.x(), last.pose.y()), 1.0);  // the robot went somewhere
  for (std::size_t k = 0; k < 2; ++k) {
    const Pose2 view = integrateDrive(config_, session.source(k).activeModel().first,
                                      session.source(k).sensorPose(),
                                      fit.outcome.fit->fit_interval_s, last.stamp_s);
    EXPECT_LT(poseDifference(last.pose, view), 1e-9) << k;
  }
  // Before the fit ~odom was the nominal robot's; the joint wheels' differs from it.
  const std::vector<StampedPose2> nominal = session.source(0).paths().nominal;
  ASSERT_FALSE(nominal.empty());
  EXPECT_GT(poseDifference(last.pose, nominal.back().pose), 0.01);
}

}  // namespace
}  // namespace odometry_calibration
