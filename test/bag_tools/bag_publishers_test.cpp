// A bag in which two nodes publish the wheel joints on /joint_states (issue 32): the driver's
// readings and, interleaved, a joint_state_publisher's zeros, each connection with its own
// callerid, as `rosbag record` writes them. runBags refuses it naming both nodes; with
// joint_state_publisher set it calibrates as on the clean bag. The same for two nodes publishing
// /scan (the driver and a stale replay) and ego_motion.publisher.
#include <deque>
#include <filesystem>

#include <gtest/gtest.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {
namespace {

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// A connection header as a recorder writes it: the message's type and the publishing node.
template <typename Message>
boost::shared_ptr<ros::M_string> publishedBy(const std::string& callerid)
{
  auto header = boost::make_shared<ros::M_string>();
  (*header)["type"] = ros::message_traits::datatype<Message>();
  (*header)["md5sum"] = ros::message_traits::md5sum<Message>();
  (*header)["message_definition"] = ros::message_traits::definition<Message>();
  (*header)["callerid"] = callerid;
  return header;
}

/// `clean`'s joint states and scans again, from '/driver' and '/laser_driver'; with
/// `intruder`, each joint state followed by one of zeros from '/joint_state_publisher'; with
/// `scan_intruder`, each scan followed by the one of ten scans earlier, stamped now, from
/// '/laser_replay' (a stale laser beside the driver).
void rewrite(const std::string& clean, const std::string& path, bool intruder,
             bool scan_intruder = false)
{
  rosbag::Bag in(clean, rosbag::bagmode::Read);
  rosbag::Bag out(path, rosbag::bagmode::Write);
  std::deque<sensor_msgs::LaserScan> earlier;
  for (const rosbag::MessageInstance& message : rosbag::View(in)) {
    if (const auto joints = message.instantiate<sensor_msgs::JointState>()) {
      out.write(message.getTopic(), message.getTime(), *joints,
                publishedBy<sensor_msgs::JointState>("/driver"));
      if (!intruder)
        continue;
      sensor_msgs::JointState zeros = *joints;
      zeros.header.stamp += ros::Duration(1e-4);
      std::fill(zeros.position.begin(), zeros.position.end(), 0.0);
      out.write(message.getTopic(), message.getTime() + ros::Duration(1e-4), zeros,
                publishedBy<sensor_msgs::JointState>("/joint_state_publisher"));
    } else if (const auto scan = message.instantiate<sensor_msgs::LaserScan>()) {
      out.write(message.getTopic(), message.getTime(), *scan,
                publishedBy<sensor_msgs::LaserScan>("/laser_driver"));
      if (!scan_intruder)
        continue;
      earlier.push_back(*scan);
      sensor_msgs::LaserScan stale = earlier.front();
      if (earlier.size() > 10)
        earlier.pop_front();
      stale.header.stamp = scan->header.stamp + ros::Duration(1e-3);
      out.write(message.getTopic(), message.getTime() + ros::Duration(1e-3), stale,
                publishedBy<sensor_msgs::LaserScan>("/laser_replay"));
    }
  }
}

class BagPublishers : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/bag_publishers_test.XXXXXX";
    directory_ = mkdtemp(pattern);
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 40.0;
    simulateToBag(scenario, directory_ + "/sim.bag", "");
    rewrite(directory_ + "/sim.bag", clean_ = directory_ + "/clean.bag", false);
    rewrite(directory_ + "/sim.bag", two_ = directory_ + "/two_publishers.bag", true);
    rewrite(directory_ + "/sim.bag", two_lasers_ = directory_ + "/two_laser_publishers.bag", false,
            true);
    config_ = loadCalibrationConfig(kConfig + "/diff_drive.yaml");
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }

  std::string directory_, clean_, two_, two_lasers_;
  CalibrationConfig config_;
};

TEST_F(BagPublishers, TwoJointStatePublishersAreRefusedNamingBoth)
{
  try {
    runBags({two_}, config_);
    FAIL() << "a bag with two JointState publishers was accepted";
  } catch (const std::runtime_error& error) {
    const std::string what = error.what();
    for (const char* part : {"'/driver'", "'/joint_state_publisher'", "joint_state_publisher:"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " in: " << what;
  }
}

TEST_F(BagPublishers, TheChosenPublisherCalibratesWithinATenthOfAPercentOfTheCleanBag)
{
  const BagRunResult clean = runBags({clean_}, config_);
  config_.joint_state_publisher = "/driver";
  const BagRunResult chosen = runBags({two_}, config_);
  EXPECT_EQ(chosen.counts.ignored_encoder_messages, clean.counts.encoder_messages);
  EXPECT_EQ(chosen.counts.ignored_encoder_publisher, "/joint_state_publisher");
  EXPECT_EQ(chosen.pairs.size(), clean.pairs.size());
  const auto notes = chosen.session->source(0).collectionNotes();
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.front().find("ignored 2001 JointState messages from '/joint_state_publisher'"),
            std::string::npos)
      << notes.front();
  const ModelReport expected = makeModel("diff_drive", config_.models)->fit(clean.pairs);
  const ModelReport fitted = makeModel("diff_drive", config_.models)->fit(chosen.pairs);
  ASSERT_TRUE(expected.converged && fitted.converged);
  for (std::size_t p = 0; p < 3; ++p) {  // r_L, r_R, b
    EXPECT_NEAR(fitted.parameters[p].value, expected.parameters[p].value,
                1e-3 * expected.parameters[p].value);
  }
  EXPECT_NEAR(fitted.parameters[0].value, 0.0765, 0.0765 * 0.005);  // and the truth
}

TEST_F(BagPublishers, AChosenPublisherThatNeverPublishedIsNamed)
{
  config_.joint_state_publisher = "/base_driver";
  try {
    runBags({two_}, config_);
    FAIL() << "a joint_state_publisher absent from the bag was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("'/base_driver' published no JointState"),
              std::string::npos)
        << error.what();
  }
}

TEST_F(BagPublishers, TwoScanPublishersAreRefusedNamingBoth)
{
  try {
    runBags({two_lasers_}, config_);
    FAIL() << "a bag with two LaserScan publishers was accepted";
  } catch (const std::runtime_error& error) {
    const std::string what = error.what();
    for (const char* part : {"'/laser_driver'", "'/laser_replay'", "ego_motion.publisher:"})
      EXPECT_NE(what.find(part), std::string::npos) << part << " in: " << what;
  }
}

TEST_F(BagPublishers, TheChosenScanPublisherCalibratesWithinATenthOfAPercentOfTheCleanBag)
{
  const BagRunResult clean = runBags({clean_}, config_);
  config_.ego_motion_publisher = "/laser_driver";
  const BagRunResult chosen = runBags({two_lasers_}, config_);
  EXPECT_EQ(chosen.counts.ignored_ego_messages, clean.counts.ego_messages);
  EXPECT_EQ(chosen.counts.ignored_ego_publisher, "/laser_replay");
  EXPECT_EQ(chosen.counts.ego_publisher, "/laser_driver");
  EXPECT_EQ(chosen.counts.ignored_encoder_messages, 0u);
  EXPECT_EQ(chosen.pairs.size(), clean.pairs.size());
  const auto notes = chosen.session->source(0).collectionNotes();
  ASSERT_FALSE(notes.empty());
  EXPECT_NE(notes.front().find("ignored " + std::to_string(clean.counts.ego_messages) +
                               " LaserScan messages from '/laser_replay' (ego_motion.publisher: "
                               "'/laser_driver')"),
            std::string::npos)
      << notes.front();
  const ModelReport expected = makeModel("diff_drive", config_.models)->fit(clean.pairs);
  const ModelReport fitted = makeModel("diff_drive", config_.models)->fit(chosen.pairs);
  ASSERT_TRUE(expected.converged && fitted.converged);
  for (std::size_t p = 0; p < 3; ++p) {  // r_L, r_R, b
    EXPECT_NEAR(fitted.parameters[p].value, expected.parameters[p].value,
                1e-3 * expected.parameters[p].value);
  }
  // A chosen laser that never published is named.
  config_.ego_motion_publisher = "/front_laser";
  try {
    runBags({two_lasers_}, config_);
    FAIL() << "an ego_motion.publisher absent from the bag was accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what())
                  .find("ego_motion.publisher '/front_laser' published no "
                        "LaserScan on '/scan'"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace odometry_calibration
