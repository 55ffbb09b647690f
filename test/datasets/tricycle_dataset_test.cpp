#include <cmath>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"

namespace odometry_calibration {
namespace {

const char* kHeader =
    "#kinematic_model: traction_drive_wheel\n"
    "#parameters: [ Ksteer Ktraction axis_length steer_offset ]\n"
    "#parameter_values: 0.1 0.0106141 1.4 0 \n"
    "#joints_max_enc: [ steering traction_wheel ]\n"
    "#joints_max_enc_values: 8192 5000 \n"
    "#laser wrt base_link \n"
    "#\ttranslation:\t[ 1.5, 0.25, 0 ],\n"
    "#\trotation:\t [ 0, 0, 0.0998334166, 0.9950041653 ]\n";

const char* kTwoRows =
    "time: 1668091587.485239267 ticks: 290 4294962835 model_pose:    0.218764 0.000380236  "
    "0.00347622 tracker_pose: 0.232356 0.0160216 0.0162944\n"
    "time: 1668091587.525347471 ticks: 290 526 model_pose:    0.229347 0.000417918   0.0036444 "
    "tracker_pose: 0.241088 0.0233116 0.0151734\n";

TricycleDataset parse(const std::string& text)
{
  std::istringstream stream(text);
  return parseTricycleDataset(stream, "test.txt");
}

/// The 1-based line of the error that parsing `text` raises, or 0 if it parses.
std::size_t errorLine(const std::string& text, std::string* message = nullptr)
{
  try {
    parse(text);
  } catch (const DatasetParseError& error) {
    if (message)
      *message = error.what();
    return error.line();
  }
  return 0;
}

TEST(TricycleDataset, ParsesHeaderAndRows)
{
  const TricycleDataset dataset = parse(std::string(kHeader) + kTwoRows);
  const TricycleDatasetHeader& header = dataset.header;
  EXPECT_EQ(header.kinematic_model, "traction_drive_wheel");
  ASSERT_EQ(header.parameter_names.size(), 4u);
  EXPECT_EQ(header.parameter_names[3], "steer_offset");
  ASSERT_EQ(header.parameter_values.size(), 4u);
  EXPECT_DOUBLE_EQ(header.parameter_values[1], 0.0106141);
  ASSERT_EQ(header.joint_max_values.size(), 2u);
  EXPECT_EQ(header.joint_max_values[0], 8192.0);
  EXPECT_TRUE(header.has_sensor_pose);
  EXPECT_DOUBLE_EQ(header.T_base_sensor.x(), 1.5);
  EXPECT_DOUBLE_EQ(header.T_base_sensor.y(), 0.25);
  EXPECT_NEAR(header.T_base_sensor.theta(), 0.2, 1e-9);  // quaternion of yaw 0.2

  ASSERT_EQ(dataset.rows.size(), 2u);
  EXPECT_EQ(dataset.rows[0].line, 9u);
  EXPECT_EQ(dataset.rows[0].stamp_s, 0.0);
  // Nanosecond digits survive: 0.040108204 s between the stamps.
  EXPECT_NEAR(dataset.rows[1].stamp_s, 0.040108204, 1e-12);
  EXPECT_EQ(dataset.rows[0].traction_ticks, 4294962835.0);
  EXPECT_EQ(dataset.rows[1].steering_ticks, 290.0);
  EXPECT_DOUBLE_EQ(dataset.rows[1].T_world_sensor.y(), 0.0233116);
  EXPECT_DOUBLE_EQ(dataset.rows[0].T_odom_base_model.theta(), 0.00347622);
}

TEST(TricycleDataset, ReportsTheLineAndWhatWasExpected)
{
  const std::string header(kHeader);
  std::string message;
  // Missing token.
  EXPECT_EQ(
      errorLine(header + "time: 1.0 ticks: 290 5 model_pose: 0 0 tracker_pose: 0 0 0\n", &message),
      9u);
  EXPECT_NE(message.find("test.txt:9"), std::string::npos) << message;
  EXPECT_NE(message.find("13 tokens"), std::string::npos) << message;
  // Wrong label.
  EXPECT_EQ(
      errorLine(header + "time: 1.0 tics: 290 5 model_pose: 0 0 0 tracker_pose: 0 0 0\n", &message),
      9u);
  EXPECT_NE(message.find("'ticks:'"), std::string::npos) << message;
  // Not a number in the tracker pose, on the second data line.
  EXPECT_EQ(errorLine(header + kTwoRows +
                          "time: 1668091588.0 ticks: 290 600 model_pose: 0 0 0 tracker_pose: "
                          "0 abc 0\n",
                      &message),
            11u);
  EXPECT_NE(message.find("tracker_pose"), std::string::npos) << message;
  EXPECT_NE(message.find("'abc'"), std::string::npos) << message;
  // Negative and fractional ticks.
  EXPECT_EQ(errorLine("time: 1.0 ticks: -3 5 model_pose: 0 0 0 tracker_pose: 0 0 0\n"), 1u);
  EXPECT_EQ(errorLine("time: 1.0 ticks: 3 5.5 model_pose: 0 0 0 tracker_pose: 0 0 0\n"), 1u);
  EXPECT_EQ(errorLine("time: 1.0 ticks: 3 4294967296 model_pose: 0 0 0 tracker_pose: 0 0 0\n"), 1u);
  // Bad time and time going backwards.
  EXPECT_EQ(errorLine("time: soon ticks: 3 5 model_pose: 0 0 0 tracker_pose: 0 0 0\n"), 1u);
  EXPECT_EQ(errorLine(std::string(kTwoRows) +
                          "time: 1668091587.0 ticks: 3 5 model_pose: 0 0 0 tracker_pose: 0 0 0\n",
                      &message),
            3u);
  EXPECT_NE(message.find("backwards"), std::string::npos) << message;
  // A non-finite pose value.
  EXPECT_EQ(errorLine("time: 1.0 ticks: 3 5 model_pose: 0 nan 0 tracker_pose: 0 0 0\n"), 1u);
  // Malformed header numbers.
  EXPECT_EQ(errorLine("#parameter_values: 0.1 x 1.4 0\n"), 1u);
  EXPECT_EQ(errorLine("#laser wrt base_link\n#\ttranslation:\t[ 1.5, 0 ],\n"), 2u);
}

TEST(TricycleDataset, RefusesAbsurdAndLeapingTrackerPoses)
{
  // Issue 32: a tracker x of 1e308 crashed the fit, one of 1e10 gave an ATE of 1.8e8 m, one of
  // 1000 among poses centimetres apart an ATE of 20 m instead of 0.38 m.
  std::string message;
  EXPECT_EQ(errorLine("time: 1.0 ticks: 3 5 model_pose: 0 0 0 tracker_pose: 1e308 0 0\n", &message),
            1u);
  EXPECT_NE(message.find("tracker_pose x = 1e308 is beyond +-1e6"), std::string::npos) << message;
  EXPECT_EQ(errorLine("time: 1.0 ticks: 3 5 model_pose: 0 -1e10 0 tracker_pose: 0 0 0\n"), 1u);
  std::string rows;
  for (int i = 0; i < 20; ++i) {
    const double x = i == 10 ? 1000.0 : 0.02 * i;
    rows += "time: " + std::to_string(1.0 + 0.04 * i) + " ticks: 3 " + std::to_string(5 + i) +
            " model_pose: 0 0 0 tracker_pose: " + std::to_string(x) + " 0 0\n";
  }
  EXPECT_EQ(errorLine(rows, &message), 11u);
  EXPECT_NE(message.find("tracker_pose leaps 999.8"), std::string::npos) << message;
  // The same drive with a real jump (the robot carried 5 m away, staying there): accepted.
  std::string carried;
  for (int i = 0; i < 20; ++i) {
    const double x = 0.02 * i + (i >= 10 ? 5.0 : 0.0);
    carried += "time: " + std::to_string(1.0 + 0.04 * i) + " ticks: 3 " + std::to_string(5 + i) +
               " model_pose: 0 0 0 tracker_pose: " + std::to_string(x) + " 0 0\n";
  }
  EXPECT_EQ(errorLine(carried), 0u);
}

TEST(TricycleDataset, ToleratesBlankLinesAndWindowsLineEnds)
{
  const TricycleDataset dataset = parse(std::string(kHeader) + "\n" + kTwoRows + "\r\n");
  EXPECT_EQ(dataset.rows.size(), 2u);
}

TEST(TricycleLog, HeaderGivesLayoutAndNominalParameters)
{
  const TricycleDataset dataset = parse(std::string(kHeader) + kTwoRows);
  const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
  EXPECT_EQ(layout.steering_index, 0);
  EXPECT_EQ(layout.steering_ticks_per_turn, 8192.0);
  EXPECT_EQ(layout.traction_ticks_per_turn, 5000.0);
  const TricycleParameters nominal = tricycleNominalFromHeader(dataset.header);
  EXPECT_EQ(nominal.axis_length_m, 1.4);
  EXPECT_EQ(nominal.T_base_sensor.x(), 1.5);

  TricycleDatasetHeader incomplete = dataset.header;
  incomplete.parameter_values.pop_back();
  EXPECT_THROW(tricycleNominalFromHeader(incomplete), std::invalid_argument);
  incomplete.joint_max_values.clear();
  EXPECT_THROW(tricycleLayoutFromHeader(incomplete), std::invalid_argument);
}

TEST(TricycleLog, DecodesTheRealLogsWrapAndReversals)
{
  const std::string path =
      std::string(ODOMETRY_CALIBRATION_SHARED_DATA_DIR) + "/tricycle/dataset.txt";
  if (!std::ifstream(path)) {
    GTEST_SKIP() << "real dataset not found at " << path;
  }
  const TricycleDataset dataset = loadTricycleDataset(path);
  ASSERT_EQ(dataset.rows.size(), 2434u);
  const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
  const auto samples = decodeTricycleEncoders(dataset, layout);
  // Numbers from shared/data/tricycle/README.md.
  EXPECT_EQ(samples[59].values(1) - samples[58].values(1), 4987.0);
  EXPECT_EQ(samples.back().values(1), 5650996.0);  // net travel in ticks
  double absolute_ticks = 0.0;
  int negative_steps = 0, negative_steering = 0;
  for (std::size_t k = 1; k < samples.size(); ++k) {
    const double step = samples[k].values(1) - samples[k - 1].values(1);
    absolute_ticks += std::abs(step);
    negative_steps += step < 0.0;
  }
  for (const auto& sample : samples) {
    negative_steering += sample.values(0) < 0.0;
  }
  EXPECT_EQ(absolute_ticks, 17432208.0);
  EXPECT_EQ(negative_steps, 767);
  EXPECT_EQ(negative_steering, 1424);
  EXPECT_NEAR(samples.back().stamp_s, 113.35, 0.01);
}

}  // namespace
}  // namespace odometry_calibration
