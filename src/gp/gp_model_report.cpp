// The fit report of GaussianProcessModel: residuals, hyperparameters in raw units, warnings.
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

#include "odometry_calibration/gp/gp_model.h"

namespace odometry_calibration {
namespace {

const char* const kAxisNames[3] = {"x", "y", "theta"};
const char* const kAxisUnits[3] = {"m", "m", "rad"};

/// The residuals after the fit into `report`: the RMS of the SE(2) errors of the means over all
/// pairs (`after`) and, per axis, the RMS of the inliers' residuals (residual_rms_xytheta).
void reportGpResiduals(const std::vector<MotionPair>& pairs, const Eigen::MatrixXd& targets,
                       const Eigen::MatrixXd& means, const std::vector<bool>& inlier,
                       ModelReport* report)
{
  const auto n = static_cast<Eigen::Index>(pairs.size());
  double translation2 = 0.0;
  double rotation2 = 0.0;
  Eigen::Vector3d inlier2 = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < n; ++i) {
    const Pose2 predicted(means(0, i), means(1, i), means(2, i));
    const Eigen::Vector3d error =
        boxMinus(predicted, pairs[static_cast<std::size_t>(i)].sensor_motion);
    translation2 += error.head<2>().squaredNorm();
    rotation2 += error(2) * error(2);
    if (inlier[static_cast<std::size_t>(i)]) {
      Eigen::Vector3d residual = targets.col(i) - means.col(i);
      residual(2) = normalizeAngle(residual(2));
      inlier2 += residual.cwiseAbs2();
    }
  }
  report->after.count = pairs.size();
  report->after.translation_m = std::sqrt(translation2 / static_cast<double>(n));
  report->after.rotation_rad = std::sqrt(rotation2 / static_cast<double>(n));
  report->residual_rms_xytheta =
      (inlier2 / static_cast<double>(pairs.size() - report->outliers)).cwiseSqrt();
}

/// The report rows of one output's hyperparameters in raw units (length scales times the input
/// scale, named by their joint), its noise sigmas and its mean coefficients; no start values and
/// no sigma (NaN). The noise of a pair is its own covariance plus the learned extra variance
/// (paper eq. 2's Sigma_jk + eta): `noise_sigma` is that total at the pairs' mean variance
/// `known_variance`, so never below the pairs' own measurement noise (the extra alone came out
/// at 1e-6 m on a fit whose pairs' covariance explained their scatter); `extra_noise_sigma` is
/// sqrt(eta).
std::vector<ParameterEstimate> gpOutputParameters(int axis, const GpOutputModel& output,
                                                  const Eigen::VectorXd& input_scale,
                                                  const JointLayout& joints, double known_variance)
{
  const std::string axis_name = kAxisNames[axis];
  const std::vector<std::string> names = output.posterior.kernel().parameterNames();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  std::vector<ParameterEstimate> parameters;
  for (std::size_t k = 0; k < names.size(); ++k) {
    double value = std::exp(output.hyperparameters(static_cast<Eigen::Index>(k)));
    std::string name = axis_name + "." + names[k];
    std::string unit = kAxisUnits[axis];
    if (names[k].rfind("length_scale_", 0) == 0) {
      const auto p = static_cast<Eigen::Index>(std::stoi(names[k].substr(13)) - 1);
      value *= input_scale(p);  // back to raw feature units
      name = axis_name + ".length_scale." + joints.names[static_cast<std::size_t>(p)];
      unit = "raw";
    } else if (names[k] == "linear_sigma") {
      unit += " per unit-RMS feature";
    }
    parameters.push_back({name, unit, nan, value, nan});
  }
  parameters.push_back({axis_name + ".noise_sigma", kAxisUnits[axis], nan,
                        std::sqrt(std::max(0.0, known_variance) + output.noise_variance), nan});
  parameters.push_back({axis_name + ".extra_noise_sigma", kAxisUnits[axis], nan,
                        std::sqrt(output.noise_variance), nan});
  for (Eigen::Index p = 0; p < output.mean_coefficients.size(); ++p) {
    parameters.push_back({axis_name + ".mean." + joints.names[static_cast<std::size_t>(p)],
                          std::string(kAxisUnits[axis]) + " per raw unit", nan,
                          output.mean_coefficients(p) / input_scale(p), nan});
  }
  return parameters;
}

/// The warning that the learned extra noise of an output exceeds twice the pairs' own sigma
/// (their mean variance `known_variance`); empty when it does not.
std::string gpExtraNoiseWarning(int axis, const GpOutputModel& output, double known_variance)
{
  const double known_sigma = std::sqrt(known_variance);
  if (!(known_sigma > 0.0 && std::sqrt(output.noise_variance) > 2.0 * known_sigma))
    return "";
  return "gp " + std::string(kAxisNames[axis]) + ": the learned extra noise (" +
         std::to_string(std::sqrt(output.noise_variance)) +
         ") exceeds twice the pairs' own sigma (" + std::to_string(known_sigma) +
         "): the pairs' covariance underestimates their scatter, or the motion is not a "
         "function of the encoder features alone";
}

/// The warnings about the pairs: more than 10 % rejected, fewer than 100.
void warnAboutGpPairs(std::size_t pair_count, ModelReport* report)
{
  if (report->outliers * 10 > pair_count) {
    report->warnings.push_back("gp: " + std::to_string(report->outliers) + " of " +
                               std::to_string(pair_count) +
                               " pairs rejected as outliers (more than 10 %): check the scan "
                               "matching or the encoder-to-scan time offset");
  }
  if (pair_count < 100) {
    report->warnings.push_back("gp: only " + std::to_string(pair_count) +
                               " pairs: outside the motions seen in training the prediction "
                               "falls back to the mean function");
  }
}

}  // namespace

ModelReport GaussianProcessModel::makeReport(const std::vector<MotionPair>& pairs,
                                             const Eigen::MatrixXd& targets,
                                             const Eigen::MatrixXd& variances,
                                             const Eigen::MatrixXd& means,
                                             const std::vector<bool>& inlier) const
{
  const auto inliers = static_cast<std::size_t>(std::count(inlier.begin(), inlier.end(), true));
  ModelReport report;
  report.model = name();
  report.pairs_used = pairs.size();
  report.outliers = pairs.size() - inliers;
  report.rejected = report.outliers;  // left out of the posterior; none is down-weighted
  reportGpResiduals(pairs, targets, means, inlier, &report);
  report.converged = true;
  for (int axis = 0; axis < 3; ++axis) {
    const GpOutputModel& output = outputs_[axis];
    const std::string axis_name = kAxisNames[axis];
    report.iterations += output.iterations;
    report.converged = report.converged && output.converged;
    report.termination += (axis > 0 ? "; " : "") + axis_name + ": " + output.termination;
    if (!output.converged) {
      report.warnings.push_back("gp " + axis_name +
                                ": the hyperparameter search stopped before converging (" +
                                output.termination + "); raise max_iterations");
    }
    const std::vector<ParameterEstimate> parameters =
        gpOutputParameters(axis, output, input_scale_, joints_, variances.row(axis).mean());
    report.parameters.insert(report.parameters.end(), parameters.begin(), parameters.end());
    const std::string noise_warning = gpExtraNoiseWarning(axis, output, variances.row(axis).mean());
    if (!noise_warning.empty())
      report.warnings.push_back(noise_warning);
  }
  warnAboutGpPairs(pairs.size(), &report);
  return report;
}

}  // namespace odometry_calibration
