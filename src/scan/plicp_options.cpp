#include "odometry_calibration/scan/plicp_options.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {
namespace {

void require(bool condition, const std::string& message)
{
  if (!condition) {
    throw std::invalid_argument(message);
  }
}

bool positive(double value)
{
  return std::isfinite(value) && value > 0.0;
}

}  // namespace

void validate(const PlicpOptions& options)
{
  require(positive(options.max_correspondence_distance_m),
          "max_correspondence_distance_m must be a positive number of metres");
  require(options.max_correspondence_distance_doublings >= 0 &&
              options.max_correspondence_distance_doublings <= 10,
          "max_correspondence_distance_doublings must be in [0, 10]");
  require(positive(options.max_normal_angle_rad) && options.max_normal_angle_rad <= M_PI,
          "max_normal_angle_rad must be in (0, pi] radians");
  require(std::isfinite(options.surface_extent_margin_m) && options.surface_extent_margin_m >= 0.0,
          "surface_extent_margin_m must be a number of metres >= 0");
  require(positive(options.trim_keep_fraction) && options.trim_keep_fraction <= 1.0,
          "trim_keep_fraction must be in (0, 1]");
  require(positive(options.adaptive_trim_quantile) && options.adaptive_trim_quantile <= 1.0,
          "adaptive_trim_quantile must be in (0, 1]");
  require(positive(options.adaptive_trim_multiplier),
          "adaptive_trim_multiplier must be a positive number");
  require(std::isfinite(options.adaptive_trim_floor_m) && options.adaptive_trim_floor_m >= 0.0,
          "adaptive_trim_floor_m must be a number of metres >= 0");
  require(positive(options.translation_tolerance_m),
          "translation_tolerance_m must be a positive number of metres");
  require(positive(options.rotation_tolerance_rad),
          "rotation_tolerance_rad must be a positive number of radians");
  require(options.max_iterations >= 1, "max_iterations must be at least 1");
  require(positive(options.max_correction_translation_m),
          "max_correction_translation_m must be a positive number of metres");
  require(positive(options.max_correction_rotation_rad),
          "max_correction_rotation_rad must be a positive number of radians");
  require(options.min_points >= 3, "min_points must be at least 3");
  require(options.min_correspondences >= 3, "min_correspondences must be at least 3");
  require(std::isfinite(options.min_inlier_fraction) && options.min_inlier_fraction >= 0.0 &&
              options.min_inlier_fraction <= 1.0,
          "min_inlier_fraction must be in [0, 1]");
  require(positive(options.inlier_distance_m),
          "inlier_distance_m must be a positive number of metres");
  require(positive(options.range_sigma_m), "range_sigma_m must be a positive number of metres");
  require(positive(options.min_information_ratio) && options.min_information_ratio < 1.0,
          "min_information_ratio must be in (0, 1)");
  require(options.ambiguity_max_correspondences >= 0,
          "ambiguity_max_correspondences must be >= 0 (0: only near-degenerate matches checked)");
  require(std::isfinite(options.ambiguity_max_information_ratio) &&
              options.ambiguity_max_information_ratio >= 0.0 &&
              options.ambiguity_max_information_ratio < 1.0,
          "ambiguity_max_information_ratio must be in [0, 1) (0: no near-degenerate check)");
  require(positive(options.ambiguity_sigma_m) && positive(options.ambiguity_sigma_rad) &&
              positive(options.ambiguity_offset_m),
          "ambiguity_sigma_m, ambiguity_sigma_rad and ambiguity_offset_m must be > 0");
  require(std::isfinite(options.ambiguity_offset_rad) && options.ambiguity_offset_rad >= 0.0 &&
              options.ambiguity_offset_rad <= M_PI,
          "ambiguity_offset_rad must be in [0, pi] rad (0: no turned starts, the two shifted "
          "ones only)");
  require(std::isfinite(options.ambiguity_return_sigma) && options.ambiguity_return_sigma >= 0.0 &&
              options.ambiguity_return_sigma < 3.0,
          "ambiguity_return_sigma must be in [0, 3) sigma (0: rematches run to convergence; 3 "
          "sigma and beyond widen the covariance)");
  validate(options.line_fit, "line_fit.");
}

}  // namespace odometry_calibration
