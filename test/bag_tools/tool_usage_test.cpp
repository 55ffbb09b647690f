// The tools' usage contract, on the built programs: bad usage prints "error: <message>" and the
// usage on stderr and exits 2; -h/--help prints the usage on stdout and exits 0.
#include <sys/wait.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include <gtest/gtest.h>

#include "support/files.h"

namespace {

namespace fs = std::filesystem;

struct ToolRun
{
  int status = -1;
  std::string out, err;
};

using odometry_calibration::test_support::readFile;

/// Runs a built tool with `arguments` (shell words), capturing its exit status and output.
ToolRun run(const std::string& tool, const std::string& arguments)
{
  const fs::path directory = fs::temp_directory_path() / ("tool_usage_test." + tool);
  fs::create_directories(directory);
  const std::string command = std::string(ODOMETRY_CALIBRATION_TOOLS_DIR) + "/" + tool + " " +
                              arguments + " > " + (directory / "out").string() + " 2> " +
                              (directory / "err").string();
  const int status = std::system(command.c_str());
  ToolRun result;
  result.status = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  result.out = readFile((directory / "out").string());
  result.err = readFile((directory / "err").string());
  fs::remove_all(directory);
  return result;
}

/// Bad usage: exit 2, "error: <message>\n\n<usage>" on stderr, nothing on stdout.
void expectBadUsage(const std::string& tool, const std::string& arguments,
                    const std::string& message)
{
  SCOPED_TRACE(tool + " " + arguments);
  const ToolRun result = run(tool, arguments);
  EXPECT_EQ(result.status, 2);
  EXPECT_EQ(result.out, "");
  EXPECT_EQ(result.err.rfind("error: " + message, 0), 0u) << result.err;
  EXPECT_NE(result.err.find("\n\nusage: " + tool), std::string::npos) << result.err;
}

/// Help: exit 0, the usage on stdout, nothing on stderr.
void expectHelp(const std::string& tool)
{
  for (const char* help : {"-h", "--help"}) {
    SCOPED_TRACE(tool + " " + help);
    const ToolRun result = run(tool, help);
    EXPECT_EQ(result.status, 0);
    EXPECT_EQ(result.out.rfind("usage: " + tool, 0), 0u) << result.out;
    EXPECT_EQ(result.err, "");
  }
}

TEST(ToolUsage, CalibrateBag)
{
  expectHelp("calibrate_bag");
  expectBadUsage("calibrate_bag", "--config c.yaml a.bag --start x",
                 "option --start: expected a number >= 0, got 'x'");
  expectBadUsage("calibrate_bag", "--config c.yaml a.bag --foo 1", "unknown option '--foo'");
  expectBadUsage("calibrate_bag", "--config c.yaml a.bag --holdout 1",
                 "option --holdout: expected a fraction in (0, 1)");
  expectBadUsage("calibrate_bag", "a.bag --config", "option --config needs a value");
  expectBadUsage("calibrate_bag", "a.bag", "give --config and at least one bag");
  expectBadUsage("calibrate_bag", "--config c.yaml a.bag --start 5 --end 2",
                 "--end must come after --start");
}

TEST(ToolUsage, CalibrateTricycle)
{
  expectHelp("calibrate_tricycle");
  expectBadUsage("calibrate_tricycle", "", "missing the dataset file");
  expectBadUsage("calibrate_tricycle", "log.txt --interval 0",
                 "option --interval: the keyframe spacing must be > 0 s");
  expectBadUsage("calibrate_tricycle", "log.txt --huber x",
                 "option --huber: expected a number, got 'x'");
  expectBadUsage("calibrate_tricycle", "a b", "only one dataset file is accepted, got 'a' and 'b'");
  expectBadUsage("calibrate_tricycle", "log.txt --holdout 2",
                 "option --holdout: expected a fraction in (0, 1)");
}

TEST(ToolUsage, CompareModels)
{
  expectHelp("compare_models");
  expectBadUsage("compare_models", "--train a.csv",
                 "give at least one --train and one --test pairs file");
  expectBadUsage("compare_models", "--train a --test b --start 1,2",
                 "option --start: expected 6 comma-separated numbers, got '1,2'");
  expectBadUsage("compare_models", "--train a --test b --ticks-per-rev 0",
                 "option --ticks-per-rev: expected a number >= 1, got '0'");
  expectBadUsage("compare_models", "--train a --test b --models linear,cubic",
                 "--models: unknown model 'cubic'");
  expectBadUsage("compare_models", "--train a --test b --config c.yaml --left-joint l",
                 "give either --config or the diff_drive and mecanum options");
}

TEST(ToolUsage, GeneratePairs)
{
  expectHelp("generate_pairs");
  expectBadUsage("generate_pairs", "s.yaml", "give a scenario and --output");
  expectBadUsage("generate_pairs", "s.yaml --output p.csv --noise-m -1",
                 "option --noise-m: expected a number >= 0, got '-1'");
}

TEST(ToolUsage, MinesToBag)
{
  expectHelp("mines_to_bag");
  expectBadUsage("mines_to_bag", "exp1.dat", "give the Mines log and the bag to write");
  expectBadUsage("mines_to_bag", "a b c", "unexpected argument 'c'");
}

TEST(ToolUsage, Simulate)
{
  expectHelp("simulate");
  expectBadUsage("simulate", "", "missing the scenario file");
  expectBadUsage("simulate", "s.yaml --seed 1.5",
                 "option --seed: expected a whole number >= 0, got '1.5'");
  expectBadUsage("simulate", "s.yaml --duration 0",
                 "option --duration: expected a number > 0, got '0'");
  expectBadUsage("simulate", "a.yaml b.yaml", "unexpected argument 'b.yaml'");
  expectBadUsage("simulate", "s.yaml --format mcap2",
                 "unknown bag format 'mcap2' (bag, db3, db3.zstd or mcap)");
  expectBadUsage("simulate", "s.yaml --format mcap --chunk-compression lzma",
                 "unknown chunk compression 'lzma' (zstd, lz4 or none)");
}

TEST(ToolUsage, ScoreCalibration)
{
  expectHelp("score_calibration");
  expectBadUsage("score_calibration", "a.bag", "give --config and --result");
  expectBadUsage("score_calibration", "--config c.yaml --result r.yaml",
                 "give either bags or --pairs files");
  expectBadUsage("score_calibration", "--config c.yaml --result r.yaml a.bag --pairs p.csv",
                 "give either bags or --pairs files");
  expectBadUsage("score_calibration", "--config c.yaml --result r.yaml a.bag --start 5 --end 2",
                 "--end must come after --start");
}

TEST(ToolUsage, BadInputIsNotBadUsage)
{
  const ToolRun result =
      run("compare_models", "--train /nonexistent/a.csv --test /nonexistent/b.csv");
  EXPECT_EQ(result.status, 1);
  EXPECT_EQ(result.err.rfind("error: ", 0), 0u) << result.err;
  EXPECT_EQ(result.err.find("usage:"), std::string::npos) << result.err;
}

}  // namespace
