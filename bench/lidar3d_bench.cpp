// Where a 16-beam lidar cloud's time goes in calibrate_bag (issue 19): the PointCloud2 ->
// PCL conversion, the filtering into a planar scan (band, voxel grid, bearing bins), and the
// scan preparation plus one PLICP match, per cloud of the simulated office run
// (config/sim/scenarios/diff_drive_office_lidar3d.yaml: 16 rings, 0.4 deg, ~14000 points).
// The filtering and matching run with ego_motion.cloud.scan_from bins (argument 0) and points
// (argument 1).
// Run through scripts/bench or scripts/bench_lidar3d.
#include <benchmark/benchmark.h>

#include <unistd.h>

#include <cstdio>
#include <string>
#include <vector>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "odometry_calibration/bag_writers/sim_bag_writer.h"
#include "odometry_calibration/config/calibration_config.h"
#include "odometry_calibration/ros/point_cloud_conversion.h"
#include "odometry_calibration/scan/cloud_to_scan.h"
#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/sim/scenario.h"

namespace {

using namespace odometry_calibration;

const std::string kConfig = ODOMETRY_CALIBRATION_CONFIG_DIR;

/// The clouds of a 3 s simulated office run (simulated once).
const std::vector<sensor_msgs::PointCloud2>& clouds()
{
  static const std::vector<sensor_msgs::PointCloud2> result = [] {
    sim::Scenario scenario = sim::loadScenarioYaml(
        kConfig + "/sim/scenarios/diff_drive_office_lidar3d.yaml", kConfig + "/sim/worlds");
    scenario.duration_s = 3.0;
    const std::string bag_path =
        "/tmp/odometry_calibration_bench_lidar3d." + std::to_string(::getpid()) + ".bag";
    simulateToBag(scenario, bag_path, "");
    std::vector<sensor_msgs::PointCloud2> messages;
    {
      rosbag::Bag bag(bag_path, rosbag::bagmode::Read);
      rosbag::View view(bag, rosbag::TopicQuery(scenario.laser.topic));
      for (const rosbag::MessageInstance& message : view)
        messages.push_back(*message.instantiate<sensor_msgs::PointCloud2>());
    }
    std::remove(bag_path.c_str());
    return messages;
  }();
  return result;
}

const CalibrationConfig& config()
{
  static const CalibrationConfig result =
      loadCalibrationConfig(kConfig + "/diff_drive_lidar3d.yaml");
  return result;
}

/// The config's cloud options with scan_from bins (0) or points (1).
CloudToScanOptions cloudOptions(const benchmark::State& state)
{
  CloudToScanOptions options = config().cloud;
  options.scan_from = state.range(0) == 0 ? ScanFrom::kBins : ScanFrom::kPoints;
  return options;
}

void BM_ConvertPointCloud2(benchmark::State& state)
{
  const auto& messages = clouds();
  std::size_t i = 0;
  for (auto _ : state) {
    auto cloud = ros_conversions::fromPointCloud2Msg(messages[i++ % messages.size()]);
    benchmark::DoNotOptimize(cloud.cloud->size());
  }
  state.counters["points"] = static_cast<double>(messages[0].width);
}

void BM_FilterCloudToScan(benchmark::State& state)
{
  std::vector<ros_conversions::LidarCloud> converted;
  for (const auto& message : clouds())
    converted.push_back(ros_conversions::fromPointCloud2Msg(message));
  std::size_t i = 0;
  CloudToScanCounts counts;
  const CloudToScanOptions options = cloudOptions(state);
  for (auto _ : state) {
    const auto& cloud = converted[i++ % converted.size()];
    Scan scan = cloudToScan(cloud.cloud, cloud.has_times, options, &counts);
    benchmark::DoNotOptimize(scan.ranges_m.data());
  }
  state.counters["in_band"] = static_cast<double>(counts.band);
  state.counters["voxels"] = static_cast<double>(counts.voxels);
  state.counters["rays"] = static_cast<double>(counts.rays);
}

void BM_PrepareAndMatchConsecutiveScans(benchmark::State& state)
{
  std::vector<Scan> scans;
  const CloudToScanOptions options = cloudOptions(state);
  for (const auto& message : clouds()) {
    const auto cloud = ros_conversions::fromPointCloud2Msg(message);
    scans.push_back(cloudToScan(cloud.cloud, cloud.has_times, options));
  }
  const LineFitOptions lines = config().collector.plicp.line_fit;
  PreparedScan previous = prepareScan(scans[0], lines);
  std::size_t i = 1;
  for (auto _ : state) {
    const PreparedScan current = prepareScan(scans[i % scans.size()], lines);
    const PlicpResult result = matchScans(previous, current, Pose2(), config().collector.plicp);
    benchmark::DoNotOptimize(result.T_ref_new);
    previous = current;
    if (++i % scans.size() == 0)
      previous = prepareScan(scans[0], lines);
  }
}

}  // namespace

BENCHMARK(BM_ConvertPointCloud2)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_FilterCloudToScan)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_PrepareAndMatchConsecutiveScans)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK_MAIN();
