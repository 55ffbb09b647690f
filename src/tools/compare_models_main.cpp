// compare_models: trains several models on some pairs files and scores them on others
// (the paper's Tables III/IV).
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <string>
#include <vector>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/models/model_factory.h"

namespace {

using namespace odometry_calibration;

const char* kUsage =
    "usage: compare_models --train PAIRS.csv [--train ...] --test PAIRS.csv [--test ...]\n"
    "                      [--models linear,diff_drive,gp (default: all three)]\n"
    "                      [diff_drive options]\n"
    "\n"
    "Fits each model on the training pairs and prints, per model, the ATE and RPE of the\n"
    "test trajectory integrated from its predictions (paper eqs. 10-11, against the chain of\n"
    "measured displacements) and the per-axis RMSE of the predicted displacements.\n"
    "\n"
    "diff_drive options:\n"
    "  --left-joint NAME      left wheel joint (default: the first incremental joint)\n"
    "  --right-joint NAME     right wheel joint (default: the second incremental joint)\n"
    "  --ticks-per-rev N      encoder ticks per wheel turn (default 2000)\n"
    "  --start R_L,R_R,B,X,Y,THETA  start values [m, m, m, m, m, rad]\n"
    "                         (default 0.077,0.077,0.33,0.15,0,0)\n";

std::vector<double> numbers(const std::string& option, const std::string& text)
{
  std::vector<double> values;
  std::stringstream stream(text);
  std::string part;
  while (std::getline(stream, part, ','))
    values.push_back(parseNumberArgument(option, part));
  return values;
}

/// Appends the pairs of several files, which must share their joints.
PairsFile readAll(const std::vector<std::string>& paths)
{
  PairsFile all;
  for (const std::string& path : paths) {
    PairsFile file = readPairsCsv(path);
    if (all.joints.names.empty()) {
      all.joints = file.joints;
    } else if (file.joints.names != all.joints.names) {
      throw std::invalid_argument("'" + path + "' has other joints than the first file");
    }
    all.pairs.insert(all.pairs.end(), file.pairs.begin(), file.pairs.end());
  }
  return all;
}

int indexOf(const JointLayout& joints, const std::string& name, int nth_incremental)
{
  int seen = 0;
  for (std::size_t j = 0; j < joints.names.size(); ++j) {
    if (name.empty() ? (joints.kinds[j] == EncoderKind::kIncremental && seen++ == nth_incremental)
                     : joints.names[j] == name) {
      return static_cast<int>(j);
    }
  }
  throw std::invalid_argument(name.empty() ? "diff_drive needs two incremental joints"
                                           : "no joint named '" + name + "' in the pairs");
}

}  // namespace

int main(int argc, char** argv)
{
  std::vector<std::string> train, test, models = {"linear", "diff_drive", "gp"};
  std::string left, right;
  double ticks_per_rev = 2000.0;
  std::vector<double> start = {0.077, 0.077, 0.33, 0.15, 0.0, 0.0};
  try {
    const std::vector<std::string> args(argv + 1, argv + argc);
    for (std::size_t i = 0; i < args.size(); ++i) {
      const std::string& arg = args[i];
      if (arg == "-h" || arg == "--help") {
        std::cout << kUsage;
        return 0;
      }
      if (i + 1 >= args.size())
        throw std::invalid_argument("option " + arg + " needs a value");
      const std::string& value = args[++i];
      if (arg == "--train") {
        train.push_back(value);
      } else if (arg == "--test") {
        test.push_back(value);
      } else if (arg == "--models") {
        models.clear();
        std::stringstream stream(value);
        std::string name;
        while (std::getline(stream, name, ','))
          models.push_back(name);
      } else if (arg == "--left-joint") {
        left = value;
      } else if (arg == "--right-joint") {
        right = value;
      } else if (arg == "--ticks-per-rev") {
        ticks_per_rev = parseNumberArgument(arg, value, 1.0);
      } else if (arg == "--start") {
        start = numbers(arg, value);
        if (start.size() != 6)
          throw std::invalid_argument("--start needs 6 numbers");
      } else {
        throw std::invalid_argument("unknown option '" + arg + "'");
      }
    }
    for (const std::string& name : models)
      requireKnownModel(name, "--models");
    if (train.empty() || test.empty()) {
      throw std::invalid_argument("give at least one --train and one --test pairs file");
    }
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n\n" << kUsage;
    return 2;
  }
  try {
    const PairsFile training = readAll(train);
    const PairsFile testing = readAll(test);
    if (testing.joints.names != training.joints.names) {
      throw std::invalid_argument("the test pairs have other joints than the training pairs");
    }
    ModelFactoryOptions options;
    options.joints = training.joints;
    options.diff_drive.layout = {indexOf(training.joints, left, 0),
                                 indexOf(training.joints, right, 1), ticks_per_rev};
    options.diff_drive.initial_left_radius_m = start[0];
    options.diff_drive.initial_right_radius_m = start[1];
    options.diff_drive.initial_separation_m = start[2];
    options.diff_drive.initial_T_base_sensor = Pose2(start[3], start[4], start[5]);
    std::cout << "training pairs: " << training.pairs.size()
              << ", test pairs: " << testing.pairs.size() << "\n\n";
    std::vector<ModelScore> scores;
    for (const std::string& name : models) {
      auto model = makeModel(name, options);
      if (training.pairs.empty())
        throw std::invalid_argument("the training files hold no pair");
      const ModelReport report = model->fit(training.pairs);
      ModelScore score = scoreModel(*model, testing.pairs);
      score.fit_time_s = report.fit_time_s;
      score.outliers = report.outliers;
      score.warnings = report.warnings;
      scores.push_back(score);
    }
    std::cout << formatComparisonTable(scores);
    for (const ModelScore& score : scores) {
      for (const std::string& warning : score.warnings) {
        std::cout << "\n" << score.model << ": " << warning;
      }
    }
    std::cout << "\n";
  } catch (const std::exception& error) {
    std::cerr << "error: " << error.what() << "\n";
    return 1;
  }
  return 0;
}
