#include "odometry_calibration/calibration/saved_calibration_score.h"

#include <map>
#include <stdexcept>

#include <gtest/gtest.h>

#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/factory/model_factory.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

sim::GeneratedPairs simulatedPairs()
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.T_base_sensor = Pose2(0.145, 0.02, 0.03);
  options.duration_s = 60.0;
  options.interval_s = 0.5;
  return sim::generatePairs(options);
}

CalibrationConfig nominalConfig(const JointLayout& joints)
{
  CalibrationConfig config;
  config.prior_model = "diff_drive";
  config.models.joints = joints;
  config.models.diff_drive.initial_left_radius_m = 0.077;
  config.models.diff_drive.initial_right_radius_m = 0.077;
  config.models.diff_drive.initial_separation_m = 0.33;
  config.models.diff_drive.initial_T_base_sensor = Pose2(0.1, 0.0, 0.0);
  return config;
}

TEST(SavedCalibrationScore, JointsMustBeTheCalibrations)
{
  EXPECT_NO_THROW(requireCalibrationJoints({"l", "r"}, {"l", "r"}, "the bag"));
  EXPECT_NO_THROW(requireCalibrationJoints({}, {"a", "b", "c"}, "the bag"));  // not recorded
  try {
    requireCalibrationJoints({"l", "r"}, {"r", "l"}, "the bag x.bag");
    FAIL() << "swapped joints accepted";
  } catch (const std::runtime_error& error) {
    EXPECT_STREQ(
        error.what(),
        "the bag x.bag carries the joints (r, l) but the calibration was made with (l, r)");
  }
}

TEST(SavedCalibrationScore, SavedModelThenNominalWithoutRefitting)
{
  const sim::GeneratedPairs data = simulatedPairs();
  const CalibrationConfig config = nominalConfig(data.joints);
  CalibrationResult saved;
  auto model = makeModel("diff_drive", config.models);
  const std::vector<MotionPair> training(data.pairs.begin(), data.pairs.begin() + 60);
  const std::vector<MotionPair> fresh(data.pairs.begin() + 60, data.pairs.end());
  model->fit(training);
  saved.model = std::move(model);
  const std::string before = saved.model->toYaml();

  const std::vector<ModelScore> scores = scoreSavedCalibration(config, saved, fresh, {});
  ASSERT_EQ(scores.size(), 2u);
  EXPECT_EQ(scores[0].model, "diff_drive");
  EXPECT_FALSE(scores[0].fitted);
  EXPECT_EQ(scores[1].model, "nominal");
  EXPECT_EQ(scores[0].test_pairs, fresh.size());
  EXPECT_EQ(saved.model->toYaml(), before);  // not refitted
  EXPECT_DOUBLE_EQ(scores[0].ate_m, scoreModel(*saved.model, fresh).ate_m);
  // The calibration carries over to the unseen pairs; the nominal robot does much worse.
  EXPECT_GT(scores[1].rmse_xytheta(1), 3.0 * scores[0].rmse_xytheta(1));

  // Too few pairs, or pairs without the model's joints: said, not crashed.
  EXPECT_THROW(scoreSavedCalibration(config, saved, {fresh[0]}, {}), std::runtime_error);
  std::vector<MotionPair> one_joint(fresh.begin(), fresh.begin() + 3);
  for (MotionPair& pair : one_joint) {
    for (EncoderSample& sample : pair.encoder_samples)
      sample.values.conservativeResize(1);
  }
  try {
    scoreSavedCalibration(config, saved, one_joint, {});
    FAIL() << "pairs without the right wheel were scored";
  } catch (const std::runtime_error& error) {
    EXPECT_NE(std::string(error.what()).find("does not fit the saved calibration"),
              std::string::npos)
        << error.what();
  }
  // No prior model: the saved row alone.
  CalibrationConfig none = config;
  none.prior_model = "none";
  EXPECT_EQ(scoreSavedCalibration(none, saved, fresh, {}).size(), 1u);
}

TEST(SavedCalibrationScore, NominalAtTimeOffsetZeroWhenTheHistoryAllows)
{
  const sim::GeneratedPairs data = simulatedPairs();
  std::map<double, EncoderSample> by_stamp;
  for (const MotionPair& pair : data.pairs)
    for (const EncoderSample& sample : pair.encoder_samples)
      by_stamp.emplace(sample.stamp_s, sample);
  std::vector<EncoderSample> history;
  for (const auto& entry : by_stamp)
    history.push_back(entry.second);
  const CalibrationConfig config = nominalConfig(data.joints);
  CalibrationResult saved;
  saved.model = makeModel("diff_drive", config.models);  // start values: the same as nominal
  saved.time_offset_s = 0.1;
  const std::vector<MotionPair> late = rewindowPairs(data.pairs, history, 0.1);
  const std::vector<ModelScore> scores = scoreSavedCalibration(config, saved, late, history);
  ASSERT_EQ(scores.size(), 2u);
  const auto nominal = makeModel("diff_drive", config.models);
  EXPECT_DOUBLE_EQ(scores[1].ate_m, scoreModel(*nominal, rewindowPairs(late, history, 0.0)).ate_m);
  EXPECT_DOUBLE_EQ(scores[0].ate_m, scoreModel(*nominal, late).ate_m);
}

}  // namespace
}  // namespace odometry_calibration
