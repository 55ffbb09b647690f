#include "odometry_calibration/gp/gp_options.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {

void validate(const GpOptions& options)
{
  if (options.starts < 1) {
    throw std::invalid_argument("gp option starts must be at least 1, got " +
                                std::to_string(options.starts));
  }
  if (options.max_iterations < 1) {
    throw std::invalid_argument("gp option max_iterations must be at least 1, got " +
                                std::to_string(options.max_iterations));
  }
  if (options.likelihood_subset < 10) {
    throw std::invalid_argument("gp option likelihood_subset must be at least 10 inputs, got " +
                                std::to_string(options.likelihood_subset));
  }
  if (options.refine_iterations < 0) {
    throw std::invalid_argument("gp option refine_iterations must be >= 0, got " +
                                std::to_string(options.refine_iterations));
  }
  if (options.refine_subset < options.likelihood_subset) {
    throw std::invalid_argument("gp option refine_subset must be >= likelihood_subset (" +
                                std::to_string(options.likelihood_subset) + "), got " +
                                std::to_string(options.refine_subset));
  }
  if (options.inducing_points < 1) {
    throw std::invalid_argument("gp option inducing_points must be at least 1");
  }
  if (!std::isfinite(options.outlier_threshold)) {
    throw std::invalid_argument(
        "gp option outlier_threshold must be a number of sigma (<= 0 keeps every pair)");
  }
  if (!(options.prefit_huber_threshold > 0.0) || !std::isfinite(options.prefit_huber_threshold)) {
    throw std::invalid_argument("gp option prefit_huber_threshold must be a positive number");
  }
  if (options.outlier_passes < 0) {
    throw std::invalid_argument("gp option outlier_passes must be >= 0, got " +
                                std::to_string(options.outlier_passes));
  }
  if (options.num_threads < 0) {
    throw std::invalid_argument("gp option num_threads must be >= 0 (0 = automatic), got " +
                                std::to_string(options.num_threads));
  }
}

std::string toString(GpMeanFunction mean)
{
  return mean == GpMeanFunction::kZero ? "zero" : "linear";
}

std::string toString(GpKernelType kernel)
{
  switch (kernel) {
    case GpKernelType::kRbf:
      return "rbf";
    case GpKernelType::kLinear:
      return "linear";
    case GpKernelType::kRbfPlusLinear:
      return "rbf+linear";
  }
  return "rbf";
}

GpMeanFunction parseGpMeanFunction(const std::string& text)
{
  if (text == "zero") {
    return GpMeanFunction::kZero;
  }
  if (text == "linear") {
    return GpMeanFunction::kLinear;
  }
  throw std::invalid_argument("unknown gp mean function '" + text + "' (zero | linear)");
}

GpKernelType parseGpKernelType(const std::string& text)
{
  if (text == "rbf") {
    return GpKernelType::kRbf;
  }
  if (text == "linear") {
    return GpKernelType::kLinear;
  }
  if (text == "rbf+linear") {
    return GpKernelType::kRbfPlusLinear;
  }
  throw std::invalid_argument("unknown gp kernel '" + text + "' (rbf | linear | rbf+linear)");
}

}  // namespace odometry_calibration
