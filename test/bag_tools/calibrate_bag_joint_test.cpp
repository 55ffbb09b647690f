// End-to-end (issue 35): calibrate_bag on a simulated bag of a robot with a front and a rear
// laser and a configuration listing both as ego_motion.sources: each laser paired and fitted on
// its own, then one joint fit of the wheels and both poses, written to result.yaml.
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

#include "odometry_calibration/bag_tools/bag_calibration.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// A joint calibrate_bag run: config/sim/scenarios/`name`.yaml simulated (`duration_s`, `seed`)
/// into a bag in a new temporary `directory`, then `calibrate` (calibrate_bag's job) with
/// config/`name`.yaml into `directory`/out. `before_run` sees the options first (e.g. to leave
/// an earlier run's files).
struct JointBagRun
{
  std::string directory;
  sim::Scenario scenario;
  BagCalibrationOptions options;
  int status = -1;
  std::string text;
};

using BagJob = std::function<int(const BagCalibrationOptions&, std::ostream&)>;

/// calibrate_bag's job with the usual joint fit.
int calibrateWithTheJointFit(const BagCalibrationOptions& options, std::ostream& out)
{
  return calibrateBags(options, out);
}

JointBagRun runJointBag(const std::string& name, unsigned seed,
                        const std::function<void(const BagCalibrationOptions&)>& before_run = {},
                        double duration_s = 90.0,
                        const BagJob& calibrate = calibrateWithTheJointFit)
{
  JointBagRun run;
  char pattern[] = "/tmp/calibrate_bag_joint_test.XXXXXX";
  run.directory = mkdtemp(pattern);
  run.scenario =
      sim::loadScenarioYaml(kConfig + "/sim/scenarios/" + name + ".yaml", kConfig + "/sim/worlds");
  run.scenario.duration_s = duration_s;
  run.scenario.seed = seed;
  const std::string bag = run.directory + "/front_rear.bag";
  simulateToBag(run.scenario, bag, "");
  run.options.config_path = kConfig + "/" + name + ".yaml";
  run.options.bags = {bag};
  run.options.output_dir = run.directory + "/out";
  run.options.quiet = true;
  if (before_run)
    before_run(run.options);
  std::ostringstream out;
  run.status = calibrate(run.options, out);
  run.text = out.str();
  return run;
}

/// result.yaml's `sensors`: each laser's pose within 1 cm and 0.01 rad of `scenario`'s, with
/// a σ.
void expectPosesNearTruth(const YAML::Node& sensors, const sim::Scenario& scenario)
{
  const std::vector<sim::LaserOptions> lasers = sim::allLasers(scenario);
  ASSERT_EQ(sensors.size(), lasers.size());
  for (std::size_t s = 0; s < lasers.size(); ++s) {
    const YAML::Node pose = sensors[s]["T_base_sensor"];
    const Pose2& truth = lasers[s].T_base_laser;
    EXPECT_NEAR(pose["x_m"].as<double>(), truth.x(), 0.01) << s;
    EXPECT_NEAR(pose["y_m"].as<double>(), truth.y(), 0.01) << s;
    EXPECT_NEAR(normalizeAngle(pose["theta_rad"].as<double>() - truth.theta()), 0.0, 0.01) << s;
    EXPECT_GT(pose["x_m_sigma"].as<double>(), 0.0) << s;
  }
}

TEST(CalibrateBagJoint, FrontAndRearLasersGiveOneSetOfWheelsAndBothPoses)
{
  char pattern[] = "/tmp/calibrate_bag_joint_test.XXXXXX";
  const std::string directory = mkdtemp(pattern);
  sim::Scenario scenario = sim::loadScenarioYaml(
      kConfig + "/sim/scenarios/diff_drive_front_rear.yaml", kConfig + "/sim/worlds");
  scenario.duration_s = 90.0;
  scenario.seed = 5;
  scenario.extra_lasers.at(0).time_offset_s = 0.05;  // the rear laser's own clock
  const std::string bag = directory + "/front_rear.bag";
  simulateToBag(scenario, bag, "");
  BagCalibrationOptions options;
  options.config_path = kConfig + "/diff_drive_front_rear.yaml";
  options.bags = {bag};
  options.output_dir = directory + "/out";
  options.quiet = true;
  std::ostringstream out;
  const int status = calibrateBags(options, out);
  const std::string text = out.str();
  EXPECT_TRUE(status == 0 || status == 4) << status << "\n" << text;
  EXPECT_NE(text.find("=== source 1: /scan_rear ==="), std::string::npos) << text;
  EXPECT_NE(text.find("wheel parameters each sensor implies alone"), std::string::npos) << text;

  const YAML::Node result = YAML::LoadFile(options.output_dir + "/result.yaml");
  const YAML::Node sensors = result["sensors"];
  ASSERT_EQ(sensors.size(), 2u) << text;
  expectPosesNearTruth(sensors, scenario);
  EXPECT_EQ(sensors[1]["topic"].as<std::string>(), "/scan_rear");
  EXPECT_EQ(sensors[1]["frame"].as<std::string>(), "laser_rear");
  // Each laser's own time offset: the rear one's stamps run 0.05 s late, its encoders are taken
  // 0.05 s earlier (tau = -0.05).
  EXPECT_NEAR(sensors[0]["time_offset_s"].as<double>(), 0.0, 0.01);
  EXPECT_NEAR(sensors[1]["time_offset_s"].as<double>(), -0.05, 0.01);
  // The model the node would load: the joint wheels, the first sensor's pose.
  const YAML::Node model = result["model"];
  EXPECT_NEAR(model["left_wheel_radius_m"].as<double>(), 0.076, 0.005 * 0.076);
  EXPECT_NEAR(model["right_wheel_radius_m"].as<double>(), 0.078, 0.005 * 0.078);
  EXPECT_NEAR(model["wheel_separation_m"].as<double>(), 0.32, 0.005 * 0.32);
  EXPECT_TRUE(fs::is_regular_file(options.output_dir + "/joint_report.txt"));
  EXPECT_TRUE(fs::is_regular_file(options.output_dir + "/source_1/result.yaml"));
  // As the node's ~save: one URDF joint per laser, the joint wheels for the controller.
  const std::string urdf = test_support::readFile(options.output_dir + "/laser_joints.urdf");
  EXPECT_NE(urdf.find("laser_rear"), std::string::npos) << urdf;
  EXPECT_NE(urdf.find("laser_front"), std::string::npos) << urdf;
  const YAML::Node controller = YAML::LoadFile(options.output_dir + "/controller.yaml");
  EXPECT_NEAR(controller["wheel_separation_multiplier"].as<double>() * 0.33,
              model["wheel_separation_m"].as<double>(), 1e-6);
  fs::remove_all(directory);
}

// The same with a skid-steer robot (config/sim/scenarios/skid_steer_front_rear.yaml: effective
// separation 1.45 times the 0.5 m track, right wheels 1 % larger) and
// config/skid_steer_front_rear.yaml: one set of sides and both poses, the multipliers of the
// geometric values in result.yaml and controller.yaml.
TEST(CalibrateBagJoint, SkidSteerFrontAndRearLasersGiveOneSetOfSidesAndBothPoses)
{
  const JointBagRun run = runJointBag("skid_steer_front_rear", 380);
  const std::string& directory = run.directory;
  const sim::Scenario& scenario = run.scenario;
  const BagCalibrationOptions& options = run.options;
  const int status = run.status;
  const std::string& text = run.text;
  EXPECT_TRUE(status == 0 || status == 4) << status << "\n" << text;
  EXPECT_NE(text.find("Joint fit of 2 sensors ('skid_steer')"), std::string::npos) << text;
  const YAML::Node result = YAML::LoadFile(options.output_dir + "/result.yaml");
  const YAML::Node sensors = result["sensors"];
  ASSERT_EQ(sensors.size(), 2u) << text;
  expectPosesNearTruth(sensors, scenario);
  EXPECT_EQ(result["model"]["model"].as<std::string>(), "skid_steer");
  const YAML::Node sides = result["model"]["sides"];
  EXPECT_NEAR(sides["left_wheel_radius_m"].as<double>(), 0.1, 0.005 * 0.1);
  EXPECT_NEAR(sides["right_wheel_radius_m"].as<double>(), 0.101, 0.005 * 0.101);
  EXPECT_NEAR(sides["wheel_separation_m"].as<double>(), 0.725, 0.005 * 0.725);
  EXPECT_NE(test_support::readFile(options.output_dir + "/result.yaml")
                .find("wheel_separation_multiplier"),
            std::string::npos);
  const YAML::Node controller = YAML::LoadFile(options.output_dir + "/controller.yaml");
  EXPECT_DOUBLE_EQ(controller["wheel_separation"].as<double>(), 0.5);  // the geometric value
  EXPECT_NEAR(controller["wheel_separation_multiplier"].as<double>(),
              sides["wheel_separation_m"].as<double>() / 0.5, 1e-6);
  EXPECT_NE(test_support::readFile(options.output_dir + "/laser_joints.urdf").find("laser_rear"),
            std::string::npos);
  fs::remove_all(directory);
}

TEST(CalibrateBagJoint, SeveralSourcesWithAModelWithoutJointFitAreRefusedNamingIt)
{
  char pattern[] = "/tmp/calibrate_bag_joint_test.XXXXXX";
  const std::string directory = mkdtemp(pattern);
  std::string config = test_support::readFile(kConfig + "/diff_drive_front_rear.yaml");
  config.replace(config.find("model: diff_drive"), 17, "model: linear");
  const std::string config_path = directory + "/linear.yaml";
  std::ofstream(config_path) << config;
  BagCalibrationOptions options;
  options.config_path = config_path;
  options.bags = {directory + "/never_read.bag"};
  options.output_dir = directory + "/out";
  std::ostringstream out;
  try {
    calibrateBags(options, out);
    ADD_FAILURE() << "several sources with model linear accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("model 'linear' has no joint fit"), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(options.output_dir));
  // The one-source options a joint run does not take are refused by name, not ignored.
  options.config_path = kConfig + "/diff_drive_front_rear.yaml";
  options.test_bags = {options.config_path};  // (an existing file: checked before the refusal)
  try {
    calibrateBags(options, out);
    ADD_FAILURE() << "--test with several sources accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("option --test is not supported with several"),
              std::string::npos)
        << error.what();
  }
  options.test_bags.clear();
  options.interval = "0.5";
  try {
    calibrateBags(options, out);
    ADD_FAILURE() << "--interval with several sources accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("option --interval"), std::string::npos)
        << error.what();
  }
  EXPECT_FALSE(fs::exists(options.output_dir));
  fs::remove_all(directory);
}

// The tricycle (config/sim/scenarios/tricycle_front_rear.yaml: the seed's values, a laser over
// the steering wheel and one at the back turned round) with config/tricycle_front_rear.yaml:
// one set of Ks, Kt, axis length and steering offset, both poses; no controller.yaml (no
// controller form).
TEST(CalibrateBagJoint, TricycleFrontAndRearLasersGiveOneSetOfKinematicsAndBothPoses)
{
  // An earlier run's files in the output folder: a controller.yaml (of another robot) must not
  // stay beside this tricycle's result, a source folder's old file must go with its folder.
  const JointBagRun run =
      runJointBag("tricycle_front_rear", 381, [](const BagCalibrationOptions& options) {
        fs::create_directories(options.output_dir + "/source_1");
        std::ofstream(options.output_dir + "/controller.yaml") << "wheel_separation: 0.33\n";
        std::ofstream(options.output_dir + "/source_1/stale.txt") << "an earlier run\n";
      });
  const std::string& directory = run.directory;
  const sim::Scenario& scenario = run.scenario;
  const BagCalibrationOptions& options = run.options;
  const int status = run.status;
  const std::string& text = run.text;
  EXPECT_TRUE(status == 0 || status == 4) << status << "\n" << text;
  const YAML::Node result = YAML::LoadFile(options.output_dir + "/result.yaml");
  const YAML::Node sensors = result["sensors"];
  ASSERT_EQ(sensors.size(), 2u) << text;
  expectPosesNearTruth(sensors, scenario);
  const YAML::Node model = result["model"];
  EXPECT_EQ(model["model"].as<std::string>(), "tricycle");
  EXPECT_NEAR(model["steering_scale"].as<double>(), 0.56, 0.005 * 0.56);
  EXPECT_NEAR(model["traction_scale_m_per_turn"].as<double>(), 0.0106, 0.005 * 0.0106);
  EXPECT_NEAR(model["axis_length_m"].as<double>(), 1.54, 0.005 * 1.54);
  EXPECT_NEAR(model["steering_offset_rad"].as<double>(), -0.064, 0.002);
  EXPECT_TRUE(fs::is_regular_file(options.output_dir + "/laser_joints.urdf"));
  EXPECT_FALSE(fs::exists(options.output_dir + "/controller.yaml"));
  EXPECT_FALSE(fs::exists(options.output_dir + "/source_1/stale.txt"));
  EXPECT_TRUE(fs::is_regular_file(options.output_dir + "/source_1/result.yaml"));
  EXPECT_NE(text.find("laser_joints.urdf, joint_report.txt, source_0/, source_1/}"),
            std::string::npos)
      << text;
  for (const auto& entry : fs::directory_iterator(options.output_dir))  // no staging left
    EXPECT_EQ(entry.path().filename().string().rfind(".result_set", 0), std::string::npos);
  fs::remove_all(directory);
}

// The joint fit failing after both lasers were fitted alone (forced here: it cannot fail on
// pairs each sensor's fit alone took): each source's text is printed and its files written as
// one set, an earlier run's joint files removed, and the failure reported by an exception
// (calibrate_bag: "error: ..." and exit 1). Before, nothing was printed or written.
TEST(CalibrateBagJoint, AFailedJointFitStillWritesEverySourcesFitAlone)
{
  std::string thrown;
  std::size_t rear_pairs = 0;
  const JointFitFunction failing =
      [&](const CalibrationConfig&, const std::vector<JointSourceInput>& inputs) -> JointFitReport {
    rear_pairs = inputs.at(1).pairs.size();
    throw std::invalid_argument("diff_drive joint fit, sensor 1: forced by the test");
  };
  const JointBagRun run = runJointBag(
      "diff_drive_front_rear", 382,
      [](const BagCalibrationOptions& options) {  // an earlier joint run's files
        fs::create_directories(options.output_dir + "/source_1");
        for (const char* name : {"result.yaml", "controller.yaml", "laser_joints.urdf"})
          std::ofstream(options.output_dir + "/" + name) << "an earlier run\n";
        std::ofstream(options.output_dir + "/source_1/stale.txt") << "an earlier run\n";
      },
      40.0,
      [&](const BagCalibrationOptions& options, std::ostream& out) {
        try {
          return calibrateBags(options, out, failing);
        } catch (const std::runtime_error& error) {
          thrown = error.what();
          return 1;
        }
      });
  const std::string& out = run.options.output_dir;
  EXPECT_EQ(run.status, 1) << run.text;
  EXPECT_EQ(thrown.find("the joint diff_drive fit failed after every source was fitted alone: "
                        "diff_drive joint fit, sensor 1: forced by the test (each source's fit "
                        "alone is in " +
                        out + "/source_<k>/; no joint result.yaml)"),
            0u)
      << thrown;
  EXPECT_GT(rear_pairs, 10u);  // the rear laser was paired and fitted alone
  for (const char* part : {"=== source 0: /scan_front ===", "=== source 1: /scan_rear ===",
                           "=== joint fit ===\nthe joint diff_drive fit failed",
                           "written: ", "joint_report.txt, source_0/, source_1/}"})
    EXPECT_NE(run.text.find(part), std::string::npos) << part << "\n" << run.text;
  for (const std::string source : {"/source_0/", "/source_1/"}) {
    for (const char* name : {"result.yaml", "report.txt", "pairs.csv", "controller.yaml"})
      EXPECT_TRUE(fs::is_regular_file(out + source + name)) << source << name;
  }
  EXPECT_FALSE(fs::exists(out + "/source_1/stale.txt"));
  for (const char* name : {"result.yaml", "controller.yaml", "laser_joints.urdf"})
    EXPECT_FALSE(fs::exists(out + "/" + name)) << name;  // none passes for this run's
  EXPECT_NE(test_support::readFile(out + "/joint_report.txt").find("forced by the test"),
            std::string::npos);
  EXPECT_NE(test_support::readFile(out + "/source_1/report.txt").find("/scan_rear"),
            std::string::npos);
  for (const auto& entry : fs::directory_iterator(out))  // no staging left
    EXPECT_EQ(entry.path().filename().string().rfind(".result_set", 0), std::string::npos);
  fs::remove_all(run.directory);
}

}  // namespace
}  // namespace odometry_calibration
