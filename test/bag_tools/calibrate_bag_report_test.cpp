// End-to-end: calibrate_bag on a small simulated bag writes the Markdown report with its plots
// (valid PNG images of the trajectories, the residual histograms and the time-offset curve),
// still writes the report when gnuplot is missing, and writes nothing on bad input.
#include <sys/wait.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include <gtest/gtest.h>
#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/report/report_plots.h"
#include "odometry_calibration/sim/scenario.h"

#include "support/files.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;
const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;
const std::string kTool = CALIBRATE_BAG_PROGRAM;

using test_support::readFile;

/// Width and height from a PNG's IHDR chunk.
std::pair<unsigned, unsigned> pngSize(const std::string& path)
{
  const std::string bytes = readFile(path);
  auto be32 = [&](std::size_t at) {
    return (unsigned(static_cast<unsigned char>(bytes[at])) << 24) |
           (unsigned(static_cast<unsigned char>(bytes[at + 1])) << 16) |
           (unsigned(static_cast<unsigned char>(bytes[at + 2])) << 8) |
           unsigned(static_cast<unsigned char>(bytes[at + 3]));
  };
  return bytes.size() > 24 ? std::make_pair(be32(16), be32(20)) : std::make_pair(0u, 0u);
}

std::size_t count(const std::string& text, const std::string& what)
{
  std::size_t n = 0;
  for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
    ++n;
  return n;
}

class CalibrateBagReport : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    char pattern[] = "/tmp/calibrate_bag_report_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_deformed.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 60.0;
    bag_ = directory_ + "/deformed.bag";
    simulateToBag(scenario, bag_, "");
  }
  static void TearDownTestSuite() { fs::remove_all(directory_); }

  /// Runs calibrate_bag with the demo config (time offset estimated); returns its exit status.
  /// A relative output_dir is taken from directory_.
  int run(const std::string& output_dir, const std::string& extra = "")
  {
    const std::string command = "cd " + directory_ + " && " + kTool + " --config " + kConfig +
                                "/diff_drive_demo.yaml " + bag_ + " --quiet --output-dir " +
                                output_dir + " " + extra + " > " + directory_ + "/stdout.txt 2> " +
                                directory_ + "/stderr.txt";
    const int status = std::system(command.c_str());
    return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  std::string output(const char* which) { return readFile(directory_ + "/" + which + ".txt"); }

  static std::string directory_, bag_;
};
std::string CalibrateBagReport::directory_, CalibrateBagReport::bag_;

TEST_F(CalibrateBagReport, WritesTheMarkdownReportWithPlots)
{
  // A relative output folder, as scripts/demo gives.
  ASSERT_EQ(run("results/with_plots"), 0) << output("stdout") << output("stderr");
  EXPECT_NE(output("stdout").find("report: results/with_plots/report.md"), std::string::npos);
  EXPECT_EQ(output("stderr"), "");
  const std::string out = directory_ + "/results/with_plots";
  const std::string report = readFile(out + "/report.md");
  ASSERT_FALSE(report.empty());

  // The parameter table holds every fitted parameter with the estimate and sigma of
  // result.yaml.
  const YAML::Node result = YAML::LoadFile(out + "/result.yaml");
  ASSERT_EQ(result["parameters"].size(), 6u);
  for (const auto& parameter : result["parameters"]) {
    const std::string name = parameter.first.as<std::string>();
    const std::size_t at = report.find("| " + name + " | ");
    ASSERT_NE(at, std::string::npos) << name;
    const std::string line = report.substr(at, report.find('\n', at) - at);
    char estimate[32], sigma[32];
    std::snprintf(estimate, sizeof(estimate), "%.7g", parameter.second["value"].as<double>());
    std::snprintf(sigma, sizeof(sigma), "%.3g", parameter.second["sigma"].as<double>());
    EXPECT_NE(line.find(std::string(" ") + estimate + " | " + sigma + " | "), std::string::npos)
        << line;
  }
  // The time offset (truth -0.15 s) with its sigma, the verdict, the sections.
  // The estimate, and the offset the fit used (result.yaml's: the offset the pairs were made
  // at when the estimate lies within the pairing tolerance of it).
  char tau[64];
  std::snprintf(tau, sizeof(tau), "the final fit used τ = %.4f s",
                result["time_offset_s"].as<double>());
  EXPECT_NE(report.find(tau), std::string::npos) << report;
  const std::size_t estimated = report.find("Estimated τ = ");
  ASSERT_NE(estimated, std::string::npos) << report;
  EXPECT_NEAR(std::stod(report.substr(estimated + std::string("Estimated τ = ").size())),
              result["time_offset_s"].as<double>(), 0.0101);
  EXPECT_NEAR(result["time_offset_s"].as<double>(), -0.15, 0.02);
  EXPECT_NE(report.find("the encoders run ahead of the laser"), std::string::npos);
  for (const char* section :
       {"## Parameters", "## Observability", "## Time offset",
        "## Per-pair errors before and after", "## Trajectories", "## Pair collection"}) {
    EXPECT_EQ(count(report, std::string(section) + "\n"), 1u) << section;
  }
  EXPECT_EQ(report.find("Some plots are missing"), std::string::npos);
  // Table rows keep their columns: the solver's message ("|cost_change|/cost") is escaped.
  const std::size_t fit_row = report.find("\n| fit | ");
  ASSERT_NE(fit_row, std::string::npos);
  const std::string fit = report.substr(fit_row + 1, report.find('\n', fit_row + 1) - fit_row - 1);
  std::size_t separators = 0;
  for (std::size_t i = 0; i < fit.size(); ++i)
    separators += fit[i] == '|' && (i == 0 || fit[i - 1] != '\\');
  EXPECT_EQ(separators, 3u) << fit;
  // The error table: calibration beats the nominal model by far (the robot is deformed).
  auto median_after = [&](const std::string& row) {
    const std::size_t at = report.find(row);
    return at == std::string::npos ? -1.0 : std::atof(report.c_str() + at + row.size());
  };
  const double before = median_after("| nominal (before) | ");
  const double after = median_after("| calibrated `diff_drive` (after) | ");
  EXPECT_GT(after, 0.0);
  EXPECT_LT(after, 0.5 * before);

  // Three images referenced, present, valid PNG of the scripted sizes.
  for (const auto& [image, width] : {std::make_pair(std::string(kTrajectoryPlot), 900u),
                                     std::make_pair(std::string(kResidualPlot), 1100u),
                                     std::make_pair(std::string(kTimeOffsetPlot), 900u)}) {
    EXPECT_EQ(count(report, "](plots/" + image + ")"), 1u) << image;
    const std::string path = out + "/plots/" + image;
    EXPECT_TRUE(isPngFile(path)) << path;
    EXPECT_GT(fs::file_size(path), 5000u) << path;
    EXPECT_EQ(pngSize(path).first, width) << path;
  }
  // The plotted data: one trajectory row per keyframe, the histogram counts every pair.
  const std::string trajectories = readFile(out + "/plots/trajectories.dat");
  const std::size_t pairs = count(readFile(out + "/pairs.csv"), "\n") - 3;  // header lines
  EXPECT_GT(pairs, 100u);
  // Comment + first keyframe + one per pair the nominal robot is compared on: it is taken at time
  // offset 0 (compareTrajectories), where the last pair's window may end after the last encoder
  // reading (the drive's encoders run 0.15 s ahead of the laser) and is then left out.
  EXPECT_GE(count(trajectories, "\n"), pairs + 1);
  EXPECT_LE(count(trajectories, "\n"), pairs + 2);
  std::istringstream histogram(readFile(out + "/plots/residuals.dat"));
  std::size_t calibrated = 0;
  for (std::string line; std::getline(histogram, line) && !line.empty();) {
    if (line[0] == '#')
      continue;
    double centre, nominal_count, calibrated_count;
    std::istringstream(line) >> centre >> nominal_count >> calibrated_count;
    calibrated += static_cast<std::size_t>(calibrated_count);
  }
  EXPECT_LE(calibrated, pairs);
  EXPECT_GE(calibrated, pairs * 95 / 100);  // 98 % of all errors on the axis
  // Nothing temporary left behind.
  for (const auto& entry : fs::directory_iterator(out))
    EXPECT_EQ(entry.path().filename().string().find(".plots.tmp"), std::string::npos);
}

/// One line of a TUM file: t x y z qx qy qz qw.
struct TumPose
{
  double t = 0.0;
  Eigen::Vector3d p;
  Eigen::Quaterniond q;
};

std::vector<TumPose> readTum(const std::string& path)
{
  std::istringstream lines(readFile(path));
  std::vector<TumPose> poses;
  std::string line;
  while (std::getline(lines, line)) {
    TumPose pose;
    double x, y, z, w;
    std::istringstream fields(line);
    fields >> pose.t >> pose.p.x() >> pose.p.y() >> pose.p.z() >> x >> y >> z >> w;
    EXPECT_TRUE(fields && fields.peek() == EOF) << path << ": " << line;
    pose.q = Eigen::Quaterniond(w, x, y, z);
    poses.push_back(pose);
  }
  return poses;
}

/// The ATE and RPE of a table row of `text` ("<row> <ATE> <RPE> ..."; -1 when absent).
std::pair<double, double> tableScores(const std::string& text, const std::string& row)
{
  const std::size_t at = text.find("\n" + row + " ");
  double ate = -1.0, rpe = -1.0;
  if (at != std::string::npos)
    std::istringstream(text.substr(at + row.size() + 1)) >> ate >> rpe;
  return {ate, rpe};
}

TEST_F(CalibrateBagReport, HoldsOutTheLastPairsAndScoresEveryModelOnThem)
{
  ASSERT_EQ(run("holdout", "--holdout 0.4"), 0) << output("stdout") << output("stderr");
  const std::string report = readFile(directory_ + "/holdout/report.md");
  EXPECT_EQ(count(report, "## Held-out pairs\n"), 1u);
  // Rows of the configured model, of compare_models (linear, gp) and the nominal robot.
  const double calibrated = tableScores(report, "diff_drive").second;
  const double nominal = tableScores(report, "nominal").second;
  EXPECT_GT(calibrated, 0.0) << report;
  EXPECT_LT(calibrated, 0.6 * nominal) << report;
  for (const char* row : {"linear", "gp"})
    EXPECT_GT(tableScores(report, row).first, 0.0) << row << "\n" << report;
  // The best row named, with its factor over the next: the lowest ATE of the table.
  const std::size_t best = report.find("best on the held-out pairs: ");
  ASSERT_NE(best, std::string::npos) << report;
  char best_name[32] = "";
  double best_ate = 0.0;
  std::sscanf(report.c_str() + best, "best on the held-out pairs: %31[a-z_], ATE %lf", best_name,
              &best_ate);
  for (const char* row : {"diff_drive", "linear", "gp", "nominal"})
    EXPECT_LE(best_ate, tableScores(report, row).first + 5e-5) << row << "\n" << report;
  EXPECT_NEAR(best_ate, tableScores(report, best_name).first, 5e-5) << report;
  // Every scored row's dead reckoning in TUM format: unit quaternions about z, increasing
  // stamps, and against the scan matches the ATE the table printed.
  const std::string folder = directory_ + "/holdout/trajectories/holdout/";
  const std::vector<TumPose> matched = readTum(folder + "scan_matched.tum");
  ASSERT_GT(matched.size(), 40u);
  for (const char* row : {"diff_drive", "linear", "gp", "nominal"}) {
    const std::vector<TumPose> poses = readTum(folder + row + ".sensor.tum");
    const std::vector<TumPose> reference = fs::exists(folder + row + ".scan_matched.tum")
                                               ? readTum(folder + row + ".scan_matched.tum")
                                               : matched;
    ASSERT_EQ(poses.size(), reference.size()) << row;
    double sum = 0.0;
    for (std::size_t k = 0; k < poses.size(); ++k) {
      EXPECT_NEAR(poses[k].q.norm(), 1.0, 1e-9) << row << " " << k;
      EXPECT_EQ(poses[k].q.x(), 0.0);
      EXPECT_EQ(poses[k].q.y(), 0.0);
      EXPECT_EQ(poses[k].t, reference[k].t);
      if (k > 0) {
        EXPECT_GT(poses[k].t, poses[k - 1].t) << row << " " << k;
      }
      sum += (poses[k].p - reference[k].p).squaredNorm();
    }
    EXPECT_NEAR(std::sqrt(sum / poses.size()), tableScores(report, row).first, 6e-5) << row;
  }
  // The models that know the sensor's pose also in base_link; the model-free ones do not.
  EXPECT_TRUE(fs::exists(folder + "diff_drive.base_link.tum"));
  EXPECT_TRUE(fs::exists(folder + "nominal.base_link.tum"));
  EXPECT_FALSE(fs::exists(folder + "gp.base_link.tum"));
  // 40 % of the 60 s held out: the fit saw the pairs before about 36 s only.
  const std::size_t at = report.find("held out: the ");
  ASSERT_NE(at, std::string::npos);
  std::size_t test_pairs = 0;
  double border_s = 0.0;
  std::sscanf(report.c_str() + at, "held out: the %zu pairs (T = %*f s) after %lf s", &test_pairs,
              &border_s);
  EXPECT_NEAR(border_s, 36.0, 1.5);
  EXPECT_GT(test_pairs, 40u);
  // Fitted + held out < collected: the pair across the border is in neither.
  const std::string stdout_text = output("stdout");
  const std::size_t summary = stdout_text.find("keyframe pairs: ");
  ASSERT_NE(summary, std::string::npos) << stdout_text;
  const std::size_t collected = std::stoul(stdout_text.substr(summary + 16));
  const YAML::Node result = YAML::LoadFile(directory_ + "/holdout/result.yaml");
  EXPECT_LT(result["fit"]["pairs"].as<std::size_t>() + test_pairs, collected);
  EXPECT_GE(result["fit"]["pairs"].as<std::size_t>() + test_pairs + 3, collected);
  // result.yaml's scores: the table's rows, the held-out pairs named as the report names them.
  const YAML::Node held_out = result["scores"]["held_out"];
  EXPECT_EQ(held_out["description"].as<std::string>().rfind("held out: the ", 0), 0u);
  ASSERT_EQ(held_out["models"].size(), 4u);
  for (const YAML::Node& row : held_out["models"]) {
    const std::string model = row["model"].as<std::string>();
    // The nominal row's pairs are cut again at time offset 0: one may fall out at an end.
    EXPECT_NEAR(static_cast<double>(row["pairs"].as<std::size_t>()),
                static_cast<double>(test_pairs), model == "nominal" ? 1.0 : 0.0)
        << model;
    EXPECT_NEAR(row["ate_m"].as<double>(), tableScores(report, model).first, 6e-5) << model;
    EXPECT_NEAR(row["rpe_m"].as<double>(), tableScores(report, model).second, 6e-5) << model;
  }
  EXPECT_FALSE(result["scores"]["test"]);
  EXPECT_FALSE(result["fit_interval_choice"]);  // the configured interval
}

/// The "held out: the N pairs" count of a report (0 if none).
std::size_t heldOutPairs(const std::string& report)
{
  const std::size_t at = report.find("held out: the ");
  std::size_t pairs = 0;
  if (at != std::string::npos)
    std::sscanf(report.c_str() + at, "held out: the %zu pairs", &pairs);
  return pairs;
}

TEST_F(CalibrateBagReport, FitIntervalGivenOrChosenByCrossValidation)
{
  // A given interval: the fit uses 1 s pairs (about 36 over the 36 s before the border), the
  // held-out yardstick stays the configured 0.5 s pairs.
  ASSERT_EQ(run("interval_fixed", "--holdout 0.4 --interval 1.0"), 0) << output("stderr");
  const std::string fixed = readFile(directory_ + "/interval_fixed/report.md");
  EXPECT_NE(fixed.find("fit interval T = 1.00 s (--interval)"), std::string::npos) << fixed;
  const std::size_t fitted_1s =
      YAML::LoadFile(directory_ + "/interval_fixed/result.yaml")["fit"]["pairs"].as<std::size_t>();
  EXPECT_GE(fitted_1s, 28u);
  EXPECT_LE(fitted_1s, 37u);
  const std::size_t yardstick = heldOutPairs(fixed);
  EXPECT_GT(yardstick, 40u);

  // auto: three candidates scored, one chosen, its curve plotted; same held-out pairs.
  ASSERT_EQ(run("interval_auto", "--holdout 0.4 --interval auto"), 0) << output("stderr");
  const std::string report = readFile(directory_ + "/interval_auto/report.md");
  EXPECT_EQ(count(report, "## Fit interval\n"), 1u);
  double chosen = 0.0;
  const std::size_t at = report.find("fit interval T = ");
  ASSERT_NE(at, std::string::npos) << report;
  std::sscanf(report.c_str() + at, "fit interval T = %lf s", &chosen);
  EXPECT_TRUE(chosen == 0.3 || chosen == 0.5 || chosen == 1.0) << chosen;
  EXPECT_EQ(count(report, " m (chosen)"), 1u) << report;
  for (const char* candidate : {"0.30 s 0.", "0.50 s 0.", "1.00 s 0."})
    EXPECT_NE(report.find(candidate), std::string::npos) << candidate << "\n" << report;
  EXPECT_TRUE(isPngFile(directory_ + "/interval_auto/plots/" + kFitIntervalPlot));
  EXPECT_NE(report.find("](plots/fit_interval.png)"), std::string::npos);
  EXPECT_EQ(heldOutPairs(report), yardstick);
  const YAML::Node result = YAML::LoadFile(directory_ + "/interval_auto/result.yaml");
  const std::size_t fitted = result["fit"]["pairs"].as<std::size_t>();
  EXPECT_NEAR(static_cast<double>(fitted), 36.0 / chosen, 0.25 * 36.0 / chosen);
  // result.yaml's fit_interval_choice: the curve the report printed, by the RPE of the 0.5 s
  // pairs (a laser's relative displacements), its lowest point the fit's interval.
  const YAML::Node choice = result["fit_interval_choice"];
  EXPECT_EQ(choice["criterion"].as<std::string>(), "RPE");
  EXPECT_DOUBLE_EQ(choice["evaluation_interval_s"].as<double>(), 0.5);
  ASSERT_EQ(choice["curve"].size(), 3u);
  double lowest = INFINITY, lowest_at_s = 0.0;
  for (const YAML::Node& score : choice["curve"]) {
    if (score["validation_error_m"].as<double>() < lowest) {
      lowest = score["validation_error_m"].as<double>();
      lowest_at_s = score["interval_s"].as<double>();
    }
  }
  EXPECT_EQ(lowest_at_s, chosen);
  EXPECT_DOUBLE_EQ(result["fit_interval_s"].as<double>(), chosen);

  EXPECT_EQ(run("interval_bad", "--interval often"), 2);
  EXPECT_NE(output("stderr").find("option --interval: expected 'auto' or a number of seconds"),
            std::string::npos)
      << output("stderr");
  EXPECT_FALSE(fs::exists(directory_ + "/interval_bad"));
}

TEST_F(CalibrateBagReport, WithoutGnuplotTheReportSaysWhatIsMissing)
{
  const std::string out = directory_ + "/without_gnuplot";
  ASSERT_EQ(run(out, "--gnuplot /nonexistent/gnuplot"), 0) << output("stderr");
  EXPECT_NE(output("stderr").find("gnuplot-nox"), std::string::npos) << output("stderr");
  const std::string report = readFile(out + "/report.md");
  EXPECT_NE(report.find("Some plots are missing: the plotting program '/nonexistent/gnuplot' was "
                        "not found (install the Debian package gnuplot-nox"),
            std::string::npos)
      << report;
  EXPECT_NE(report.find("| sensor_x | "), std::string::npos);
  EXPECT_EQ(report.find("](plots/"), std::string::npos);  // no broken image links
  EXPECT_FALSE(fs::exists(out + "/plots/" + kTrajectoryPlot));
  EXPECT_GT(fs::file_size(out + "/plots/trajectories.gp"), 100u);  // to draw them later
  EXPECT_TRUE(fs::exists(out + "/result.yaml"));
  EXPECT_TRUE(fs::exists(out + "/pairs.csv"));

  // Run again with gnuplot into the same folder: the plot folder is replaced as a whole.
  ASSERT_EQ(run(out), 0) << output("stderr");
  EXPECT_TRUE(isPngFile(out + "/plots/" + kTrajectoryPlot));
  EXPECT_EQ(readFile(out + "/report.md").find("Some plots are missing"), std::string::npos);
  std::size_t folders = 0;
  for (const auto& entry : fs::directory_iterator(out))
    folders += entry.is_directory() ? 1 : 0;
  EXPECT_EQ(folders, 1u);
}

TEST_F(CalibrateBagReport, BadInputWritesNothing)
{
  const std::string out = directory_ + "/bad_input";
  EXPECT_EQ(run(out, directory_ + "/missing.bag"), 1);
  EXPECT_NE(output("stderr").find("missing.bag"), std::string::npos);
  EXPECT_FALSE(fs::exists(out));
}

}  // namespace
}  // namespace odometry_calibration
