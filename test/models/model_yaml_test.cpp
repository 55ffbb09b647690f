#include "odometry_calibration/models/model_yaml.h"

#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace odometry_calibration {
namespace {

/// A model's saved values, as a key table (the way the models list theirs).
struct Saved
{
  int index = 0;
  double radius_m = 0.0;
  std::vector<int> joints;
};

template <class Values, class Visit>
void visitSaved(Values& values, const Visit& visit)
{
  visit("index", values.index);
  visit("radius_m", values.radius_m);
  visit("joints", values.joints);
}

std::string writeSaved(const Saved& saved)
{
  return writeModelYaml("toy", [&](YAML::Emitter& out) {
    visitSaved(saved, YamlKeyWriter(out));
    emitSensorPoseYaml(out, Pose2(0.1, -0.2, 0.3), Eigen::Matrix3d::Identity() * 1e-6);
  });
}

Saved readSaved(const std::string& text)
{
  return readModelYaml(text, "toy", [](const YAML::Node& node) {
    Saved saved;
    visitSaved(saved, YamlKeyReader(node));
    return saved;
  });
}

std::string runtimeError(const std::string& text)
{
  try {
    readSaved(text);
  } catch (const std::runtime_error& error) {
    return error.what();
  }
  return "";
}

TEST(ModelYaml, TheKeyTableRoundTripsBitExactWithTheModelFirst)
{
  Saved saved;
  saved.index = 3;
  saved.radius_m = 0.07700000000000001;  // needs all 17 digits
  saved.joints = {2, 0};
  const std::string text = writeSaved(saved);
  EXPECT_EQ(text.rfind("model: toy\n", 0), 0u) << text;
  EXPECT_NE(text.find("joints: [2, 0]"), std::string::npos) << text;
  EXPECT_EQ(text.back(), '\n');
  const Saved read = readSaved(text);
  EXPECT_EQ(read.index, 3);
  EXPECT_EQ(read.radius_m, saved.radius_m);  // bit-exact
  EXPECT_EQ(read.joints, saved.joints);
  const SensorPoseYaml pose = readSensorPoseYaml(YAML::Load(text));
  EXPECT_EQ(pose.T_base_sensor.y(), -0.2);
  EXPECT_EQ(pose.prediction_covariance(2, 2), 1e-6);
  EXPECT_EQ(pose.prediction_covariance(0, 1), 0.0);
}

TEST(ModelYaml, ErrorsNameTheModel)
{
  EXPECT_EQ(runtimeError("model: other\nindex: 1\n"), "not a toy model");
  const std::string missing = runtimeError("model: toy\nindex: 1\n");
  EXPECT_EQ(missing.rfind("toy model YAML: ", 0), 0u) << missing;
  const std::string wrong_type = runtimeError("model: toy\nindex: one\nradius_m: 1\njoints: []\n");
  EXPECT_EQ(wrong_type.rfind("toy model YAML: ", 0), 0u) << wrong_type;
  EXPECT_EQ(runtimeError("model: [toy").rfind("toy model YAML: ", 0), 0u);
  // No `model` key: yaml-cpp names it (the map is read as a const node, as the models always
  // did, so the key is reported missing rather than read as null).
  const std::string no_model = runtimeError("{}");
  EXPECT_EQ(no_model.rfind("toy model YAML: ", 0), 0u) << no_model;
  EXPECT_NE(no_model.find("\"model\""), std::string::npos) << no_model;
}

TEST(ModelYaml, AWrongSensorPoseCountIsRefused)
{
  const YAML::Node node = YAML::Load("T_base_sensor: [1, 2]\nprediction_covariance: [0]\n");
  EXPECT_THROW(readSensorPoseYaml(node), std::runtime_error);
}

}  // namespace
}  // namespace odometry_calibration
