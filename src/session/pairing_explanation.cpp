#include "odometry_calibration/session/pairing_explanation.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <utility>
#include <vector>

namespace odometry_calibration {
namespace {

/// The rejection reasons, most frequent first.
std::vector<std::pair<std::string, std::size_t>> byCount(const CollectorStatistics& statistics)
{
  std::vector<std::pair<std::string, std::size_t>> reasons(statistics.rejected.begin(),
                                                           statistics.rejected.end());
  std::stable_sort(reasons.begin(), reasons.end(),
                   [](const auto& a, const auto& b) { return a.second > b.second; });
  return reasons;
}

/// The encoder gap limit against the readings' spacing, and what to set.
std::string encoderGapCause(const CollectorStatistics& statistics, const CollectorOptions& options)
{
  char text[400];
  const double spacing_s = statistics.encoder_spacing_median_s;
  if (!(std::isfinite(spacing_s) && statistics.encoder_spacings > 0))
    return " The encoder readings are too few to measure their spacing.";
  if (options.max_encoder_gap_s > 0.0) {
    const double suggested_s = roundedUpForAdvice_s(derivedEncoderGap_s(spacing_s));
    std::snprintf(text, sizeof(text),
                  " The encoder readings arrive every %.3g s (median); keyframes need one "
                  "within keyframes.max_encoder_gap_s = %.3g s (configured) of each keyframe: "
                  "set it to at least %.2f, or remove it (its default follows the readings).",
                  spacing_s, options.max_encoder_gap_s, suggested_s);
  } else {
    std::snprintf(text, sizeof(text),
                  " The encoder readings arrive every %.3g s (median); the limit derived from "
                  "that, %.3g s (keyframes.max_encoder_gap_s), is exceeded: the encoder stream "
                  "drops readings or stops while the sensor goes on.",
                  spacing_s, statistics.max_encoder_gap_s);
  }
  return text;
}

bool isEncoderReason(const std::string& reason)
{
  return reason == kNoEncoderReadingReason || reason == kEncoderGapReason;
}

}  // namespace

std::string explainTooFewPairs(const CollectorStatistics& statistics,
                               const CollectorOptions& options, std::size_t pairs,
                               std::size_t needed)
{
  std::string text =
      "only " + std::to_string(pairs) + " pairs collected, " + std::to_string(needed) + " needed";
  if (statistics.encoder_messages == 0)
    return text + ": no encoder reading arrived.";
  if (statistics.scans == 0 && statistics.keyframes == 0)
    return text + ": no scan or sensor pose arrived.";
  const auto reasons = byCount(statistics);
  if (reasons.empty()) {
    char line[200];
    std::snprintf(line, sizeof(line),
                  ": %zu keyframes from %zu scans and none rejected: the drive is too short for "
                  "keyframes.interval_s = %.3g s; drive longer, straight and turning both ways.",
                  statistics.keyframes, statistics.scans, options.keyframe_interval_s);
    return text + line;
  }
  std::size_t rejected = 0;
  for (const auto& reason : reasons)
    rejected += reason.second;
  text += "; " + std::to_string(rejected) + " keyframe intervals rejected:";
  for (std::size_t i = 0; i < reasons.size() && i < 3; ++i)
    text += (i ? "; " : " ") + reasons[i].first + " (" + std::to_string(reasons[i].second) + ")";
  text += ".";
  const std::string& leading = reasons.front().first;
  if (isEncoderReason(leading))
    text += encoderGapCause(statistics, options);
  else if (leading.rfind("too little motion", 0) == 0)
    text +=
        " The robot barely moved between keyframes: drive more, straight and turning both "
        "ways.";
  return text;
}

}  // namespace odometry_calibration
