#include <filesystem>
#include <fstream>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/data/pairs_csv.h"
#include "support/file_size_limit.h"

namespace odometry_calibration {
namespace {

JointLayout joints()
{
  return {{"steering", "traction"}, {EncoderKind::kAbsolute, EncoderKind::kIncremental}};
}

MotionPair pair(double t)
{
  MotionPair p;
  p.start_stamp_s = 1700000000.0 + t;
  p.end_stamp_s = p.start_stamp_s + 0.5;
  p.sensor_motion = Pose2(0.1 + t, -0.02, 0.0312345678901234);
  p.covariance << 1e-4, 2e-6, 3e-7, 2e-6, 5e-4, -1e-7, 3e-7, -1e-7, 2e-5;
  for (int k = 0; k < 3; ++k) {
    p.encoder_samples.push_back(
        {p.start_stamp_s + 0.25 * k, Eigen::Vector2d(-36 + k, 1e6 + 4987.0 * k)});
  }
  return p;
}

class PairsCsv : public ::testing::Test
{
protected:
  void SetUp() override
  {
    char pattern[] = "/tmp/pairs_csv_test.XXXXXX";
    directory_ = mkdtemp(pattern);
  }
  void TearDown() override { std::filesystem::remove_all(directory_); }
  std::string directory_;
};

TEST_F(PairsCsv, RoundTripIsExact)
{
  const std::string path = directory_ + "/pairs.csv";
  writePairsCsv(path, {joints(), {pair(0.0), pair(0.5)}});
  const PairsFile file = readPairsCsv(path);
  EXPECT_EQ(file.joints.names, joints().names);
  EXPECT_EQ(file.joints.kinds, joints().kinds);
  ASSERT_EQ(file.pairs.size(), 2u);
  const MotionPair expected = pair(0.5);
  EXPECT_EQ(file.pairs[1].start_stamp_s, expected.start_stamp_s);
  EXPECT_EQ(file.pairs[1].sensor_motion.theta(), expected.sensor_motion.theta());
  EXPECT_EQ(file.pairs[1].covariance, expected.covariance);
  ASSERT_EQ(file.pairs[1].encoder_samples.size(), 3u);
  EXPECT_EQ(file.pairs[1].encoder_samples[2].values, expected.encoder_samples[2].values);
  EXPECT_EQ(file.pairs[1].encoder_samples[2].stamp_s, expected.encoder_samples[2].stamp_s);
}

TEST_F(PairsCsv, AppenderContinuesAFileAndSurvivesACutOffRow)
{
  const std::string path = directory_ + "/live.csv";
  {
    PairsCsvAppender appender(path, joints());
    EXPECT_TRUE(appender.existing().empty());
    appender.append(pair(0.0));
    appender.append(pair(0.5));
  }
  // A crash in the middle of a row.
  std::ofstream(path, std::ios::app) << "1700000001,1700000001.5,0.1,0.2";
  PairsCsvAppender resumed(path, joints());
  EXPECT_TRUE(resumed.dropped_partial_line());
  ASSERT_EQ(resumed.existing().size(), 2u);
  EXPECT_EQ(resumed.existing()[1].sensor_motion.x(), pair(0.5).sensor_motion.x());
  resumed.append(pair(1.0));
  EXPECT_EQ(readPairsCsv(path).pairs.size(), 3u);

  JointLayout other = joints();
  other.names[1] = "left_wheel";
  EXPECT_THROW(PairsCsvAppender(path, other), std::runtime_error);
}

TEST_F(PairsCsv, ErrorsNameTheLine)
{
  auto message = [](const std::string& text) -> std::string {
    std::istringstream input(text);
    try {
      parsePairsCsv(input, "p.csv");
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  const std::string header = pairsCsvHeader(joints());
  EXPECT_NE(message("1,2,3\n").find("joints"), std::string::npos);
  EXPECT_NE(message("").find("p.csv: the file is empty"), std::string::npos);
  EXPECT_NE(message(header + "1,2,3\n").find("p.csv:4: expected 12"), std::string::npos);
  std::string row = pairsCsvRow(pair(0.0));
  EXPECT_EQ(message(header + row), "");
  std::string bad_number = row;
  bad_number.replace(0, bad_number.find(','), "soon");
  EXPECT_NE(message(header + bad_number).find("field 1"), std::string::npos);
  std::string short_sample = row;
  short_sample.replace(short_sample.rfind(' '), std::string::npos, "\n");
  EXPECT_NE(message(header + short_sample).find("samples"), std::string::npos);
  EXPECT_NE(message("# joints: a:sideways\n").find("a:sideways"), std::string::npos);
  // Values no pair has (issue 32): a motion of 1e10 m, a covariance that is not positive
  // definite, a joint value of 1e300.
  auto replaced = [&](std::size_t field, const std::string& value) {
    std::string changed = row;
    std::size_t begin = 0;
    for (std::size_t i = 0; i < field; ++i)
      begin = changed.find(',', begin) + 1;
    changed.replace(begin, changed.find(',', begin) - begin, value);
    return header + changed;
  };
  EXPECT_NE(message(replaced(2, "1e10")).find("p.csv:4: the sensor motion"), std::string::npos);
  EXPECT_NE(message(replaced(5, "-1")).find("not positive definite"), std::string::npos);
  EXPECT_NE(message(replaced(6, "1e3")).find("not positive definite"), std::string::npos);
  std::string huge_joint = row;
  huge_joint.replace(huge_joint.rfind(' ') + 1, std::string::npos, "1e300\n");
  EXPECT_NE(message(header + huge_joint).find("a joint value beyond 1e15"), std::string::npos)
      << message(header + huge_joint);
}

TEST_F(PairsCsv, SeveralFilesMustShareTheirJoints)
{
  const std::string a = directory_ + "/a.csv", b = directory_ + "/b.csv", c = directory_ + "/c.csv";
  writePairsCsv(a, {joints(), {pair(0.0), pair(0.5)}});
  writePairsCsv(b, {joints(), {pair(1.0)}});
  writePairsCsv(c, {{{"left", "right"}, {EncoderKind::kIncremental, EncoderKind::kIncremental}},
                    {pair(2.0)}});
  const PairsFile all = readPairsCsvFiles({a, b});
  EXPECT_EQ(all.joints.names, joints().names);
  ASSERT_EQ(all.pairs.size(), 3u);
  EXPECT_EQ(all.pairs[2].start_stamp_s, pair(1.0).start_stamp_s);
  EXPECT_TRUE(readPairsCsvFiles({}).pairs.empty());
  try {
    readPairsCsvFiles({a, c});
    FAIL() << "files with other joints were accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_EQ(std::string(error.what()), "'" + c + "' has other joints than the first file");
  }

  const TrainTestPairs pairs = readTrainTestPairsCsv({a}, {b});
  EXPECT_EQ(pairs.training.pairs.size(), 2u);
  EXPECT_EQ(pairs.testing.pairs.size(), 1u);
  try {
    readTrainTestPairsCsv({a, b}, {c});
    FAIL() << "test pairs with other joints were accepted";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "the test pairs have other joints than the training pairs");
  }
}
TEST_F(PairsCsv, AFailedAppendLeavesNoHalfRowAndCanBeRetried)
{
  const std::string path = directory_ + "/live.csv";
  PairsCsvAppender appender(path, joints());
  appender.append(pair(0.0));
  const auto size = std::filesystem::file_size(path);
  {
    // The disk fills up in the middle of the next row.
    const test::FileSizeLimit full_disk(size + 20);
    EXPECT_THROW(appender.append(pair(0.5)), std::runtime_error);
    EXPECT_THROW(appender.append(pair(0.5)), std::runtime_error);
  }
  EXPECT_EQ(std::filesystem::file_size(path), size);  // cut back: no half row
  appender.append(pair(0.5));                         // room again: the same pair goes in
  const PairsFile file = readPairsCsv(path);
  ASSERT_EQ(file.pairs.size(), 2u);
  EXPECT_EQ(file.pairs[1].start_stamp_s, pair(0.5).start_stamp_s);
}

}  // namespace
}  // namespace odometry_calibration
