// compare_models' logic without the program: its argument checks, and a comparison of two models
// trained and tested on simulated pairs files.
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/cli/compare_models_cli.h"
#include "odometry_calibration/data/pairs_csv.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

CompareModelsCliOptions parse(std::vector<std::string> arguments)
{
  return parseCompareModelsCliArguments(arguments);
}

/// A pairs file of a simulated 40 s drive of a slightly uneven diff-drive robot.
std::string writeSimulatedPairs(const std::string& directory, unsigned seed)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.duration_s = 40.0;
  options.seed = seed;
  const sim::GeneratedPairs generated = sim::generatePairs(options);
  PairsFile file;
  file.joints = generated.joints;
  file.pairs = generated.pairs;
  const std::string path = directory + "/pairs_" + std::to_string(seed) + ".csv";
  writePairsCsv(path, file);
  return path;
}

TEST(CompareModelsCli, RefusesBadUsage)
{
  EXPECT_THROW(parse({"--train", "a.csv"}), std::invalid_argument);  // no --test
  EXPECT_THROW(parse({"--train", "a.csv", "--test", "b.csv", "--models", "spline"}),
               std::exception);
  EXPECT_THROW(parse({"--train", "a.csv", "--test", "b.csv", "--config", "c.yaml", "--start",
                      "0.08,0.08,0.33,0.15,0,0"}),
               std::invalid_argument);
  EXPECT_THROW(parse({"--train", "a.csv", "--test", "b.csv", "--wheel-joints", "fl,fr,rl"}),
               std::invalid_argument);
  EXPECT_TRUE(parse({"--help"}).help);
  const CompareModelsCliOptions options =
      parse({"--train", "a.csv", "--test", "b.csv", "--models", "diff_drive"});
  EXPECT_FALSE(options.help);
  EXPECT_EQ(options.models, std::vector<std::string>{"diff_drive"});
}

TEST(CompareModelsCli, ComparesTheModelsOnTheTestPairs)
{
  char pattern[] = "/tmp/compare_models_cli_test.XXXXXX";
  ASSERT_NE(mkdtemp(pattern), nullptr);
  const std::string directory = pattern;
  CompareModelsCliOptions options;
  options.train = {writeSimulatedPairs(directory, 1)};
  options.test = {writeSimulatedPairs(directory, 2)};
  options.models = {"linear", "diff_drive"};
  std::ostringstream out, err;
  const int status = runCompareModelsCli(options, out, err);
  EXPECT_EQ(status, 0) << err.str();
  EXPECT_NE(out.str().find("training pairs: "), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("diff_drive"), std::string::npos) << out.str();
  EXPECT_NE(out.str().find("nominal"), std::string::npos) << out.str();

  options.test = {directory + "/missing.csv"};
  std::ostringstream missing_out, missing_err;
  EXPECT_EQ(runCompareModelsCli(options, missing_out, missing_err), 1);
  EXPECT_EQ(missing_err.str().rfind("error: ", 0), 0u) << missing_err.str();
  std::filesystem::remove_all(directory);
}

}  // namespace
}  // namespace odometry_calibration
