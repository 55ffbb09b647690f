#include "odometry_calibration/eval/trajectory_comparison.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <utility>

namespace odometry_calibration {

TrajectoryComparison compareTrajectories(const std::vector<MotionPair>& calibrated_pairs,
                                         const MotionModel& calibrated,
                                         const std::vector<MotionPair>& nominal_pairs,
                                         const MotionModel* nominal)
{
  // The nominal pairs by keyframe interval (rewindowing keeps the stamps as they are).
  std::map<std::pair<double, double>, const MotionPair*> nominal_by_interval;
  if (nominal) {
    for (const MotionPair& pair : nominal_pairs)
      nominal_by_interval[{pair.start_stamp_s, pair.end_stamp_s}] = &pair;
  }
  TrajectoryComparison result;
  for (const MotionPair& pair : calibrated_pairs) {
    const MotionPair* nominal_pair = nullptr;
    if (nominal) {
      const auto found = nominal_by_interval.find({pair.start_stamp_s, pair.end_stamp_s});
      if (found == nominal_by_interval.end())
        continue;
      nominal_pair = found->second;
    }
    const Pose2 predicted = calibrated.predict(pair.encoder_samples).mean;
    if (result.stamps_s.empty()) {
      result.stamps_s.push_back(pair.start_stamp_s);
      result.matched.emplace_back();
      result.calibrated.emplace_back();
      if (nominal)
        result.nominal.emplace_back();
    } else if (pair.start_stamp_s != result.stamps_s.back()) {
      ++result.gaps;
    }
    result.stamps_s.push_back(pair.end_stamp_s);
    result.matched.push_back(result.matched.back() * pair.sensor_motion);
    result.calibrated.push_back(result.calibrated.back() * predicted);
    result.calibrated_errors.push_back(between(pair.sensor_motion, predicted));
    if (nominal) {
      const Pose2 nominal_predicted = nominal->predict(nominal_pair->encoder_samples).mean;
      result.nominal.push_back(result.nominal.back() * nominal_predicted);
      result.nominal_errors.push_back(between(pair.sensor_motion, nominal_predicted));
    }
  }
  if (result.calibrated_errors.empty()) {
    throw std::invalid_argument(
        "no keyframe pair to compare the models on (none in common at the two time offsets)");
  }
  return result;
}

std::vector<double> translationErrors(const std::vector<Pose2>& errors)
{
  std::vector<double> lengths;
  lengths.reserve(errors.size());
  for (const Pose2& error : errors)
    lengths.push_back(std::hypot(error.x(), error.y()));
  return lengths;
}

std::vector<double> rotationErrors(const std::vector<Pose2>& errors)
{
  std::vector<double> angles;
  angles.reserve(errors.size());
  for (const Pose2& error : errors)
    angles.push_back(std::abs(error.theta()));
  return angles;
}

}  // namespace odometry_calibration
