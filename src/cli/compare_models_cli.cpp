#include "odometry_calibration/cli/compare_models_cli.h"

#include <algorithm>
#include <array>
#include <memory>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/saved_calibration_score.h"
#include "odometry_calibration/common/text_file.h"
#include "odometry_calibration/common/yaml_reading.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {

std::string compareModelsCliUsage()
{
  return "usage: compare_models --train PAIRS.csv [--train ...] --test PAIRS.csv [--test ...]\n"
         "                      [--models linear,diff_drive,gp (default: all three)]\n"
         "                      [diff_drive options] [mecanum options] | [--config CONFIG.yaml]\n"
         "\n"
         "Fits each model on the training pairs and prints, per model, the ATE and RPE of the\n"
         "test trajectory integrated from its predictions (paper eqs. 10-11, against the chain of\n"
         "measured displacements) and the per-axis RMSE of the predicted displacements; the last\n"
         "row, \"nominal\", is the diff_drive at the --start values (the mecanum at "
         "--mecanum-start\n"
         "when mecanum is among the models), not fitted (the baseline).\n"
         "\n"
         "  --config CONFIG.yaml   take every model's options (skid_steer's sides too) and the\n"
         "                         nominal row (its prior_model) from a calibration config "
         "instead\n"
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
}

CompareModelsCliOptions parseCompareModelsCliArguments(const std::vector<std::string>& arguments)
{
  CompareModelsCliOptions options;
  const CompareModelsCliOptions defaults;
  ArgumentParser parser;
  parser.repeatedOption("--train", &options.train)
      .repeatedOption("--test", &options.test)
      .listOption("--models", &options.models)
      .option("--left-joint", &options.left_joint)
      .option("--right-joint", &options.right_joint)
      .number("--ticks-per-rev", &options.ticks_per_rev, 1.0)
      .numberList("--start", &options.start, 6)
      .listOption("--wheel-joints", &options.wheel_joints)
      .numberList("--mecanum-start", &options.mecanum_start, 5)
      .option("--config", &options.config_path);
  if (!parser.parse(arguments)) {
    options.help = true;
    return options;
  }
  for (const std::string& name : options.models)
    requireKnownModel(name, "--models");
  if (!options.config_path.empty() &&
      (!options.left_joint.empty() || !options.right_joint.empty() ||
       options.ticks_per_rev != defaults.ticks_per_rev || options.start != defaults.start ||
       !options.wheel_joints.empty() || options.mecanum_start != defaults.mecanum_start)) {
    throw std::invalid_argument("give either --config or the diff_drive and mecanum options");
  }
  if (!options.wheel_joints.empty() && options.wheel_joints.size() != 4) {
    throw std::invalid_argument("--wheel-joints needs four joint names: FL,FR,RL,RR");
  }
  if (options.train.empty() || options.test.empty()) {
    throw std::invalid_argument("give at least one --train and one --test pairs file");
  }
  return options;
}

namespace {

/// The models' options and the nominal row from the calibration config: its model sections
/// are resolved (joints by name) for the models it uses, the ones to compare.
ModelFactoryOptions optionsFromConfig(const CompareModelsCliOptions& cli, const PairsFile& training,
                                      std::shared_ptr<MotionModel>& nominal)
{
  YAML::Node root =
      loadYamlDocument(readTextFile(cli.config_path, "the configuration"), cli.config_path);
  root["compare_models"] = cli.models;
  std::ostringstream text;
  text << root;
  const CalibrationConfig config = parseCalibrationConfig(text.str(), cli.config_path);
  requireCalibrationJoints(jointLayout(config).names, training.joints.names,
                           "the pairs file " + cli.train.front());
  nominal = priorModel(config);
  return config.models;
}

/// The diff_drive's (and, when compared, the mecanum's) options from the command line; the
/// nominal row is the last of them at its start values, unfitted.
ModelFactoryOptions optionsFromArguments(const CompareModelsCliOptions& cli,
                                         const PairsFile& training,
                                         std::shared_ptr<MotionModel>& nominal)
{
  ModelFactoryOptions options;
  const std::vector<double>& start = cli.start;
  options.joints = training.joints;
  options.diff_drive.layout =
      diffDriveLayoutForJoints(training.joints, cli.left_joint, cli.right_joint, cli.ticks_per_rev);
  options.diff_drive.initial_left_radius_m = start[0];
  options.diff_drive.initial_right_radius_m = start[1];
  options.diff_drive.initial_separation_m = start[2];
  options.diff_drive.initial_T_base_sensor = Pose2(start[3], start[4], start[5]);
  nominal = std::make_shared<DiffDriveModel>(options.diff_drive);  // unfitted: start values
  if (std::find(cli.models.begin(), cli.models.end(), "mecanum") != cli.models.end()) {
    std::array<std::string, 4> wheels;
    std::copy(cli.wheel_joints.begin(), cli.wheel_joints.end(), wheels.begin());
    options.mecanum.layout = mecanumLayoutForJoints(training.joints, wheels, cli.ticks_per_rev);
    options.mecanum.initial_radius_m.fill(cli.mecanum_start[0]);
    options.mecanum.initial_lx_plus_ly_m = cli.mecanum_start[1];
    options.mecanum.initial_T_base_sensor =
        Pose2(cli.mecanum_start[2], cli.mecanum_start[3], cli.mecanum_start[4]);
    nominal = std::make_shared<MecanumModel>(options.mecanum);  // unfitted: start values
  }
  return options;
}

}  // namespace

int runCompareModelsCli(const CompareModelsCliOptions& cli, std::ostream& out, std::ostream& err)
{
  bool all_converged = true;
  try {
    const TrainTestPairs pairs = readTrainTestPairsCsv(cli.train, cli.test);
    const PairsFile& training = pairs.training;
    const PairsFile& testing = pairs.testing;
    std::shared_ptr<MotionModel> nominal;
    const ModelFactoryOptions options = cli.config_path.empty()
                                            ? optionsFromArguments(cli, training, nominal)
                                            : optionsFromConfig(cli, training, nominal);
    out << "training pairs: " << training.pairs.size() << ", test pairs: " << testing.pairs.size()
        << "\n\n";
    const std::vector<ModelScore> scores =
        compareModels(cli.models, options, training.pairs, testing.pairs, nominal.get());
    out << formatComparisonTable(scores);
    for (const ModelScore& score : scores) {
      all_converged = all_converged && score.converged;
      for (const std::string& warning : score.warnings) {
        out << "\n" << score.model << ": " << warning;
      }
    }
    out << "\n";
  } catch (const std::exception& error) {
    err << "error: " << error.what() << "\n";
    return 1;
  }
  return all_converged ? 0 : 3;
}

}  // namespace odometry_calibration
