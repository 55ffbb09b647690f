#include "odometry_calibration/models/tricycle_observability.h"

#include <cmath>
#include <sstream>

namespace odometry_calibration {
namespace {

// Below these the data do not excite the parameters enough to trust them.
constexpr double kMinTravelM = 2.0;            // total distance driven by the sensor
constexpr double kMinTurnRad = 0.5;            // total heading change each way
constexpr double kMaxRelativeSigma = 0.05;     // sigma / |value| of scale-like parameters
constexpr double kMaxAbsoluteSigmaM = 0.05;    // sigma of lengths without a natural scale
constexpr double kMaxAbsoluteSigmaRad = 0.02;  // sigma of angles
constexpr double kMaxCorrelation = 0.995;

std::string formatNumber(double value)
{
  std::ostringstream stream;
  stream.precision(3);
  stream << value;
  return stream.str();
}

}  // namespace

std::vector<std::string> tricycleObservabilityWarnings(const std::vector<MotionPair>& pairs,
                                                       const TricycleCalibrationResult& result)
{
  std::vector<std::string> warnings;
  double travel_m = 0.0;
  double left_turn_rad = 0.0;
  double right_turn_rad = 0.0;
  for (const MotionPair& pair : pairs) {
    travel_m += std::hypot(pair.sensor_motion.x(), pair.sensor_motion.y());
    const double turn = pair.sensor_motion.theta();
    (turn > 0.0 ? left_turn_rad : right_turn_rad) += std::abs(turn);
  }
  if (travel_m < kMinTravelM) {
    warnings.push_back("too little motion: the sensor travelled only " + formatNumber(travel_m) +
                       " m; drive at least " + formatNumber(kMinTravelM) +
                       " m with turns both ways before trusting any parameter");
  }
  if (left_turn_rad < kMinTurnRad && right_turn_rad < kMinTurnRad) {
    warnings.push_back(
        "no turning: steering_scale, axis_length and sensor_y are unobservable from straight "
        "driving; drive curves in both directions");
  } else if (left_turn_rad < kMinTurnRad || right_turn_rad < kMinTurnRad) {
    warnings.push_back(std::string("turns ") + (left_turn_rad < kMinTurnRad ? "right" : "left") +
                       " only: steering_offset cannot be separated from steering_scale; drive "
                       "curves in the other direction too");
  }

  if (!result.covariance_available) {
    warnings.push_back(
        "parameter covariance unavailable (rank-deficient problem): at least one parameter is "
        "not determined by this motion; sigmas are not reported");
    return warnings;
  }
  for (std::size_t i = 0; i < result.estimates.size(); ++i) {
    const ParameterEstimate& estimate = result.estimates[i];
    bool poor = false;
    if (estimate.unit == "rad") {
      poor = estimate.sigma > kMaxAbsoluteSigmaRad;
    } else if (estimate.name == "sensor_x" || estimate.name == "sensor_y") {
      poor = estimate.sigma > kMaxAbsoluteSigmaM;
    } else {
      poor = estimate.sigma > kMaxRelativeSigma * std::abs(estimate.value);
    }
    if (poor) {
      warnings.push_back(estimate.name + " is poorly determined (sigma " +
                         formatNumber(estimate.sigma) + " " + estimate.unit +
                         "): record more varied motion (tight turns both ways, reversing)");
    }
  }
  for (int i = 0; i < 7; ++i) {
    for (int j = i + 1; j < 7; ++j) {
      const double denominator = std::sqrt(result.covariance(i, i) * result.covariance(j, j));
      if (denominator <= 0.0) {
        continue;
      }
      const double correlation = result.covariance(i, j) / denominator;
      if (std::abs(correlation) > kMaxCorrelation) {
        warnings.push_back(result.estimates[i].name + " and " + result.estimates[j].name +
                           " are almost indistinguishable (correlation " +
                           formatNumber(correlation) +
                           "): only their combination is determined by this motion");
      }
    }
  }
  return warnings;
}

}  // namespace odometry_calibration
