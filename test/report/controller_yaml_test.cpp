#include "odometry_calibration/report/controller_yaml.h"

#include <cmath>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>

namespace odometry_calibration {
namespace {

/// Every non-comment line of `text` carries a "# sigma" comment, except the nominal values.
void expectSigmaOnEveryFittedLine(const std::string& text)
{
  std::istringstream lines(text);
  std::string line;
  while (std::getline(lines, line)) {
    if (line.empty() || line[0] == '#' || line.find("configured nominal") != std::string::npos ||
        line.back() == ':')  // a map's key
      continue;
    EXPECT_NE(line.find("# sigma"), std::string::npos) << line;
  }
}

ModelReport diffDriveReport(const std::string& model)
{
  ModelReport report;
  report.model = model;
  report.pairs_used = 240;
  // name, unit, initial (configured nominal), value, sigma
  report.parameters = {{"left_wheel_radius", "m", 0.1, 0.0995, 0.0002},
                       {"right_wheel_radius", "m", 0.1, 0.101, 0.0002},
                       {"wheel_separation", "m", 0.5, 0.73, 0.002},
                       {"sensor_x", "m", 0.2, 0.25, 0.001}};
  return report;
}

TEST(ControllerYaml, DiffDriveControllerMultipliersRelativeToTheNominalValues)
{
  const std::string text = controllerYaml(diffDriveReport("skid_steer"), "drive.bag");
  const YAML::Node yaml = YAML::Load(text);
  EXPECT_DOUBLE_EQ(yaml["wheel_separation"].as<double>(), 0.5);
  EXPECT_DOUBLE_EQ(yaml["wheel_radius"].as<double>(), 0.1);
  EXPECT_NEAR(yaml["wheel_separation_multiplier"].as<double>(), 1.46, 1e-6);
  EXPECT_NEAR(yaml["left_wheel_radius_multiplier"].as<double>(), 0.995, 1e-6);
  EXPECT_NEAR(yaml["right_wheel_radius_multiplier"].as<double>(), 1.01, 1e-6);
  EXPECT_EQ(yaml.size(), 5u);  // nothing else a controller would choke on
  // The multiplier's sigma is the separation's over the nominal value: 0.002 / 0.5.
  EXPECT_NE(text.find("wheel_separation_multiplier: 1.46  # sigma 0.004; fitted effective "
                      "separation 0.73 m, sigma 0.002 m"),
            std::string::npos)
      << text;
  EXPECT_NE(text.find("drive.bag"), std::string::npos);
  EXPECT_NE(text.find("model skid_steer, 240 pairs"), std::string::npos);
  expectSigmaOnEveryFittedLine(text);
}

TEST(ControllerYaml, TrackedBaseGetsTheSeparationOnTheSpotAsAComment)
{
  ModelReport report = diffDriveReport("tracked");
  report.parameters.insert(report.parameters.begin() + 3,
                           {"separation_growth", "m", 0.0, 0.1, 0.001});
  const std::string text = controllerYaml(report, "drive.bag");
  const YAML::Node yaml = YAML::Load(text);
  EXPECT_EQ(yaml.size(), 5u);  // the controller's keys only: the rest is comments
  EXPECT_NEAR(yaml["wheel_separation_multiplier"].as<double>(), 1.46, 1e-6);  // b0 = 0.73 m
  // On the spot b0 + b1 = 0.83 m: 1.66 times the nominal 0.5 m.
  EXPECT_NE(text.find("#   b(nu) = 0.73 + 0.1 nu m (separation_growth sigma 0.001 m); on the "
                      "spot 0.83 m,\n#   wheel_separation_multiplier 1.66 for a base"),
            std::string::npos)
      << text;
  EXPECT_EQ(controllerYaml(diffDriveReport("diff_drive"), "b").find("tracked base"),
            std::string::npos);
}

TEST(ControllerYaml, UndeterminedSigmaAndWarningsAreSaid)
{
  ModelReport report = diffDriveReport("diff_drive");
  report.parameters[2].sigma = std::nan("");
  report.warnings.push_back("wheel_separation not determined");
  const std::string text = controllerYaml(report, "x.bag");
  EXPECT_NE(text.find("wheel_separation_multiplier: 1.46  # sigma unavailable"), std::string::npos)
      << text;
  EXPECT_NE(text.find("WARNINGS"), std::string::npos);
}

TEST(ControllerYaml, MecanumRadiiAndLeverFromTheParameterNames)
{
  ModelReport report;
  report.model = "mecanum";
  report.parameters = {{"wheel_radius_front_left", "m", 0.05, 0.051, 0.0001},
                       {"wheel_radius_front_right", "m", 0.05, 0.050, 0.0001},
                       {"wheel_radius_rear_left", "m", 0.05, 0.049, 0.0001},
                       {"wheel_radius_rear_right", "m", 0.05, 0.050, 0.0001},
                       {"lx_plus_ly", "m", 0.35, 0.352, 0.001},
                       {"sensor_x", "m", 0.2, 0.2, 0.001}};
  const std::string text = controllerYaml(report, "m.bag");
  // mecanum_drive_controller's own nested keys, and nothing else a controller would read.
  const YAML::Node yaml = YAML::Load(text);
  ASSERT_EQ(yaml.size(), 1u) << text;
  const YAML::Node kinematics = yaml["kinematics"];
  ASSERT_TRUE(kinematics.IsMap()) << text;
  EXPECT_EQ(kinematics.size(), 2u);
  EXPECT_NEAR(kinematics["wheels_radius"].as<double>(), 0.05, 1e-9);
  EXPECT_DOUBLE_EQ(kinematics["sum_of_robot_center_projection_on_X_Y_axis"].as<double>(), 0.352);
  EXPECT_NE(text.find("mecanum_drive_controller"), std::string::npos);
  EXPECT_NE(text.find("ROS 2 Jazzy"), std::string::npos);
  // The per-wheel radii, which no controller reads, as comments.
  EXPECT_NE(text.find("#   wheel_radius_front_left: 0.051  (sigma 0.0001 [m]"), std::string::npos)
      << text;
  EXPECT_NE(text.find("#   wheel_radius_rear_left: 0.049  (sigma 0.0001 [m]"), std::string::npos);
  // The mean's sigma: sqrt(4 * 0.0001^2) / 4 = 0.00005.
  EXPECT_NE(text.find("  wheels_radius: 0.05  # sigma 5e-05 [m]; the mean of the 4 radii"),
            std::string::npos)
      << text;
  expectSigmaOnEveryFittedLine(text);
}

TEST(ControllerYaml, AJointFitsHeaderCountsEverySensorsPairs)
{
  // A joint fit of two lasers (119 front, 121 rear pairs): the header gives the joint fit's
  // pairs, not the first sensor's alone; the values are the joint wheels.
  JointFitReport joint;
  joint.model = "diff_drive";
  const ModelReport wheels = diffDriveReport("diff_drive");
  joint.intrinsics.assign(wheels.parameters.begin(), wheels.parameters.begin() + 3);
  joint.sensors.resize(2);
  joint.sensors[0].pairs = 119;
  joint.sensors[1].pairs = 121;
  const std::string text = jointControllerYaml(joint, "front_rear.bag");
  EXPECT_NE(text.find("(joint diff_drive fit of 2 sensors, 119 + 121 = 240 pairs)."),
            std::string::npos)
      << text;
  EXPECT_EQ(text.find("WARNINGS"), std::string::npos);
  EXPECT_NEAR(YAML::Load(text)["wheel_separation_multiplier"].as<double>(), 1.46, 1e-6);
  joint.sensors[1].warnings.push_back("sensor_theta not determined");  // the rear's warning
  EXPECT_NE(jointControllerYaml(joint, "front_rear.bag")
                .find("240 pairs; the fit has WARNINGS, see joint_report.txt)."),
            std::string::npos);
}

TEST(ControllerYaml, NoControllerFormForModelFreeOrTricycleFits)
{
  ModelReport gp;
  gp.model = "gp";
  gp.parameters = {{"length_scale_x", "-", NAN, 1.0, NAN}};
  EXPECT_EQ(controllerYaml(gp, "a.bag"), "");
  ModelReport tricycle;
  tricycle.model = "tricycle";
  tricycle.parameters = {{"axis_length", "m", 1.5, 1.54, 0.01}};
  EXPECT_EQ(controllerYaml(tricycle, "a.bag"), "");
}

}  // namespace
}  // namespace odometry_calibration
