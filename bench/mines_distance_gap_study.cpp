// Where the Mines log's distance gap between our PLICP and the reference (CSM) comes from: every
// consecutive pair of ../shared/data/mines/exp1.dat matched by both from the same guess (the
// nominal odometry one line earlier, as test/scan/plicp_mines_test.cpp), once per variant that
// changes one candidate cause. Not a timing benchmark: a study printing, per variant, the summed
// matched distance of each against the nominal odometry's over the pairs both converge on, and
// the per-pair ratio of the two (a matcher biased short on every pair shows as a median ratio
// below 1 of the size of the sum's deficit; a few wrong pairs show as a median near 1).
//
// Usage: study_mines_distance_gap (no arguments; needs the Mines log and CSM's sources).
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

#include "odometry_calibration/scan/plicp.h"
#include "support/mines_log.h"

#include "csm_matcher.h"

namespace odometry_calibration {
namespace {

/// One variant: what ours and CSM are given.
struct Variant
{
  std::string name;
  PlicpOptions ours;
  bool ours_compensates = true;    ///< ours sees the scans moved to the stamp's pose (sweep)
  bool csm_on_our_points = false;  ///< CSM gets our prepared points instead of the raw scan
  double range_min_m = -1.0;       ///< both drop readings below this [m] (< 0: the log's 0.02 m)
};

struct Sums
{
  int pairs = 0;
  int both = 0;
  double ours_m = 0.0;
  double csm_m = 0.0;
  double odometry_m = 0.0;
  std::vector<double> ratios;  // |t ours| / |t CSM| per pair moving more than 5 cm
};

double median(std::vector<double> values)
{
  if (values.empty())
    return std::nan("");
  std::nth_element(values.begin(), values.begin() + values.size() / 2, values.end());
  return values[values.size() / 2];
}

Sums run(const std::vector<mines::Record>& records, const Variant& variant)
{
  std::vector<Scan> scans;
  std::vector<PreparedScan> ours;
  std::vector<PreparedScan> uncompensated;
  for (std::size_t k = 0; k < records.size(); ++k) {
    Scan scan = records[k].scan;
    if (variant.range_min_m >= 0.0)
      scan.range_min_m = variant.range_min_m;
    Scan still = scan;
    still.time_increment_s = 0.0;
    scans.push_back(still);
    ours.push_back(variant.ours_compensates
                       ? prepareScan(scan, variant.ours.line_fit, mines::laserVelocity(records, k))
                       : prepareScan(still, variant.ours.line_fit));
  }
  Sums sums;
  for (std::size_t k = 0; k + 1 < records.size(); ++k) {
    const Pose2 odometry = mines::laserMotion(mines::wheelOdometry(records[k], records[k + 1]));
    const Pose2 guess =
        k == 0 ? odometry : mines::laserMotion(mines::wheelOdometry(records[k - 1], records[k]));
    const PlicpResult mine = matchScans(ours[k], ours[k + 1], guess, variant.ours);
    Pose2 csm;
    bool csm_valid = false;
    if (variant.csm_on_our_points) {
      const PlicpResult theirs =
          csm_reference::matchPreparedWithCsm(ours[k], ours[k + 1], guess, false);
      csm_valid = theirs.valid();
      csm = theirs.T_ref_new;
    } else {
      const csm_reference::CsmOutcome theirs =
          csm_reference::matchWithCsm(scans[k], scans[k + 1], guess, false);
      csm_valid = theirs.valid;
      csm = theirs.T_ref_new;
    }
    ++sums.pairs;
    if (!mine.converged() || !csm_valid)
      continue;
    ++sums.both;
    const double ours_m = std::hypot(mine.T_ref_new.x(), mine.T_ref_new.y());
    const double csm_m = std::hypot(csm.x(), csm.y());
    sums.ours_m += ours_m;
    sums.csm_m += csm_m;
    sums.odometry_m += std::hypot(odometry.x(), odometry.y());
    if (csm_m > 0.05)
      sums.ratios.push_back(ours_m / csm_m);
  }
  return sums;
}

std::vector<Variant> variants()
{
  std::vector<Variant> list;
  list.push_back({"defaults (ours sweep-compensated, CSM raw scans)", PlicpOptions()});
  Variant no_sweep{"sweep compensation off (both the raw scans)", PlicpOptions()};
  no_sweep.ours_compensates = false;
  list.push_back(no_sweep);
  Variant same_points{"CSM on our prepared points (same points for both)", PlicpOptions()};
  same_points.csm_on_our_points = true;
  list.push_back(same_points);
  Variant same_raw = same_points;
  same_raw.name = "CSM on our prepared points, no sweep compensation";
  same_raw.ours_compensates = false;
  list.push_back(same_raw);
  for (const double range_min_m : {0.1, 0.3}) {
    Variant near{"both drop readings below " + std::to_string(range_min_m).substr(0, 3) + " m",
                 PlicpOptions()};
    near.range_min_m = range_min_m;
    list.push_back(near);
  }
  Variant gate{"ours max_correspondence_distance_m 2 (CSM's)", PlicpOptions()};
  gate.ours.max_correspondence_distance_m = 2.0;
  list.push_back(gate);
  Variant normals{"ours without the normal test (max_normal_angle_rad pi)", PlicpOptions()};
  normals.ours.max_normal_angle_rad = M_PI;
  list.push_back(normals);
  Variant extent{"ours surface_extent_margin_m 1", PlicpOptions()};
  extent.ours.surface_extent_margin_m = 1.0;
  list.push_back(extent);
  Variant short_fits{"ours line fits over 0.06 m (radius_m), 3 points", PlicpOptions()};
  short_fits.ours.line_fit.radius_m = 0.06;
  short_fits.ours.line_fit.min_points = 3;
  short_fits.ours.line_fit.min_points_one_sided = 3;
  list.push_back(short_fits);
  Variant long_fits{"ours line fits over 0.25 m (radius_m)", PlicpOptions()};
  long_fits.ours.line_fit.radius_m = 0.25;
  list.push_back(long_fits);
  Variant all_kept{"ours trim_keep_fraction 1", PlicpOptions()};
  all_kept.ours.trim_keep_fraction = 1.0;
  list.push_back(all_kept);
  return list;
}

}  // namespace
}  // namespace odometry_calibration

int main()
{
  using namespace odometry_calibration;
  const std::string path = mines::logPath(ODOMETRY_CALIBRATION_SHARED_DATA_DIR);
  const std::vector<mines::Record> records = mines::loadLog(path);
  if (records.empty()) {
    std::fprintf(stderr, "study_mines_distance_gap: the Mines log was not found at %s\n",
                 path.c_str());
    return 1;
  }
  std::printf(
      "| variant | both converge | ours vs odometry | CSM vs odometry | ours vs CSM | "
      "median pair ratio ours / CSM - 1 |\n|---|---|---|---|---|---|\n");
  for (const Variant& variant : variants()) {
    const Sums sums = run(records, variant);
    std::printf("| %s | %d / %d | %+.2f %% | %+.2f %% | %+.2f %% | %+.2f %% |\n",
                variant.name.c_str(), sums.both, sums.pairs,
                100.0 * (sums.ours_m / sums.odometry_m - 1.0),
                100.0 * (sums.csm_m / sums.odometry_m - 1.0),
                100.0 * (sums.ours_m / sums.csm_m - 1.0), 100.0 * (median(sums.ratios) - 1.0));
    std::fflush(stdout);
  }
  return 0;
}
