// compare_models: trains several models on some pairs files and scores them on others
// (the paper's Tables III/IV).
#include <algorithm>
#include <array>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_config.h"
#include "odometry_calibration/calibration/saved_calibration_score.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/factory/model_factory.h"

namespace {

using namespace odometry_calibration;

const char* kUsage =
    "usage: compare_models --train PAIRS.csv [--train ...] --test PAIRS.csv [--test ...]\n"
    "                      [--models linear,diff_drive,gp (default: all three)]\n"
    "                      [diff_drive options] [mecanum options] | [--config CONFIG.yaml]\n"
    "\n"
    "Fits each model on the training pairs and prints, per model, the ATE and RPE of the\n"
    "test trajectory integrated from its predictions (paper eqs. 10-11, against the chain of\n"
    "measured displacements) and the per-axis RMSE of the predicted displacements; the last\n"
    "row, \"nominal\", is the diff_drive at the --start values (the mecanum at --mecanum-start\n"
    "when mecanum is among the models), not fitted (the baseline).\n"
    "\n"
    "  --config CONFIG.yaml   take every model's options (skid_steer's sides too) and the\n"
    "                         nominal row (its prior_model) from a calibration config instead\n"
    "                         of the diff_drive options below; its joints must be the pairs'\n"
    "\n"
    "diff_drive options:\n"
    "  --left-joint NAME      left wheel joint (default: the first incremental joint)\n"
    "  --right-joint NAME     right wheel joint (default: the second incremental joint)\n"
    "  --ticks-per-rev N      encoder ticks per wheel turn (default 2000)\n"
    "  --start R_L,R_R,B,X,Y,THETA  start values [m, m, m, m, m, rad]\n"
    "                         (default 0.077,0.077,0.33,0.15,0,0)\n"
    "\n"
    "mecanum options (--ticks-per-rev as above):\n"
    "  --wheel-joints FL,FR,RL,RR  the front-left, front-right, rear-left, rear-right wheel\n"
    "                         joints (default: the first four incremental joints)\n"
    "  --mecanum-start R,LXLY,X,Y,THETA  start values: radius of all four wheels, lx + ly,\n"
    "                         sensor pose [m, m, m, m, rad] (default 0.05,0.35,0.15,0,0)\n"
    "\n"
    "Exit status: 0 success; 1 bad input; 2 bad usage; 3 a model's fit did not converge (its\n"
    "row is marked NOT converged: its scores are not those of a calibration).\n";

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> train, test, models = {"linear", "diff_drive", "gp"};
  std::string left, right, config_path;
  double ticks_per_rev = 2000.0;
  std::vector<double> start = {0.077, 0.077, 0.33, 0.15, 0.0, 0.0};
  std::vector<std::string> wheel_joints;
  const std::vector<double> default_mecanum_start = {0.05, 0.35, 0.15, 0.0, 0.0};
  std::vector<double> mecanum_start = default_mecanum_start;
  bool all_converged = true;
  try {
    ArgumentParser parser;
    parser.repeatedOption("--train", &train)
        .repeatedOption("--test", &test)
        .listOption("--models", &models)
        .option("--left-joint", &left)
        .option("--right-joint", &right)
        .number("--ticks-per-rev", &ticks_per_rev, 1.0)
        .numberList("--start", &start, 6)
        .listOption("--wheel-joints", &wheel_joints)
        .numberList("--mecanum-start", &mecanum_start, 5)
        .option("--config", &config_path);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    for (const std::string& name : models)
      requireKnownModel(name, "--models");
    const std::vector<double> default_start = {0.077, 0.077, 0.33, 0.15, 0.0, 0.0};
    if (!config_path.empty() &&
        (!left.empty() || !right.empty() || ticks_per_rev != 2000.0 || start != default_start ||
         !wheel_joints.empty() || mecanum_start != default_mecanum_start)) {
      throw std::invalid_argument("give either --config or the diff_drive and mecanum options");
    }
    if (!wheel_joints.empty() && wheel_joints.size() != 4) {
      throw std::invalid_argument("--wheel-joints needs four joint names: FL,FR,RL,RR");
    }
    if (train.empty() || test.empty()) {
      throw std::invalid_argument("give at least one --train and one --test pairs file");
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    const TrainTestPairs pairs = readTrainTestPairsCsv(train, test);
    const PairsFile& training = pairs.training;
    const PairsFile& testing = pairs.testing;
    ModelFactoryOptions options;
    std::shared_ptr<MotionModel> nominal;
    if (!config_path.empty()) {
      // The config's model sections are resolved (joints by name) for the models it uses:
      // the ones to compare.
      YAML::Node root = YAML::Load(readTextFile(config_path, "the configuration"));
      root["compare_models"] = models;
      std::ostringstream text;
      text << root;
      const CalibrationConfig config = parseCalibrationConfig(text.str(), config_path);
      requireCalibrationJoints(jointLayout(config).names, training.joints.names,
                               "the pairs file " + train.front());
      options = config.models;
      nominal = priorModel(config);
    } else {
      options.joints = training.joints;
      options.diff_drive.layout =
          diffDriveLayoutForJoints(training.joints, left, right, ticks_per_rev);
      options.diff_drive.initial_left_radius_m = start[0];
      options.diff_drive.initial_right_radius_m = start[1];
      options.diff_drive.initial_separation_m = start[2];
      options.diff_drive.initial_T_base_sensor = Pose2(start[3], start[4], start[5]);
      nominal = std::make_shared<DiffDriveModel>(options.diff_drive);  // unfitted: start values
      if (std::find(models.begin(), models.end(), "mecanum") != models.end()) {
        std::array<std::string, 4> wheels;
        std::copy(wheel_joints.begin(), wheel_joints.end(), wheels.begin());
        options.mecanum.layout = mecanumLayoutForJoints(training.joints, wheels, ticks_per_rev);
        options.mecanum.initial_radius_m.fill(mecanum_start[0]);
        options.mecanum.initial_lx_plus_ly_m = mecanum_start[1];
        options.mecanum.initial_T_base_sensor =
            Pose2(mecanum_start[2], mecanum_start[3], mecanum_start[4]);
        nominal = std::make_shared<MecanumModel>(options.mecanum);  // unfitted: start values
      }
    }
    std::cout << "training pairs: " << training.pairs.size()
              << ", test pairs: " << testing.pairs.size() << "\n\n";
    const std::vector<ModelScore> scores =
        compareModels(models, options, training.pairs, testing.pairs, nominal.get());
    std::cout << formatComparisonTable(scores);
    for (const ModelScore& score : scores) {
      all_converged = all_converged && score.converged;
      for (const std::string& warning : score.warnings) {
        std::cout << "\n" << score.model << ": " << warning;
      }
    }
    std::cout << "\n";
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return all_converged ? 0 : 3;
}
