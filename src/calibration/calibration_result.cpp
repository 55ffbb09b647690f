#include "odometry_calibration/calibration/calibration_result.h"

#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {

std::string calibrationResultYaml(const ModelReport& report, const MotionModel& model,
                                  const std::string& source, double time_offset_s,
                                  const std::vector<std::string>& joints, double fit_interval_s)
{
  char offset[64];
  std::snprintf(offset, sizeof(offset), "time_offset_s: %.6f\n", time_offset_s);
  std::string text = modelResultYaml(report, model.toYaml(), source) + offset;
  if (!joints.empty()) {
    YAML::Emitter names;
    names << YAML::Flow << joints;
    text += "joints: " + std::string(names.c_str()) + "\n";
  }
  if (fit_interval_s > 0.0) {
    char interval[64];
    std::snprintf(interval, sizeof(interval), "fit_interval_s: %.4f\n", fit_interval_s);
    text += interval;
  }
  return text;
}

std::string fitIntervalChoiceYaml(const FitIntervalChoice& choice, double evaluation_interval_s)
{
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap << YAML::Key << "fit_interval_choice" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "criterion" << YAML::Value << criterionName(choice.criterion);
  out << YAML::Key << "evaluation_interval_s" << YAML::Value << evaluation_interval_s;
  out << YAML::Key << "fold_counts" << YAML::Value << YAML::Flow << choice.fold_counts;
  out << YAML::Key << "curve" << YAML::Value << YAML::BeginSeq;
  for (const FitIntervalScore& score : choice.curve) {
    out << YAML::Flow << YAML::BeginMap;
    out << YAML::Key << "interval_s" << YAML::Value << score.interval_s;
    out << YAML::Key << "pairs" << YAML::Value << score.pairs;
    out << YAML::Key << "validation_error_m" << YAML::Value << score.validation_error_m;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

namespace {

/// One row of a `scores:` set.
void emitScoreRow(YAML::Emitter& out, const ModelScore& score)
{
  out << YAML::Flow << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << score.model;
  if (!score.skipped.empty()) {
    out << YAML::Key << "skipped" << YAML::Value << score.skipped << YAML::EndMap;
    return;
  }
  out << YAML::Key << "pairs" << YAML::Value << score.test_pairs;
  out << YAML::Key << "ate_m" << YAML::Value << score.ate_m;
  out << YAML::Key << "rpe_m" << YAML::Value << score.rpe_m;
  out << YAML::Key << "rmse_x_m" << YAML::Value << score.rmse_xytheta(0);
  out << YAML::Key << "rmse_y_m" << YAML::Value << score.rmse_xytheta(1);
  out << YAML::Key << "rmse_theta_rad" << YAML::Value << score.rmse_xytheta(2);
  out << YAML::Key << "converged" << YAML::Value << score.converged;
  out << YAML::EndMap;
}

}  // namespace

std::string scoresYaml(const std::vector<ResultScores>& sets)
{
  if (sets.empty())
    return "";
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap << YAML::Key << "scores" << YAML::Value << YAML::BeginMap;
  for (const ResultScores& set : sets) {
    out << YAML::Key << set.data << YAML::Value << YAML::BeginMap;
    out << YAML::Key << "description" << YAML::Value << set.description;
    out << YAML::Key << "models" << YAML::Value << YAML::BeginSeq;
    for (const ModelScore& score : set.rows)
      emitScoreRow(out, score);
    out << YAML::EndSeq << YAML::EndMap;
  }
  out << YAML::EndMap << YAML::EndMap;
  return std::string(out.c_str()) + "\n";
}

CalibrationResult parseCalibrationResult(const std::string& text, const std::string& source)
{
  YAML::Node root;
  try {
    root = YAML::Load(text);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(source + ": not YAML: " + error.what());
  }
  refuseYamlBeyond(root, source);
  if (!root.IsMap() || !root["model"] || !root["model"].IsMap()) {
    throw std::runtime_error(source + ": no 'model' section (not an odometry_calibration result)");
  }
  CalibrationResult result;
  std::ostringstream model_yaml;
  model_yaml << root["model"];
  try {
    if (const YAML::Node interval = root["fit_interval_s"]) {
      result.fit_interval_s = interval.as<double>();
      if (!(result.fit_interval_s > 0.0) || !(result.fit_interval_s <= 3600.0))
        throw std::runtime_error("fit_interval_s must be in (0, 3600] s");
    }
    result.model = loadModel(model_yaml.str());
    if (const YAML::Node pose = root["T_base_sensor"]) {
      result.T_base_sensor =
          Pose2(pose["x_m"].as<double>(), pose["y_m"].as<double>(), pose["theta_rad"].as<double>());
      result.has_extrinsic = true;
    }
    if (const YAML::Node offset = root["time_offset_s"])
      result.time_offset_s = offset.as<double>();
    if (const YAML::Node joints = root["joints"])
      result.joints = joints.as<std::vector<std::string>>();
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(source + ": " + error.what());
  } catch (const std::exception& error) {
    throw std::runtime_error(source + ": " + error.what());
  }
  return result;
}

CalibrationResult readCalibrationResult(const std::string& path)
{
  return parseCalibrationResult(readTextFile(path, "the calibration"), path);
}

std::string laserJointUrdf(const Pose2& T_base_laser, const std::string& base_frame,
                           const std::string& laser_frame)
{
  char text[1024];
  std::snprintf(text, sizeof(text),
                "<!-- odometry_calibration: the laser's pose on the robot, estimated from planar "
                "motion.\n     z, roll and pitch are not observable that way: set z by hand. -->\n"
                "<joint name=\"%s_joint\" type=\"fixed\">\n"
                "  <parent link=\"%s\"/>\n"
                "  <child link=\"%s\"/>\n"
                "  <origin xyz=\"%.6f %.6f 0\" rpy=\"0 0 %.6f\"/>\n"
                "</joint>\n",
                laser_frame.c_str(), base_frame.c_str(), laser_frame.c_str(), T_base_laser.x(),
                T_base_laser.y(), T_base_laser.theta());
  return text;
}

}  // namespace odometry_calibration
