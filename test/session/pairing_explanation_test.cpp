// Too few pairs explained in the data's numbers: the leading rejection's key and the value the
// data asks for; advice about driving only when the driving is the cause.
#include <gtest/gtest.h>

#include "odometry_calibration/session/pairing_explanation.h"

namespace odometry_calibration {
namespace {

CollectorStatistics slowEncoders()
{
  CollectorStatistics statistics;
  statistics.encoder_messages = 230;
  statistics.scans = 240;
  statistics.keyframes = 107;
  statistics.rejected[kNoEncoderReadingReason] = 102;
  statistics.rejected[kEncoderGapReason] = 5;
  statistics.encoder_spacing_median_s = 0.26;
  statistics.encoder_spacings = 100;
  statistics.max_encoder_gap_s = 0.25;
  return statistics;
}

bool contains(const std::string& text, const std::string& part)
{
  return text.find(part) != std::string::npos;
}

TEST(PairingExplanation, NamesTheEncoderGapKeyTheSpacingAndTheValueToSet)
{
  CollectorOptions options;
  options.max_encoder_gap_s = 0.25;  // configured
  const std::string text = explainTooFewPairs(slowEncoders(), options, 0, 10);
  for (const char* part :
       {"only 0 pairs collected, 10 needed", "107 keyframe intervals rejected", "(102)", "(5)",
        "every 0.26 s (median)", "keyframes.max_encoder_gap_s = 0.25 s", "set it to at least 0.65"})
    EXPECT_TRUE(contains(text, part)) << part << " in: " << text;
  EXPECT_FALSE(contains(text, "drive")) << text;
  // The derived limit exceeded: the stream drops readings; nothing to set.
  options.max_encoder_gap_s = 0.0;
  CollectorStatistics derived = slowEncoders();
  derived.max_encoder_gap_s = 0.65;
  const std::string dropped = explainTooFewPairs(derived, options, 3, 10);
  EXPECT_TRUE(contains(dropped, "derived from that, 0.65 s")) << dropped;
  EXPECT_TRUE(contains(dropped, "drops readings")) << dropped;
  EXPECT_FALSE(contains(dropped, "drive ")) << dropped;
}

TEST(PairingExplanation, AdvisesDrivingOnlyWhenTheDrivingIsTheCause)
{
  CollectorOptions options;
  CollectorStatistics still;
  still.encoder_messages = 500;
  still.scans = 100;
  still.keyframes = 20;
  still.rejected["too little motion (keyframes.min_translation_m/min_rotation_rad)"] = 19;
  EXPECT_TRUE(contains(explainTooFewPairs(still, options, 0, 10), "barely moved"));
  CollectorStatistics short_drive;
  short_drive.encoder_messages = 100;
  short_drive.scans = 20;
  short_drive.keyframes = 4;
  const std::string text = explainTooFewPairs(short_drive, options, 3, 10);
  EXPECT_TRUE(contains(text, "4 keyframes from 20 scans and none rejected")) << text;
  EXPECT_TRUE(contains(text, "drive longer")) << text;
  CollectorStatistics silent;
  EXPECT_TRUE(contains(explainTooFewPairs(silent, options, 0, 10), "no encoder reading arrived"));
  CollectorStatistics matcher = slowEncoders();
  matcher.rejected.clear();
  matcher.rejected["keyframe match disagrees with consecutive matches"] = 50;
  const std::string failed = explainTooFewPairs(matcher, options, 2, 10);
  EXPECT_TRUE(contains(failed, "keyframe match disagrees with consecutive matches (50)")) << failed;
  EXPECT_FALSE(contains(failed, "drive")) << failed;
}

}  // namespace
}  // namespace odometry_calibration
