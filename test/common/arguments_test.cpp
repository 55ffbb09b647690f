#include <limits>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/common/arguments.h"

namespace odometry_calibration {
namespace {

/// The message of the ArgumentError that parsing `arguments` with `parser` throws ("" if none).
std::string errorOf(const ArgumentParser& parser, const std::vector<std::string>& arguments)
{
  try {
    parser.parse(arguments);
  } catch (const ArgumentError& error) {
    return error.what();
  }
  return "";
}

/// A parser with one argument of each kind, and the variables it fills.
struct Tool
{
  std::string config = "default.yaml";
  std::vector<std::string> tests, models = {"linear", "gp"}, bags;
  double start = 0.0, ticks = 2000.0, duration = 60.0;
  long long seed = 1;
  std::vector<double> pose = {0.0, 0.0, 0.0};
  bool quiet = false;
  ArgumentParser parser;

  Tool()
  {
    parser.option("--config", &config)
        .repeatedOption("--test", &tests)
        .listOption("--models", &models)
        .number("--start", &start, 0.0)
        .number("--ticks", &ticks)
        .positiveNumber("--duration", &duration)
        .wholeNumber("--seed", &seed, 0, 1000)
        .numberList("--pose", &pose, 3)
        .flag("--quiet", &quiet)
        .positionals(&bags, 2);
  }
};

TEST(Arguments, FillsTheDeclaredVariables)
{
  Tool tool;
  EXPECT_TRUE(tool.parser.parse(
      {"a.bag",      "--config", "c.yaml",        "--test",  "t1",     "--quiet",  "--test",
       "t2",         "--models", "gp,diff_drive", "--start", "1.5",    "--ticks",  "-3",
       "--duration", "2e1",      "--seed",        "7",       "--pose", "1,-2,0.5", "b.bag"}));
  EXPECT_EQ(tool.config, "c.yaml");
  EXPECT_EQ(tool.tests, (std::vector<std::string>{"t1", "t2"}));
  EXPECT_EQ(tool.models, (std::vector<std::string>{"gp", "diff_drive"}));
  EXPECT_EQ(tool.start, 1.5);
  EXPECT_EQ(tool.ticks, -3.0);
  EXPECT_EQ(tool.duration, 20.0);
  EXPECT_EQ(tool.seed, 7);
  EXPECT_EQ(tool.pose, (std::vector<double>{1.0, -2.0, 0.5}));
  EXPECT_TRUE(tool.quiet);
  EXPECT_EQ(tool.bags, (std::vector<std::string>{"a.bag", "b.bag"}));
}

TEST(Arguments, KeepsDefaultsAndTakesTheLastValue)
{
  Tool tool;
  EXPECT_TRUE(tool.parser.parse({"--config", "a", "--config", "b"}));
  EXPECT_EQ(tool.config, "b");
  EXPECT_EQ(tool.models, (std::vector<std::string>{"linear", "gp"}));
  EXPECT_EQ(tool.start, 0.0);
  EXPECT_EQ(tool.seed, 1);
  EXPECT_FALSE(tool.quiet);
  EXPECT_TRUE(tool.bags.empty());
}

TEST(Arguments, ValuesMayStartWithADashAndDoubleDashEndsTheOptions)
{
  Tool tool;
  EXPECT_TRUE(tool.parser.parse({"--config", "--quiet", "--", "-odd.bag"}));
  EXPECT_EQ(tool.config, "--quiet");
  EXPECT_FALSE(tool.quiet);
  EXPECT_EQ(tool.bags, (std::vector<std::string>{"-odd.bag"}));
  EXPECT_TRUE(tool.parser.parse({"-"}));  // "-" alone is a positional (stdin, by convention)
  EXPECT_EQ(tool.bags.back(), "-");
}

TEST(Arguments, HelpStopsTheParse)
{
  Tool tool;
  EXPECT_FALSE(tool.parser.parse({"--help"}));
  EXPECT_FALSE(tool.parser.parse({"a.bag", "-h", "--frobnicate"}));
  // An error before the help is still reported.
  EXPECT_EQ(errorOf(tool.parser, {"--start", "x", "--help"}),
            "option --start: expected a number >= 0, got 'x'");
  const char* argv[] = {"tool", "--quiet", "--help"};
  EXPECT_FALSE(tool.parser.parse(3, argv));
  EXPECT_TRUE(tool.quiet);
}

TEST(Arguments, ParsesArgvWithoutTheProgramName)
{
  Tool tool;
  const char* argv[] = {"tool", "x.bag", "--config", "y.yaml"};
  EXPECT_TRUE(tool.parser.parse(4, argv));
  EXPECT_EQ(tool.bags, (std::vector<std::string>{"x.bag"}));
  EXPECT_EQ(tool.config, "y.yaml");
}

TEST(Arguments, ErrorsNameTheOptionAndTheValue)
{
  const Tool tool;
  const ArgumentParser& p = tool.parser;
  EXPECT_EQ(errorOf(p, {"--foo"}), "unknown option '--foo'");
  EXPECT_EQ(errorOf(p, {"-x"}), "unknown option '-x'");
  EXPECT_EQ(errorOf(p, {"--config"}), "option --config needs a value");
  EXPECT_EQ(errorOf(p, {"--start", "x"}), "option --start: expected a number >= 0, got 'x'");
  EXPECT_EQ(errorOf(p, {"--start", "-1"}), "option --start: expected a number >= 0, got '-1'");
  EXPECT_EQ(errorOf(p, {"--start", ""}), "option --start: expected a number >= 0, got ''");
  EXPECT_EQ(errorOf(p, {"--start", "1s"}), "option --start: expected a number >= 0, got '1s'");
  EXPECT_EQ(errorOf(p, {"--ticks", "inf"}), "option --ticks: expected a number, got 'inf'");
  EXPECT_EQ(errorOf(p, {"--ticks", "nan"}), "option --ticks: expected a number, got 'nan'");
  EXPECT_EQ(errorOf(p, {"--duration", "0"}), "option --duration: expected a number > 0, got '0'");
  EXPECT_EQ(errorOf(p, {"--duration", "soon"}),
            "option --duration: expected a number > 0, got 'soon'");
  EXPECT_EQ(errorOf(p, {"--seed", "1.5"}),
            "option --seed: expected a whole number in [0, 1000], got '1.5'");
  EXPECT_EQ(errorOf(p, {"--seed", "1001"}),
            "option --seed: expected a whole number in [0, 1000], got '1001'");
  EXPECT_EQ(errorOf(p, {"--pose", "1,2"}),
            "option --pose: expected 3 comma-separated numbers, got '1,2'");
  EXPECT_EQ(errorOf(p, {"--pose", "1,2,3,4"}),
            "option --pose: expected 3 comma-separated numbers, got '1,2,3,4'");
  EXPECT_EQ(errorOf(p, {"--pose", "1,b,3"}), "option --pose: expected a number, got 'b'");
  EXPECT_EQ(errorOf(p, {"a", "b", "c"}), "unexpected argument 'c'");
  EXPECT_EQ(errorOf(ArgumentParser(), {"a"}), "unexpected argument 'a'");
  // ArgumentError is a std::invalid_argument: callers that catch that keep working.
  EXPECT_THROW(p.parse({"--foo"}), std::invalid_argument);
}

TEST(Arguments, WholeNumberWithoutMaximumSaysAtLeast)
{
  long long n = 0;
  ArgumentParser parser;
  parser.wholeNumber("--seed", &n, 0);
  EXPECT_EQ(errorOf(parser, {"--seed", "-1"}),
            "option --seed: expected a whole number >= 0, got '-1'");
  EXPECT_TRUE(parser.parse({"--seed", "1e3"}));
  EXPECT_EQ(n, 1000);
}

TEST(Arguments, ParseNumberArgumentKeepsItsRuleAndMessage)
{
  EXPECT_EQ(parseNumberArgument("--x", "2.5"), 2.5);
  EXPECT_EQ(parseNumberArgument("--x", "1", 1.0), 1.0);
  try {
    parseNumberArgument("--ticks-per-rev", "0.5", 1.0);
    FAIL();
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "option --ticks-per-rev: expected a number >= 1, got '0.5'");
  }
  EXPECT_THROW(parseNumberArgument("--x", "1e999"), ArgumentError);  // out of range
}

TEST(Arguments, SplitCommaListSplitsAsGetlineDoes)
{
  EXPECT_EQ(splitCommaList(""), std::vector<std::string>{});
  EXPECT_EQ(splitCommaList("a"), std::vector<std::string>{"a"});
  EXPECT_EQ(splitCommaList("a,,b,"), (std::vector<std::string>{"a", "", "b"}));
}

}  // namespace
}  // namespace odometry_calibration
