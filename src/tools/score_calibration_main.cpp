// score_calibration: scores a saved calibration (result.yaml) on new bags or pairs files without
// refitting, beside the configured nominal robot: the paper's comparison table for last month's
// calibration on today's drive.
#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <string>
#include <vector>

#include <glog/logging.h>

#include "odometry_calibration/bag/bag_message_reader.h"
#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/calibration/saved_calibration_score.h"
#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/eval/tum_trajectory.h"
#include "odometry_calibration/report/trajectory_files.h"

namespace {

using namespace odometry_calibration;

const char* kUsage =
    "usage: score_calibration --config CONFIG.yaml --result RESULT.yaml BAG [BAG ...] [options]\n"
    "       score_calibration --config CONFIG.yaml --result RESULT.yaml --pairs PAIRS.csv\n"
    "\n"
    "Scores the calibration saved in RESULT.yaml (written by calibrate_bag or the node's\n"
    "~save) on new data without refitting: pairs from the bags (paired as calibrate_bag does,\n"
    "at the saved time offset) or from pairs files (as calibrate_bag writes them). Prints the\n"
    "comparison table (ATE and RPE of the chained predictions, paper eqs. 10-11, and per-axis\n"
    "RMSE) for the saved model and the nominal robot (the configuration's prior_model at its\n"
    "start values, at time offset 0). The configuration must name the joints the calibration\n"
    "was made with.\n"
    "\n"
    "options:\n"
    "  --pairs FILE         score on this pairs file instead of bags (repeatable)\n"
    "  --start S, --end S   use only [S, E] seconds after the bags' first message\n"
    "  --trajectories DIR   write each row's dead reckoning and the scan matches in TUM\n"
    "                       format into DIR (<model>.sensor.tum, <model>.base_link.tum,\n"
    "                       scan_matched.tum; compare with evo_ape tum)\n"
    "  --quiet              no progress display\n"
    "\n"
    "exit status: 0 success; 1 bad input (message says what: a file that cannot be read, data\n"
    "whose joints are not the calibration's, too few pairs); 2 bad usage\n";

void showProgress(const BagProgress& p)
{
  std::fprintf(stderr, "\r%5.1f %%", 100.0 * p.fraction);
  if (p.fraction >= 1.0)
    std::fprintf(stderr, "\n");
}

std::string joinNames(const std::vector<std::string>& names)
{
  std::string text;
  for (const std::string& name : names)
    text += (text.empty() ? "" : ", ") + name;
  return text;
}

/// score_calibration's arguments.
struct ScoreArguments
{
  std::string config_path, result_path;
  std::vector<std::string> bags, pairs_files;
  std::string trajectory_dir;  ///< --trajectories (empty: none written)
  double start_s = 0.0, end_s = 0.0;
  bool quiet = !isatty(STDERR_FILENO);
};

/// Parses the arguments; returns -1 to go on, else the exit status (0 after the usage asked
/// for, 2 after a usage error).
int parseArguments(int argc, char** argv, ScoreArguments& arguments)
{
  try {
    ArgumentParser parser;
    parser.option("--config", &arguments.config_path)
        .option("--result", &arguments.result_path)
        .repeatedOption("--pairs", &arguments.pairs_files)
        .number("--start", &arguments.start_s, 0.0)
        .number("--end", &arguments.end_s, 0.0)
        .option("--trajectories", &arguments.trajectory_dir)
        .flag("--quiet", &arguments.quiet)
        .positionals(&arguments.bags);
    if (!parser.parse(argc, argv)) {
      std::cout << kUsage;
      return 0;
    }
    if (arguments.config_path.empty() || arguments.result_path.empty())
      throw std::invalid_argument("give --config and --result");
    if (arguments.bags.empty() == arguments.pairs_files.empty())
      throw std::invalid_argument("give either bags or --pairs files");
    if (arguments.end_s > 0.0 && arguments.end_s <= arguments.start_s)
      throw std::invalid_argument("--end must come after --start");
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  return -1;
}

/// What the saved calibration is scored on: the pairs, the encoder history (bags only) and a
/// description of where they came from.
struct ScoringData
{
  std::vector<MotionPair> pairs;
  std::vector<EncoderSample> history;
  std::string description;
};

/// The pairs of the bags, paired at the saved time offset as calibrate_bag does (set in
/// `config`, which the scoring then uses too).
ScoringData pairsFromBags(const ScoreArguments& arguments, CalibrationConfig& config,
                          const CalibrationResult& saved, const std::vector<std::string>& joints)
{
  config.collector.time_offset_s = saved.time_offset_s;
  BagRunResult run;
  try {
    run =
        runBags(arguments.bags, config, arguments.start_s, arguments.end_s,
                arguments.quiet ? nullptr : std::function<void(const BagProgress&)>(showProgress));
  } catch (const std::runtime_error& error) {
    const std::string what = error.what();
    if (what.rfind("no usable JointState", 0) != 0)
      throw;
    throw std::runtime_error(
        "the bags' JointState messages do not carry the calibration's "
        "joints (" +
        joinNames(joints) + "): " + what);
  }
  return {run.pairs, run.encoder_history,
          std::to_string(run.pairs.size()) + " pairs from " +
              std::to_string(arguments.bags.size()) + " bag(s)"};
}

/// The pairs of the pairs files, whose joints must be the calibration's.
ScoringData pairsFromFiles(const ScoreArguments& arguments, const CalibrationResult& saved,
                           const std::vector<std::string>& joints)
{
  const PairsFile file = readPairsCsvFiles(arguments.pairs_files);
  requireCalibrationJoints(saved.joints.empty() ? joints : saved.joints, file.joints.names,
                           "the pairs file " + arguments.pairs_files.front());
  return {file.pairs,
          {},
          std::to_string(file.pairs.size()) + " pairs from " +
              std::to_string(arguments.pairs_files.size()) + " pairs file(s)"};
}

}  // namespace

int main(int argc, char** argv)
{
  google::InitGoogleLogging(argv[0]);
  containBagReadFaults();
  FLAGS_minloglevel = google::GLOG_FATAL;
  ScoreArguments arguments;
  if (const int status = parseArguments(argc, argv, arguments); status >= 0)
    return status;
  try {
    CalibrationConfig config = loadCalibrationConfig(arguments.config_path);
    const CalibrationResult saved = readCalibrationResult(arguments.result_path);
    const std::vector<std::string> joints = jointLayout(config).names;
    requireCalibrationJoints(saved.joints, joints, "the configuration " + arguments.config_path);
    const ScoringData data = arguments.bags.empty()
                                 ? pairsFromFiles(arguments, saved, joints)
                                 : pairsFromBags(arguments, config, saved, joints);
    const std::vector<ModelScore> scores =
        scoreSavedCalibration(config, saved, data.pairs, data.history);
    std::printf("saved calibration: %s (model %s, time offset %.6f s)\nscored on: %s\n\n",
                arguments.result_path.c_str(), saved.model->name().c_str(), saved.time_offset_s,
                data.description.c_str());
    std::cout << formatComparisonTable(scores);
    std::cout << scores.front().model << ": the saved calibration, not refitted\n";
    if (scores.size() == 1)
      std::cout << "(no nominal row: the configuration's prior_model is none)\n";
    std::cout << formatBestModel(scores, "these pairs");
    if (!arguments.trajectory_dir.empty()) {
      std::cout << "trajectories: "
                << writeTrajectoryFiles(arguments.trajectory_dir, tumTrajectoryFiles(scores))
                << "\n";
    }
    return 0;
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
}
