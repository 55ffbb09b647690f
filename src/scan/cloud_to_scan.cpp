#include "odometry_calibration/scan/cloud_to_scan.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <vector>

#include <pcl/common/transforms.h>
#include <pcl/filters/crop_box.h>
#include <pcl/filters/statistical_outlier_removal.h>
#include <pcl/filters/voxel_grid.h>
#include <Eigen/Geometry>

namespace odometry_calibration {
namespace {

/// The scan's common fields: range limits, and the nominal spacing of `rays` rays over a turn.
Scan emptyScan(std::size_t rays, const CloudToScanOptions& options)
{
  Scan scan;
  scan.angle_increment_rad = 2.0 * M_PI / static_cast<double>(std::max<std::size_t>(rays, 1));
  scan.angle_min_rad = -M_PI + 0.5 * scan.angle_increment_rad;  // bin centres
  scan.range_min_m = options.range_min_m;
  scan.range_max_m = options.range_max_m;
  return scan;
}

/// Projected onto the plane and binned by bearing; each bin keeps its nearest point.
Scan binnedByBearing(const TimedCloud& kept, bool has_times, const CloudToScanOptions& options)
{
  const std::size_t bins =
      static_cast<std::size_t>(std::ceil(2.0 * M_PI / options.angular_resolution_rad));
  Scan scan = emptyScan(bins, options);
  scan.ranges_m.assign(bins, std::numeric_limits<double>::quiet_NaN());
  if (has_times)
    scan.ray_times_s.assign(bins, 0.0);
  for (const auto& p : kept.points) {
    const double range = std::hypot(static_cast<double>(p.x), static_cast<double>(p.y));
    if (!(range >= options.range_min_m && range <= options.range_max_m))
      continue;
    const double bearing = std::atan2(static_cast<double>(p.y), static_cast<double>(p.x));
    std::size_t bin = static_cast<std::size_t>((bearing + M_PI) / scan.angle_increment_rad);
    if (bin >= bins)
      bin = bins - 1;  // bearing == pi
    double& nearest = scan.ranges_m[bin];
    if (std::isnan(nearest) || range < nearest) {
      nearest = range;
      if (has_times)
        scan.ray_times_s[bin] = static_cast<double>(p.intensity);
    }
  }
  return scan;
}

/// The (projected) points themselves within the range limits, ordered by bearing: one ray per
/// point at its own bearing (Scan::ray_angles_rad).
Scan pointsByBearing(const TimedCloud& kept, bool has_times, const CloudToScanOptions& options)
{
  struct Polar
  {
    double bearing, range, time;
  };
  std::vector<Polar> points;
  points.reserve(kept.size());
  for (const auto& p : kept.points) {
    const double range = std::hypot(static_cast<double>(p.x), static_cast<double>(p.y));
    if (range >= options.range_min_m && range <= options.range_max_m) {
      points.push_back({std::atan2(static_cast<double>(p.y), static_cast<double>(p.x)), range,
                        static_cast<double>(p.intensity)});
    }
  }
  std::sort(points.begin(), points.end(),
            [](const Polar& a, const Polar& b) { return a.bearing < b.bearing; });
  Scan scan = emptyScan(points.size(), options);
  scan.ranges_m.reserve(points.size());
  scan.ray_angles_rad.reserve(points.size());
  for (const Polar& p : points) {
    scan.ranges_m.push_back(p.range);
    scan.ray_angles_rad.push_back(p.bearing);
    if (has_times)
      scan.ray_times_s.push_back(p.time);
  }
  if (!points.empty())
    scan.angle_min_rad = points.front().bearing;
  return scan;
}

/// The finite points of `input` (copied only when some are not), levelled (R_y(pitch) R_x(roll):
/// the plane becomes z = 0). Counts the finite points.
TimedCloud::ConstPtr finiteLevelled(const TimedCloud::ConstPtr& input,
                                    const CloudToScanOptions& options, CloudToScanCounts& counts)
{
  TimedCloud::ConstPtr points = input;
  counts.finite = 0;
  for (const auto& p : input->points)
    counts.finite += std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z) ? 1 : 0;
  if (counts.finite < counts.input) {
    auto finite = std::make_shared<TimedCloud>();
    finite->reserve(counts.finite);
    for (const auto& p : input->points) {
      if (std::isfinite(p.x) && std::isfinite(p.y) && std::isfinite(p.z))
        finite->push_back(p);
    }
    points = finite;
  }
  if (options.roll_rad != 0.0 || options.pitch_rad != 0.0) {
    const Eigen::Affine3f level(
        Eigen::AngleAxisf(static_cast<float>(options.pitch_rad), Eigen::Vector3f::UnitY()) *
        Eigen::AngleAxisf(static_cast<float>(options.roll_rad), Eigen::Vector3f::UnitX()));
    auto levelled = std::make_shared<TimedCloud>();
    pcl::transformPointCloud(*points, *levelled, level);
    points = levelled;
  }
  return points;
}

/// The height band, and the range limits as a box (the exact circle comes with the binning);
/// projected onto the plane when the scan is made of the points themselves.
TimedCloud::Ptr heightBand(const TimedCloud::ConstPtr& points, const CloudToScanOptions& options)
{
  auto band = std::make_shared<TimedCloud>();
  pcl::CropBox<pcl::PointXYZI> crop;
  const float r = static_cast<float>(options.range_max_m);
  crop.setMin(Eigen::Vector4f(-r, -r, static_cast<float>(options.band_min_m), 1.0f));
  crop.setMax(Eigen::Vector4f(r, r, static_cast<float>(options.band_max_m), 1.0f));
  crop.setInputCloud(points);
  crop.filter(*band);
  if (options.scan_from == ScanFrom::kPoints) {
    for (auto& p : band->points)
      p.z = 0.0f;  // projected onto the plane: the rings that see a wall share its voxels
  }
  return band;
}

/// The voxel grid's centroids (the cloud itself without a voxel size), then the statistical
/// outlier removal (the cloud itself without neighbours or with too few points).
TimedCloud::Ptr thinned(const TimedCloud::Ptr& band, const CloudToScanOptions& options,
                        CloudToScanCounts& counts)
{
  auto voxels = band;
  if (options.voxel_size_m > 0.0 && !band->empty()) {
    voxels = std::make_shared<TimedCloud>();
    pcl::VoxelGrid<pcl::PointXYZI> grid;
    const float leaf = static_cast<float>(options.voxel_size_m);
    grid.setLeafSize(leaf, leaf, leaf);
    grid.setInputCloud(band);
    grid.filter(*voxels);
  }
  counts.voxels = voxels->size();
  auto kept = voxels;
  if (options.outlier_neighbours > 0 &&
      voxels->size() > static_cast<std::size_t>(options.outlier_neighbours)) {
    kept = std::make_shared<TimedCloud>();
    pcl::StatisticalOutlierRemoval<pcl::PointXYZI> outliers;
    outliers.setMeanK(options.outlier_neighbours);
    outliers.setStddevMulThresh(options.outlier_stddev);
    outliers.setInputCloud(voxels);
    outliers.filter(*kept);
  }
  counts.kept = kept->size();
  return kept;
}

/// Why a scan of too few bearings was refused, with the counts of each stage.
std::string tooFewPointsMessage(const CloudToScanCounts& counts, const CloudToScanOptions& options)
{
  std::ostringstream text;
  text << "too few points in the height band " << describeBand(options) << ": " << counts.rays
       << " bearings left (" << options.min_points << " needed) of " << counts.input << " points ("
       << counts.finite << " finite, " << counts.band << " in the band, " << counts.voxels
       << " after the voxel grid, " << counts.kept << " after the outlier removal)";
  return text.str();
}

}  // namespace

Scan cloudToScan(const TimedCloud::ConstPtr& input, bool has_times,
                 const CloudToScanOptions& options, CloudToScanCounts* counts_out)
{
  validate(options);
  CloudToScanCounts counts;
  auto report = [&] {
    if (counts_out)
      *counts_out = counts;
  };
  counts.input = input->size();
  if (input->empty()) {
    report();
    throw std::invalid_argument("the cloud is empty");
  }
  const TimedCloud::Ptr band = heightBand(finiteLevelled(input, options, counts), options);
  counts.band = band->size();
  const TimedCloud::Ptr kept = thinned(band, options, counts);
  Scan scan = options.scan_from == ScanFrom::kPoints ? pointsByBearing(*kept, has_times, options)
                                                     : binnedByBearing(*kept, has_times, options);
  counts.rays = countUsableReadings(scan);
  report();
  if (counts.rays < options.min_points) {
    throw std::invalid_argument(tooFewPointsMessage(counts, options));
  }
  return scan;
}

}  // namespace odometry_calibration
