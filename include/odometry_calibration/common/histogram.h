// Equal-width histograms of non-negative error magnitudes, for the report's residual plots.
#pragma once

#include <cstddef>
#include <vector>

namespace odometry_calibration {

/// Counts of values in [0, bin_width * counts.size()); larger values are counted in
/// `overflow` (not in the last bin, so the plot does not suggest a peak there).
struct Histogram
{
  double bin_width = 0.0;           ///< in the values' unit
  std::vector<std::size_t> counts;  ///< per bin [lower edge, lower edge + width)
  std::size_t overflow = 0;         ///< values at or beyond the last edge
};

/// The histogram of `values` over [0, upper) in `bins` equal bins. Negative values count in bin
/// 0. Throws std::invalid_argument for bins == 0 or an upper limit that is not a positive number.
Histogram makeHistogram(const std::vector<double>& values, double upper, std::size_t bins);

/// A common upper limit for comparing several sets: the given quantile of their union, at
/// least `minimum` (e.g. when all values are zero). `quantile` in (0, 1].
double histogramUpperLimit(const std::vector<std::vector<double>>& sets, double quantile,
                           double minimum);

}  // namespace odometry_calibration
