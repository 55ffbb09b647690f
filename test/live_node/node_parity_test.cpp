// rostest (test/node_parity.test, issue 31): the live node and calibrate_bag are one calibration
// session fed from two readers, so the same bag through both gives the same pairs and the same
// fit: with a fixed keyframe interval, with the fit interval chosen among candidates, and with
// the time offset estimated (configured at the truth, and 0.1 s off it: paired again), and from
// the base's own odometry (wheels.source odometry, model base_odometry). The reply,
// the report and /diagnostics count the fitted, rejected and down-weighted pairs alike (issue 34).
#include <cmath>
#include <cstdlib>
#include <map>
#include <string>
#include <vector>

#include <diagnostic_msgs/DiagnosticArray.h>
#include <gtest/gtest.h>
#include <ros/ros.h>
#include <yaml-cpp/yaml.h>

#include "node_test_support.h"
#include "odometry_calibration/Calibrate.h"

namespace odometry_calibration {
namespace {

using test::fileLines;
using test::readText;
using test::waitFor;

const std::vector<std::string> kNodes = {"fixed", "intervals", "offset", "offset_off",
                                         "base_odometry"};

/// The line counts of the nodes' pairs files.
std::vector<std::size_t> pairFileLines(const std::string& output_directory)
{
  std::vector<std::size_t> counts;
  for (const std::string& name : kNodes)
    counts.push_back(fileLines(output_directory + "/" + name + "/pairs.csv"));
  return counts;
}

class NodeParity : public ::testing::TestWithParam<std::string>
{
protected:
  /// Plays the bag once every node has subscribed (a node advertises its services after
  /// subscribing), at real time, then waits until no node's pairs file grows for 5 s.
  static void SetUpTestSuite()
  {
    ros::NodeHandle private_handle("~");
    std::string bag, output_directory;
    ASSERT_TRUE(private_handle.getParam("bag", bag));
    ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
    for (const std::string& name : kNodes)
      ASSERT_TRUE(ros::service::waitForService("/" + name + "/calibrate", ros::Duration(60)));
    const std::string play = "rosbag play --clock --quiet -d 2 " + bag +
                             " --wait-for-subscribers --topics /joint_states /odom /scan > " +
                             output_directory + "/play.log 2>&1";
    ASSERT_EQ(std::system(play.c_str()), 0) << play;
    test::waitUntilSettled<std::vector<std::size_t>>(
        [&] { return pairFileLines(output_directory); }, 5, 60);
  }
};

TEST_P(NodeParity, NodeAndCalibrateBagGiveTheSamePairsAndParameters)
{
  const std::string name = GetParam();
  ros::NodeHandle private_handle("~");
  std::string bag, configs, output_directory;
  ASSERT_TRUE(private_handle.getParam("bag", bag));
  ASSERT_TRUE(private_handle.getParam("configs", configs));
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  const std::string config = configs + "/parity_" + name + ".yaml";
  const std::string node_output = output_directory + "/" + name;

  odometry_calibration::Calibrate fit;
  ASSERT_TRUE(ros::service::call("/" + name + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;

  const std::string bag_output = output_directory + "/calibrate_bag_" + name;
  ASSERT_TRUE(test::runCalibrateBag(config, bag, bag_output)) << readText(bag_output + ".log");

  // The same pairs collected (the node's file holds every pair at keyframes.interval_s)...
  const YAML::Node node_fit = YAML::LoadFile(node_output + "/last_fit.yaml");
  const YAML::Node bag_fit = YAML::LoadFile(bag_output + "/result.yaml");
  // (three header lines: the format, the joints, the columns)
  EXPECT_EQ(fit.response.report.pairs_collected + 3, fileLines(node_output + "/pairs.csv"));
  if (name == "fixed" || name == "base_odometry") {  // the bag tool writes the fitted pairs: all
                                                     // of them here, as collected
    const std::string node_text = readText(node_output + "/pairs.csv");
    const std::string bag_text = readText(bag_output + "/pairs.csv");
    EXPECT_GT(node_text.size(), 1000u);
    EXPECT_EQ(node_text, bag_text);
  }
  // ... as many as calibrate_bag collected (its summary counts them; with the offset 0.1 s off
  // the truth both paired the recorded inputs again at the estimate) ...
  const std::string bag_log = readText(bag_output + ".log");
  EXPECT_NE(bag_log.find("keyframe pairs: " + std::to_string(fit.response.report.pairs_collected) +
                         " from"),
            std::string::npos)
      << fit.response.report.pairs_collected << "\n"
      << bag_log;
  if (name == "offset_off") {
    EXPECT_NE(bag_log.find("paired again at the estimated time offset"), std::string::npos)
        << bag_log;
    EXPECT_NE(fit.response.message.find("paired again at the estimated time offset"),
              std::string::npos)
        << fit.response.message;
    EXPECT_NEAR(node_fit["time_offset_s"].as<double>(), 0.0, 0.01);  // the simulated truth
  }
  // ... the same pairs fitted, at the same interval and time offset ...
  EXPECT_EQ(node_fit["fit"]["pairs"].as<int>(), bag_fit["fit"]["pairs"].as<int>());
  EXPECT_EQ(node_fit["fit"]["outliers"].as<int>(), bag_fit["fit"]["outliers"].as<int>());
  EXPECT_EQ(node_fit["fit_interval_s"].as<double>(), bag_fit["fit_interval_s"].as<double>());
  EXPECT_NEAR(node_fit["time_offset_s"].as<double>(), bag_fit["time_offset_s"].as<double>(), 1e-6);
  // ... and the same parameters within 0.01 %.
  for (const auto& entry : bag_fit["parameters"]) {
    const std::string parameter = entry.first.as<std::string>();
    const double bag_value = entry.second["value"].as<double>();
    const double node_value = node_fit["parameters"][parameter]["value"].as<double>();
    EXPECT_NEAR(node_value, bag_value, 1e-4 * std::max(std::abs(bag_value), 1e-3))
        << name << ": " << parameter;
  }
  // ... counted alike in calibrate_bag's report (the same pairs fitted, asserted above).
  const std::string counts_row =
      "| pairs | " + node_fit["fit"]["pairs"].as<std::string>() + " used, " +
      node_fit["fit"]["rejected"].as<std::string>() + " rejected, " +
      node_fit["fit"]["down_weighted"].as<std::string>() + " down-weighted |";
  const std::string report_text = readText(bag_output + "/report.md");
  EXPECT_NE(report_text.find(counts_row), std::string::npos) << counts_row;
  RecordProperty("pairs_fitted", node_fit["fit"]["pairs"].as<std::string>());
}

/// The value of `key` in the node's "calibration" status of the newest /diagnostics.
class DiagnosticsListener
{
public:
  explicit DiagnosticsListener(const std::string& node)
      : status_name_("/" + node + ": calibration"),
        subscriber_(ros::NodeHandle().subscribe("/diagnostics", 100,
                                                &DiagnosticsListener::onDiagnostics, this))
  {
  }
  std::string value(const std::string& key) const
  {
    const auto found = values_.find(key);
    return found == values_.end() ? std::string() : found->second;
  }

private:
  void onDiagnostics(const diagnostic_msgs::DiagnosticArray& array)
  {
    for (const diagnostic_msgs::DiagnosticStatus& status : array.status) {
      if (status.name != status_name_)
        continue;
      values_.clear();
      for (const diagnostic_msgs::KeyValue& entry : status.values)
        values_[entry.key] = entry.value;
    }
  }
  std::string status_name_;
  ros::Subscriber subscriber_;
  std::map<std::string, std::string> values_;
};

TEST_P(NodeParity, ReplyReportAndDiagnosticsGiveTheSameCounts)
{
  // Issue 34: the reply said "480 pairs (24 rejected)" where the report had 1 rejected and 23
  // down-weighted; after a time-offset fit the reply said 358 pairs and /diagnostics 359.
  const std::string name = GetParam();
  ros::NodeHandle private_handle("~");
  std::string output_directory;
  ASSERT_TRUE(private_handle.getParam("output_directory", output_directory));
  DiagnosticsListener diagnostics(name);
  odometry_calibration::Calibrate fit;
  ASSERT_TRUE(ros::service::call("/" + name + "/calibrate", fit));
  ASSERT_TRUE(fit.response.success) << fit.response.message;
  const CalibrationReport& report = fit.response.report;
  const YAML::Node node_fit = YAML::LoadFile(output_directory + "/" + name + "/last_fit.yaml");
  // The report (last_fit.yaml) and the reply's report message ...
  EXPECT_EQ(node_fit["fit"]["pairs"].as<unsigned>(), report.pairs_used);
  EXPECT_EQ(node_fit["fit"]["rejected"].as<unsigned>(), report.pairs_rejected);
  EXPECT_EQ(node_fit["fit"]["down_weighted"].as<unsigned>(), report.pairs_down_weighted);
  EXPECT_EQ(node_fit["fit"]["outliers"].as<unsigned>(),
            report.pairs_rejected + report.pairs_down_weighted);
  // ... the reply's sentence ...
  const std::string sentence = "fitted to " + std::to_string(report.pairs_used) + " pairs (" +
                               std::to_string(report.pairs_rejected) + " rejected, " +
                               std::to_string(report.pairs_down_weighted) + " down-weighted)";
  EXPECT_NE(fit.response.message.find(sentence), std::string::npos) << fit.response.message;
  // ... and /diagnostics (published every second).
  EXPECT_TRUE(waitFor(
      [&] {
        return diagnostics.value("last fit: pairs used") == std::to_string(report.pairs_used);
      },
      10.0))
      << diagnostics.value("last fit: pairs used") << " vs " << report.pairs_used;
  EXPECT_EQ(diagnostics.value("last fit: pairs rejected"), std::to_string(report.pairs_rejected));
  EXPECT_EQ(diagnostics.value("last fit: pairs down-weighted"),
            std::to_string(report.pairs_down_weighted));
  EXPECT_NE(
      diagnostics.value("model").find("fit of " + std::to_string(report.pairs_used) + " pairs"),
      std::string::npos)
      << diagnostics.value("model");
  RecordProperty("counts", sentence);
}

INSTANTIATE_TEST_SUITE_P(Configurations, NodeParity,
                         ::testing::Values("fixed", "intervals", "offset", "offset_off",
                                           "base_odometry"));

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  ::testing::InitGoogleTest(&argc, argv);
  ros::init(argc, argv, "node_parity_test");
  ros::NodeHandle handle;
  return RUN_ALL_TESTS();
}
