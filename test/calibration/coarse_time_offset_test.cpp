// The coarse time-offset search by heading correlation, alone and as the job uses it: an offset
// of more than a second found with the default range, the fine search placed near it, the exit
// status when the truth lies outside the range, and a drive without turns answered honestly.
#include <map>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/calibration_job.h"
#include "odometry_calibration/calibration/coarse_time_offset.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

sim::PairGeneratorOptions robot()
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.T_base_sensor = Pose2(0.145, 0.02, 0.03);
  options.duration_s = 90.0;
  options.interval_s = 0.5;
  return options;
}

/// The pairs' encoder samples once each, in time order, stamped `shift_s` early: encoder values
/// then belong at scan time + (-shift_s).
std::vector<EncoderSample> shiftedHistory(const std::vector<MotionPair>& pairs, double shift_s)
{
  std::map<double, EncoderSample> by_stamp;
  for (const MotionPair& pair : pairs) {
    for (const EncoderSample& sample : pair.encoder_samples)
      by_stamp.emplace(sample.stamp_s, sample);
  }
  std::vector<EncoderSample> history;
  for (auto [stamp_s, sample] : by_stamp) {
    sample.stamp_s = stamp_s - shift_s;
    history.push_back(sample);
  }
  return history;
}

CalibrationConfig config(const JointLayout& joints)
{
  CalibrationConfig c;  // the defaults: estimate_time_offset, search [-2, 2] s
  c.model = "diff_drive";
  c.prior_model = "diff_drive";
  c.models.joints = joints;
  c.models.diff_drive.initial_left_radius_m = 0.077;
  c.models.diff_drive.initial_right_radius_m = 0.077;
  c.models.diff_drive.initial_separation_m = 0.35;  // 9 % off: the turns are scaled alike
  c.models.diff_drive.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  return c;
}

TEST(CoarseTimeOffset, FindsAnOffsetOfMoreThanASecondByDefault)
{
  const sim::GeneratedPairs data = sim::generatePairs(robot());
  const std::vector<EncoderSample> history = shiftedHistory(data.pairs, 1.2);  // tau = -1.2 s
  const CalibrationConfig c = config(data.joints);
  ASSERT_TRUE(c.estimate_time_offset);

  const CoarseTimeOffset coarse =
      coarseTimeOffset(data.pairs, history, priorPredictor(c), CoarseTimeOffsetOptions());
  ASSERT_TRUE(coarse.found) << coarse.problem;
  EXPECT_NEAR(coarse.offset_s, -1.2, 0.021);
  EXPECT_GT(coarse.correlation, 0.95);
  EXPECT_FALSE(coarse.at_boundary);

  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const CalibrationJobResult job = runCalibrationJob(c, data.pairs, history, options);
  ASSERT_TRUE(job.coarse_time_offset && job.time_offset);
  EXPECT_NEAR(job.time_offset_s, -1.2, 0.005);
  // The fine search refitted only near the coarse peak: 0.4 s of the 4 s range.
  EXPECT_LE(job.time_offset->curve.size(), 21u);
  EXPECT_NEAR(job.report.parameters[2].value, 0.32, 0.003);  // the separation
  EXPECT_EQ(calibrationExitStatus(job), 0);
}

TEST(CoarseTimeOffset, AnOffsetBeyondTheRangeExitsFive)
{
  const sim::GeneratedPairs data = sim::generatePairs(robot());
  const std::vector<EncoderSample> history = shiftedHistory(data.pairs, 1.2);
  CalibrationConfig c = config(data.joints);
  c.time_offset_search_min_s = -1.0;
  c.time_offset_search_max_s = 1.0;
  CalibrationJobOptions options;
  options.compare_trajectories = false;
  const CalibrationJobResult job = runCalibrationJob(c, data.pairs, history, options);
  ASSERT_TRUE(job.time_offset);
  EXPECT_TRUE(job.time_offset->at_boundary);
  EXPECT_NEAR(job.time_offset_s, -1.0, 1e-9);
  EXPECT_EQ(job.time_offset_warnings, 1u);
  EXPECT_EQ(calibrationExitStatus(job), 5);
  // The report alone (as several sources' fits are judged) counts it as any warning.
  EXPECT_EQ(calibrationExitStatus(job.report), 4);
}

TEST(CoarseTimeOffset, ADriveWithoutTurnsFindsNothingAndSaysWhy)
{
  sim::PairGeneratorOptions straight = robot();
  straight.duration_s = 60.0;
  straight.motion.type = "scripted";
  for (int leg = 0; leg < 6; ++leg) {
    sim::ScriptedMotion motion;
    motion.duration_s = 5.0;
    motion.twist.vx_mps = leg % 2 == 0 ? 0.5 : -0.5;
    straight.motion.script.push_back(motion);
  }
  const sim::GeneratedPairs data = sim::generatePairs(straight);
  const CoarseTimeOffset coarse =
      coarseTimeOffset(data.pairs, shiftedHistory(data.pairs, 0.0),
                       priorPredictor(config(data.joints)), CoarseTimeOffsetOptions());
  EXPECT_FALSE(coarse.found);
  EXPECT_NE(coarse.problem.find("barely turns"), std::string::npos) << coarse.problem;
  EXPECT_THROW(coarseTimeOffset(data.pairs, {}, priorPredictor(config(data.joints)),
                                CoarseTimeOffsetOptions{1.0, -1.0, 0.02}),
               std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
