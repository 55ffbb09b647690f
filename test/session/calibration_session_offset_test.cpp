// The session's pairing at the estimated time offset: a session configured 0.1 s off the truth
// pairs its recorded inputs again at the estimate in calibrate() and gives exactly the pairs,
// time offset and parameters of a fresh session configured at that estimate and fed the same
// messages; the record stays within its memory bound
// and a reset clears it. The next offset to pair at: the secant toward where the estimate agrees
// with the pairing offset.
#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "odometry_calibration/session/calibration_session.h"
#include "support/office_drive.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// The encoders' stamps are this much later than the scans' (the truth the estimate finds) [s].
constexpr double kEncoderDelayS = 0.1;

class SessionOffset : public ::testing::Test
{
protected:
  void SetUp() override
  {
    std::ifstream in(std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/diff_drive.yaml");
    config_text_.assign(std::istreambuf_iterator<char>(in), {});
    config_ = parseCalibrationConfig(config_text_, "diff_drive.yaml");
    config_.estimate_time_offset = true;
    config_.collector.time_offset_s = 0.0;  // 0.1 s off the truth
    options_.wall_clock = [this] { return clock_s_; };
  }

  std::unique_ptr<CalibrationSession> makeSession(double offset_s)
  {
    CalibrationConfig config = config_;
    config.collector.time_offset_s = offset_s;
    return std::make_unique<CalibrationSession>(config, config_text_, "diff_drive.yaml", options_);
  }

  /// The drive's messages in the order a bag of them is read, the encoders delayed.
  void feed(CalibrationSession& session)
  {
    const test::Recording& drive = test::officeDrive();
    std::vector<test::Recording::Message> messages = drive.inOrder();
    for (test::Recording::Message& message : messages) {
      if (message.joints)
        message.stamp_s += kEncoderDelayS;
    }
    std::stable_sort(messages.begin(), messages.end(),
                     [](const auto& a, const auto& b) { return a.stamp_s < b.stamp_s; });
    for (const test::Recording::Message& message : messages) {
      clock_s_ = message.stamp_s;
      if (message.joints) {
        const auto& positions = drive.joints[message.index].positions;
        session.addJointPositions(
            message.stamp_s, Eigen::Map<const Eigen::VectorXd>(positions.data(), positions.size()));
      } else {
        session.addScan(message.stamp_s, test::toScan(drive.scans[message.index]), "laser");
      }
    }
    session.flush();
  }

  std::string config_text_;
  CalibrationConfig config_;
  SessionOptions options_;
  double clock_s_ = 0.0;
};

void expectSamePairs(const std::vector<MotionPair>& a, const std::vector<MotionPair>& b)
{
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].start_stamp_s, b[i].start_stamp_s) << i;
    EXPECT_EQ(a[i].end_stamp_s, b[i].end_stamp_s) << i;
    EXPECT_EQ(a[i].sensor_motion.x(), b[i].sensor_motion.x()) << i;
    EXPECT_EQ(a[i].sensor_motion.y(), b[i].sensor_motion.y()) << i;
    EXPECT_EQ(a[i].sensor_motion.theta(), b[i].sensor_motion.theta()) << i;
    EXPECT_EQ(a[i].encoder_samples.size(), b[i].encoder_samples.size()) << i;
  }
}

TEST_F(SessionOffset, PairsAgainAtTheEstimateAsASessionConfiguredAtIt)
{
  auto off = makeSession(0.0);
  feed(*off);
  const std::size_t pairs_at_zero = off->pairs().size();
  const CalibrateOutcome outcome = off->calibrate({});
  ASSERT_TRUE(outcome.success) << outcome.message;
  const OffsetPairing& pairing = outcome.fit->offset_pairing;
  EXPECT_TRUE(pairing.paired_again) << pairing.text;
  EXPECT_NEAR(pairing.estimate_s, kEncoderDelayS, 0.01);
  EXPECT_NE(outcome.message.find("paired again at the estimated time offset"), std::string::npos)
      << outcome.message;
  EXPECT_EQ(off->timeOffset(), outcome.fit->job.time_offset_s);  // adopted: new pairs at it
  RecordProperty("pairs",
                 std::to_string(pairs_at_zero) + " -> " + std::to_string(outcome.pairs_collected));

  // A fresh session configured at the estimate, fed the same messages: the same pairs and fit.
  auto at_estimate = makeSession(pairing.estimate_s);
  feed(*at_estimate);
  expectSamePairs(off->pairs(), at_estimate->pairs());
  const CalibrateOutcome reference = at_estimate->calibrate({});
  ASSERT_TRUE(reference.success) << reference.message;
  EXPECT_FALSE(reference.fit->offset_pairing.paired_again);
  EXPECT_EQ(outcome.pairs_collected, reference.pairs_collected);
  EXPECT_EQ(outcome.fit->job.time_offset_s, reference.fit->job.time_offset_s);
  const auto& parameters = outcome.fit->job.report.parameters;
  ASSERT_EQ(parameters.size(), reference.fit->job.report.parameters.size());
  for (std::size_t p = 0; p < parameters.size(); ++p)
    EXPECT_EQ(parameters[p].value, reference.fit->job.report.parameters[p].value) << p;
}

TEST_F(SessionOffset, TheRepairedPairsAreTheSessionsAndThoseOfAFreshSession)
{
  options_.adopt_fits = false;  // as calibrate_bag
  auto off = makeSession(0.0);
  feed(*off);
  const CalibrateOutcome outcome = off->calibrate({});
  ASSERT_TRUE(outcome.fit.has_value()) << outcome.message;
  ASSERT_TRUE(outcome.fit->offset_pairing.paired_again);
  auto at_estimate = makeSession(outcome.fit->offset_pairing.estimate_s);
  feed(*at_estimate);
  expectSamePairs(off->pairs(), at_estimate->pairs());
  EXPECT_EQ(off->encoderHistory().size(), at_estimate->encoderHistory().size());
  EXPECT_EQ(off->counts().statistics.keyframes, at_estimate->counts().statistics.keyframes);
}

TEST_F(SessionOffset, TheRecordStaysWithinItsBoundAndAResetClearsIt)
{
  auto session = makeSession(0.0);
  feed(*session);
  const auto [memory_bytes, spilled_bytes] = session->inputRecordBytes();
  const test::Recording& drive = test::officeDrive();
  const double hours = (drive.scans.back().stamp_s - drive.scans.front().stamp_s) / 3600.0;
  // 100 MB per hour of 10 Hz 720-ray data: per scan of this drive, scaled to its rays and rate.
  const double rays = static_cast<double>(drive.scans.front().ranges.size());
  const double scans_per_hour = static_cast<double>(drive.scans.size()) / hours;
  const double bound_bytes = 100e6 * (scans_per_hour / 36000.0) * (rays / 720.0) * hours;
  EXPECT_LT(static_cast<double>(memory_bytes), bound_bytes);
  EXPECT_GT(spilled_bytes, 0u);
  RecordProperty("memory_bytes", std::to_string(memory_bytes));
  RecordProperty("spilled_bytes", std::to_string(spilled_bytes));
  EXPECT_TRUE(session->reset().first);
  EXPECT_EQ(session->inputRecordBytes().second, 0u);
  EXPECT_LT(session->inputRecordBytes().first, (1u << 20) + 4096u);  // the write buffer at most
}

TEST_F(SessionOffset, WithoutTheEstimateNothingIsRecorded)
{
  config_.estimate_time_offset = false;
  auto session = makeSession(0.0);
  feed(*session);
  EXPECT_EQ(session->inputRecordBytes().first, 0u);
  EXPECT_EQ(session->calibrate({}).fit->offset_pairing.text, "");
}

// An estimate that leans toward the pairing offset by 0.4 (f(t) = 0.6 + 0.003 + 0.4 (t - 0.6)):
// the secant through two pairings lands on its fixed point 0.605 s at once, where the plain
// iteration would pair at the last estimate 0.6074 s; a lean the secant cannot trust (one pushing
// away, or two pairings at one offset) gives the last estimate, and so does no lean at all.
TEST(NextPairingOffset, TheSecantFindsWhereTheEstimateAgreesWithThePairingOffset)
{
  auto lean = [](double t) { return 0.603 + 0.4 * (t - 0.6); };
  const OffsetRound first{0.62, lean(0.62)};
  const OffsetRound second{first.estimate_s, lean(first.estimate_s)};
  EXPECT_NEAR(nextPairingOffset_s(first, second), 0.605, 1e-12);
  EXPECT_NEAR(lean(nextPairingOffset_s(first, second)), 0.605, 1e-12);

  const OffsetRound flat_first{0.0, 0.61};
  const OffsetRound flat_second{0.61, 0.61};  // f does not depend on t: slope of g = -1
  EXPECT_NEAR(nextPairingOffset_s(flat_first, flat_second), 0.61, 1e-12);

  const OffsetRound away_first{0.60, 0.605};
  const OffsetRound away_second{0.605, 0.6125};  // f leans away: slope of g = +0.5
  EXPECT_DOUBLE_EQ(nextPairingOffset_s(away_first, away_second), 0.6125);
  EXPECT_DOUBLE_EQ(nextPairingOffset_s(away_second, away_second), 0.6125);  // t0 = t1
}

}  // namespace
}  // namespace odometry_calibration
