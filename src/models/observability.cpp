#include "odometry_calibration/models/observability.h"

#include <algorithm>
#include <cmath>

#include "odometry_calibration/common/number_text.h"

namespace odometry_calibration {
namespace {

// Below these the data do not excite the parameters enough to trust them.
constexpr double kMinTravelM = 2.0;            // total distance driven by the sensor
constexpr double kMinTurnRad = 0.5;            // total heading change each way
constexpr double kMaxRelativeSigma = 0.05;     // sigma / |value| of scale-like parameters
constexpr double kMaxAbsoluteSigmaM = 0.05;    // sigma of lengths without a natural scale
constexpr double kMaxAbsoluteSigmaRad = 0.02;  // sigma of angles
constexpr double kMaxCorrelation = 0.995;

/// Warnings about the motion in `pairs`: too little travel, no turns, turns one way only.
std::vector<std::string> motionWarnings(const std::vector<MotionPair>& pairs,
                                        const ObservabilityHints& hints)
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
    warnings.push_back("no turning: " + hints.unobservable_without_turning +
                       " are unobservable from straight driving; drive curves in both "
                       "directions");
  } else if (left_turn_rad < kMinTurnRad || right_turn_rad < kMinTurnRad) {
    warnings.push_back(std::string("turns ") + (left_turn_rad < kMinTurnRad ? "right" : "left") +
                       " only: " + hints.confused_by_one_way_turns +
                       "; drive curves in the other direction too");
  }
  return warnings;
}

/// Whether an estimate's sigma is too large: against its value for a relative parameter,
/// against an absolute tolerance for an angle (0.02 rad) or another length (0.05 m).
bool poorlyDetermined(const ParameterEstimate& estimate, const ObservabilityHints& hints)
{
  const bool relative =
      std::find(hints.relative_parameters.begin(), hints.relative_parameters.end(),
                estimate.name) != hints.relative_parameters.end();
  if (estimate.unit == "rad")
    return estimate.sigma > kMaxAbsoluteSigmaRad;
  if (relative)
    return estimate.sigma > kMaxRelativeSigma * std::abs(estimate.value);
  return estimate.sigma > kMaxAbsoluteSigmaM;
}

/// Notes on pairs of parameters correlated beyond kMaxCorrelation that are each determined
/// (a poorly determined one has its own warning).
void noteStrongCorrelations(const std::vector<ParameterEstimate>& estimates,
                            const Eigen::MatrixXd& covariance,
                            const std::vector<bool>& poorly_determined,
                            std::vector<std::string>* notes)
{
  const auto n = static_cast<Eigen::Index>(estimates.size());
  for (Eigen::Index i = 0; i < n; ++i) {
    for (Eigen::Index j = i + 1; j < n; ++j) {
      const double denominator = std::sqrt(covariance(i, i) * covariance(j, j));
      if (denominator <= 0.0) {
        continue;
      }
      const double correlation = covariance(i, j) / denominator;
      if (notes != nullptr && std::abs(correlation) > kMaxCorrelation &&
          !poorly_determined[static_cast<std::size_t>(i)] &&
          !poorly_determined[static_cast<std::size_t>(j)]) {
        notes->push_back(estimates[i].name + " and " + estimates[j].name +
                         " are strongly correlated (" + formatNumber(correlation) +
                         "); each is determined to the sigma shown");
      }
    }
  }
}

}  // namespace

std::vector<std::string> observabilityWarnings(const std::vector<MotionPair>& pairs,
                                               const std::vector<ParameterEstimate>& estimates,
                                               const Eigen::MatrixXd& covariance,
                                               bool covariance_available,
                                               const ObservabilityHints& hints,
                                               std::vector<std::string>* notes)
{
  std::vector<std::string> warnings = motionWarnings(pairs, hints);
  if (!covariance_available) {
    warnings.push_back(
        "parameter covariance unavailable (rank-deficient problem): at least one parameter is "
        "not determined by this motion; sigmas are not reported");
    return warnings;
  }
  std::vector<bool> poorly_determined(estimates.size(), false);
  for (std::size_t i = 0; i < estimates.size(); ++i) {
    const ParameterEstimate& estimate = estimates[i];
    poorly_determined[i] = poorlyDetermined(estimate, hints);
    if (poorly_determined[i]) {
      warnings.push_back(estimate.name + " is poorly determined (sigma " +
                         formatNumber(estimate.sigma) + " " + estimate.unit +
                         "): record more varied motion (tight turns both ways, reversing)");
    }
  }
  noteStrongCorrelations(estimates, covariance, poorly_determined, notes);
  return warnings;
}

}  // namespace odometry_calibration
