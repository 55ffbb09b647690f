#include <filesystem>
#include <fstream>
#include <iostream>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

class BagRunner : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/bag_runner_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    scenario_ = sim::loadScenarioYaml(kConfig + "/sim/scenarios/diff_drive_office.yaml",
                                      kConfig + "/sim/worlds");
    scenario_.duration_s = 40.0;
    bag_ = directory_ + "/office.bag";
    simulateToBag(scenario_, bag_, "");
    config_ = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::string directory_, bag_;
  sim::Scenario scenario_;
  CalibrationConfig config_;
};

TEST_F(BagRunner, CalibratesASimulatedBagToItsTruth)
{
  const BagRunResult run = runBags({bag_}, config_);
  EXPECT_EQ(run.counts.encoder_messages, 2001u);
  EXPECT_EQ(run.counts.ego_messages, 401u);
  EXPECT_GT(run.pairs.size(), 70u);
  EXPECT_EQ(run.counts.bad_encoder_messages, 0u);
  auto model = makeModel("diff_drive", config_.models);
  const ModelReport report = model->fit(run.pairs);
  ASSERT_TRUE(report.converged);
  // scenario truth: r_L 0.0765, r_R 0.0775, b 0.32, laser (0.145, 0.01, 0.02)
  EXPECT_NEAR(report.parameters[0].value, 0.0765, 0.0765 * 0.005);
  EXPECT_NEAR(report.parameters[1].value, 0.0775, 0.0775 * 0.005);
  EXPECT_NEAR(report.parameters[2].value, 0.32, 0.32 * 0.005);
  EXPECT_NEAR(report.T_base_sensor.x(), 0.145, 0.005);
  EXPECT_NEAR(report.T_base_sensor.y(), 0.01, 0.005);
  EXPECT_NEAR(report.T_base_sensor.theta(), 0.02, 0.0087);
}

TEST_F(BagRunner, EstimatesTheEncoderLaserTimeOffset)
{
  // The encoders stamped 0.15 s early (they run ahead of the laser), as on the Mines log.
  scenario_.encoders.time_offset_s = -0.15;
  scenario_.motion.max_speed_mps = 0.6;
  scenario_.motion.max_turn_rate_radps = 1.2;
  const std::string bag = directory_ + "/offset.bag";
  simulateToBag(scenario_, bag, "");
  const BagRunResult run = runBags({bag}, config_);
  ASSERT_GT(run.encoder_history.size(), 1000u);
  const TimeOffsetResult offset = estimateTimeOffset(
      run.pairs, run.encoder_history, [&]() { return makeModel("diff_drive", config_.models); },
      TimeOffsetOptions());
  EXPECT_NEAR(offset.offset_s, -0.15, 0.015);
  EXPECT_FALSE(offset.at_boundary);
  EXPECT_GT(offset.sigma_s, 0.0);
  EXPECT_LT(offset.sigma_s, 0.02);
  // The cost is far worse at zero offset than at the estimate.
  double at_zero = 0.0, at_best = 1e300;
  for (const auto& [tau, cost] : offset.curve) {
    if (std::abs(tau) < 1e-9)
      at_zero = cost;
    at_best = std::min(at_best, cost);
  }
  EXPECT_GT(at_zero, 5.0 * at_best);
}

TEST_F(BagRunner, SameBagSamePairs)
{
  const BagRunResult a = runBags({bag_}, config_);
  const BagRunResult b = runBags({bag_}, config_);
  ASSERT_EQ(a.pairs.size(), b.pairs.size());
  for (std::size_t i = 0; i < a.pairs.size(); ++i) {
    EXPECT_EQ(a.pairs[i].sensor_motion.vector(), b.pairs[i].sensor_motion.vector());
  }
  // A time window: only the first 20 s.
  const BagRunResult half = runBags({bag_}, config_, 0.0, 20.0);
  EXPECT_NEAR(static_cast<double>(half.pairs.size()), a.pairs.size() / 2.0, 3.0);
}

TEST_F(BagRunner, BadInputGivesClearErrors)
{
  auto message = [&](const std::vector<std::string>& bags, const CalibrationConfig& config) {
    try {
      runBags(bags, config);
    } catch (const std::runtime_error& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(message({directory_ + "/missing.bag"}, config_).find("no bag file"), std::string::npos);
  // A time window beyond the bag's end.
  try {
    runBags({bag_}, config_, 1000.0, 0.0);
    ADD_FAILURE() << "an empty window was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("is empty"), std::string::npos) << error.what();
  }
  // A truncated bag (cut in the middle, index lost).
  const std::string truncated = directory_ + "/truncated.bag";
  {
    std::ifstream in(bag_, std::ios::binary);
    std::string bytes((std::istreambuf_iterator<char>(in)), {});
    std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 2);
  }
  EXPECT_NE(message({truncated}, config_).find("reindex"), std::string::npos);
  // A topic that is not in the bag.
  CalibrationConfig other = config_;
  other.scan_topic = "/front_scan";
  EXPECT_NE(message({bag_}, other).find("/front_scan"), std::string::npos);
  // JointState without the configured joints.
  CalibrationConfig renamed = config_;
  renamed.joints[1].name = "rear_wheel";
  EXPECT_NE(message({bag_}, renamed).find("rear_wheel"), std::string::npos);
}

TEST_F(BagRunner, MismatchedJointStatesAreSkippedAndCounted)
{
  const std::string bag_path = directory_ + "/broken.bag";
  {
    rosbag::Bag in(bag_, rosbag::bagmode::Read);
    rosbag::Bag out(bag_path, rosbag::bagmode::Write);
    int count = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      auto joints = m.instantiate<sensor_msgs::JointState>();
      if (joints && ++count % 10 == 0) {
        joints->position.pop_back();  // names and positions of different lengths
        out.write(m.getTopic(), m.getTime(), *joints);
      } else {
        out.write(m.getTopic(), m.getTime(), m);
      }
    }
  }
  const BagRunResult run = runBags({bag_path}, config_);
  EXPECT_EQ(run.counts.bad_encoder_messages, 200u);
  EXPECT_NE(run.counts.first_bad_encoder_message.find("2 names but 1 positions"), std::string::npos)
      << run.counts.first_bad_encoder_message;
  EXPECT_GT(run.pairs.size(), 60u);
}

TEST_F(BagRunner, ScansWithAnImpossibleGeometryAreSkippedAndCountedAsTheNodeDoes)
{
  const std::string bag_path = directory_ + "/broken_scans.bag";
  {
    rosbag::Bag in(bag_, rosbag::bagmode::Read);
    rosbag::Bag out(bag_path, rosbag::bagmode::Write);
    int count = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      auto scan = m.instantiate<sensor_msgs::LaserScan>();
      if (scan && ++count % 50 == 0) {
        scan->angle_increment = 0.0f;  // no ray direction: the conversion refuses it
        out.write(m.getTopic(), m.getTime(), *scan);
      } else {
        out.write(m.getTopic(), m.getTime(), m);
      }
    }
  }
  const BagRunResult clean = runBags({bag_}, config_);
  const BagRunResult run = runBags({bag_path}, config_);
  EXPECT_EQ(run.counts.bad_ego_messages, 8u);  // 401 scans, every 50th
  EXPECT_NE(run.counts.first_bad_ego_message.find("angle_increment"), std::string::npos)
      << run.counts.first_bad_ego_message;
  const std::vector<std::string> notes = run.session->source(0).collectionNotes();
  ASSERT_FALSE(notes.empty());
  EXPECT_EQ(notes.front().rfind("skipped 8 LaserScan messages, first: ", 0), 0u) << notes.front();
  // The keyframes move to the neighbouring scans: the run goes on with about as many pairs.
  EXPECT_GT(run.pairs.size(), clean.pairs.size() - 20);
}

TEST(BagRunSummary, ScaleCheckLineAndTheLinesAfterIt)
{
  BagRunResult run;
  run.counts.statistics.pairs = 7;
  run.counts.statistics.rejected["keyframe match disagrees with consecutive matches"] = 3;
  const std::string without = formatBagRunSummary(run, run.counts, {});
  EXPECT_EQ(without.find("scale check"), std::string::npos) << without;
  // Two pairs: chains 4 and 6 m, keyframe matches 4.04 and 6.01 m (R = 1.005; residuals
  // +0.02, -0.02; standard error 100 sqrt(2 * 0.0008) / 10 = 0.40 %).
  run.counts.statistics.chained_m = 10.0;
  run.counts.statistics.keyframe_along_chain_m = 10.05;
  run.counts.statistics.scale_check_pairs = 2;
  run.counts.statistics.chained_m2 = 4.0 * 4.0 + 6.0 * 6.0;
  run.counts.statistics.keyframe_along_chain_m2 = 4.04 * 4.04 + 6.01 * 6.01;
  run.counts.statistics.chained_times_keyframe_m2 = 4.0 * 4.04 + 6.0 * 6.01;
  EXPECT_NEAR(run.counts.statistics.keyframeVersusChainStandardErrorPercent(), 0.40, 1e-9);
  const std::string summary = formatBagRunSummary(run, run.counts, {});
  EXPECT_NE(summary.find("scale check: keyframe matches +0.50 % (± 0.40) against the chained "
                         "consecutive matches over 2 pairs"),
            std::string::npos)
      << summary;
  // The stream's number format is back to the default after it (no sign, no fixed digits).
  EXPECT_NE(summary.find("  rejected 3: keyframe match disagrees"), std::string::npos) << summary;
}

TEST_F(BagRunner, EncoderGlitchesAreSkippedCountedAndChangeNoParameter)
{
  // 20 single-message jumps of 1e6 ticks (alternately on each wheel), every 300th JointState
  // of a 2-minute drive. Each is a spike (the next reading is where the wheel was): the counts
  // go on across it, so it takes no interval away and the pairs are the clean drive's.
  scenario_.duration_s = 120.0;
  const std::string clean_path = directory_ + "/long.bag";
  simulateToBag(scenario_, clean_path, "");
  const std::string bag_path = directory_ + "/glitches.bag";
  {
    rosbag::Bag in(clean_path, rosbag::bagmode::Read);
    rosbag::Bag out(bag_path, rosbag::bagmode::Write);
    int count = 0, injected = 0;
    for (const rosbag::MessageInstance& m : rosbag::View(in)) {
      auto joints = m.instantiate<sensor_msgs::JointState>();
      if (joints && ++count % 300 == 150 && injected < 20) {
        joints->position[static_cast<std::size_t>(injected++ % 2)] += 1e6;
        out.write(m.getTopic(), m.getTime(), *joints);
      } else {
        out.write(m.getTopic(), m.getTime(), m);
      }
    }
    ASSERT_EQ(injected, 20);
  }
  const BagRunResult clean = runBags({clean_path}, config_);
  const BagRunResult glitched = runBags({bag_path}, config_);
  EXPECT_EQ(glitched.pairs.size(), clean.pairs.size());
  std::cout << "pairs: clean " << clean.pairs.size() << ", glitched " << glitched.pairs.size()
            << "\n";
  ASSERT_EQ(glitched.counts.statistics.glitches.size(), 2u);
  EXPECT_EQ(glitched.counts.statistics.glitches.at("left_wheel"), 10u);
  EXPECT_EQ(glitched.counts.statistics.glitches.at("right_wheel"), 10u);
  EXPECT_EQ(clean.counts.statistics.glitches.size(), 0u);
  EXPECT_EQ(glitched.counts.bad_encoder_messages, 0u);
  EXPECT_EQ(glitched.counts.statistics.rejected.count("encoder glitch in the interval"), 0u);
  const std::string summary =
      formatBagRunSummary(glitched, glitched.counts, glitched.session->source(0).collectionNotes());
  EXPECT_NE(summary.find("skipped 10 encoder glitches on joint 'left_wheel'"), std::string::npos)
      << summary;
  // No glitch reaches the decoded history (a jump would be 500 turns).
  for (std::size_t k = 1; k < glitched.encoder_history.size(); ++k) {
    const Eigen::VectorXd step =
        glitched.encoder_history[k].values - glitched.encoder_history[k - 1].values;
    ASSERT_LT(step.cwiseAbs().maxCoeff(), 1000.0) << k;
  }
  auto clean_model = makeModel("diff_drive", config_.models);
  auto glitched_model = makeModel("diff_drive", config_.models);
  const ModelReport a = clean_model->fit(clean.pairs);
  const ModelReport b = glitched_model->fit(glitched.pairs);
  ASSERT_TRUE(a.converged);
  ASSERT_TRUE(b.converged);
  ASSERT_EQ(a.parameters.size(), b.parameters.size());
  for (std::size_t p = 0; p < a.parameters.size(); ++p) {
    EXPECT_LT(std::abs(a.parameters[p].value - b.parameters[p].value), a.parameters[p].sigma)
        << a.parameters[p].name;
    std::cout << a.parameters[p].name << ": clean " << a.parameters[p].value << ", glitched "
              << b.parameters[p].value << " ("
              << (b.parameters[p].value - a.parameters[p].value) / a.parameters[p].sigma
              << " sigma)\n";
  }
}

}  // namespace
}  // namespace odometry_calibration
