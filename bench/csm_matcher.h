// The reference PLICP (Censi's CSM, sm_icp) called on our Scan type, for the benchmark that puts
// it side by side with ours (plicp_vs_csm_bench.cpp).
// Built only with cmake/reference_csm.cmake's reference_csm library.
#pragma once

#include <cmath>
#include <limits>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/plicp.h"
#include "odometry_calibration/scan/scan.h"

// CSM's C headers last: they define min and max as macros.
#include <csm/csm_all.h>
#include <options/options.h>
#undef min
#undef max

// CSM's option table with its defaults (csm/sm_options.c; no header declares it).
extern "C" void sm_options(struct sm_params* p, struct option* ops);

namespace odometry_calibration {
namespace csm_reference {

/// What CSM returned for one pair.
struct CsmOutcome
{
  bool valid = false;
  Pose2 T_ref_new;
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
};

/// CSM's laser_data for a scan: the same usable rays as ours (finite, within the scan's range
/// limits), the others marked invalid. CSM has no per-ray times: all rays at the stamp.
inline LDP toLaserData(const Scan& scan)
{
  const int n = static_cast<int>(scan.ranges_m.size());
  LDP ld = ld_alloc_new(n);
  for (int i = 0; i < n; ++i) {
    const double range = scan.ranges_m[static_cast<std::size_t>(i)];
    ld->theta[i] = scan.angle_min_rad + i * scan.angle_increment_rad;
    const bool usable =
        std::isfinite(range) && range >= scan.range_min_m && range <= scan.range_max_m;
    ld->valid[i] = usable ? 1 : 0;
    ld->readings[i] = usable ? range : std::numeric_limits<double>::quiet_NaN();
  }
  ld->min_theta = ld->theta[0];
  ld->max_theta = ld->theta[n - 1];
  return ld;
}

/// CSM's defaults (its sm_options), the scan's range limits, covariance as asked.
inline sm_params csmDefaults(const Scan& scan, bool covariance)
{
  static const sm_params defaults = [] {
    sm_params params{};
    struct option* options = options_allocate(100);  // kept: CSM has no way to free it
    sm_options(&params, options);
    return params;
  }();
  sm_params params = defaults;
  params.min_reading = scan.range_min_m;
  params.max_reading = scan.range_max_m;
  params.laser[0] = params.laser[1] = params.laser[2] = 0.0;
  params.do_compute_covariance = covariance ? 1 : 0;
  return params;
}

/// Runs sm_icp with `params` (its scans and first guess set; both freed here) and returns its
/// result, the covariance copied into `covariance` when asked for and computed (GSL matrices
/// freed).
inline sm_result runCsm(sm_params* params, Eigen::Matrix3d* covariance)
{
  sm_result result{};
  sm_icp(params, &result);
  if (covariance && result.valid != 0 && result.cov_x_m) {
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        (*covariance)(r, c) = gsl_matrix_get(result.cov_x_m, r, c);
  }
  for (gsl_matrix* matrix : {result.cov_x_m, result.dx_dy1_m, result.dx_dy2_m}) {
    if (matrix)
      gsl_matrix_free(matrix);
  }
  result.cov_x_m = result.dx_dy1_m = result.dx_dy2_m = nullptr;
  ld_free(params->laser_ref);
  ld_free(params->laser_sens);
  return result;
}

/// sm_icp with its defaults on two scans from a first guess.
inline CsmOutcome matchWithCsm(const Scan& reference, const Scan& current, const Pose2& guess,
                               bool covariance)
{
  sm_params params = csmDefaults(reference, covariance);
  params.laser_ref = toLaserData(reference);
  params.laser_sens = toLaserData(current);
  params.first_guess[0] = guess.x();
  params.first_guess[1] = guess.y();
  params.first_guess[2] = guess.theta();
  CsmOutcome outcome;
  const sm_result result = runCsm(&params, covariance ? &outcome.covariance : nullptr);
  outcome.valid = result.valid != 0;
  outcome.T_ref_new = Pose2(result.x[0], result.x[1], result.x[2]);
  return outcome;
}

/// CSM's laser_data for a prepared scan's points (motion compensated when the scan was): each
/// point as a reading at its own bearing, in the scan's order; CSM recomputes the points from
/// these, so it sees exactly the points ours matches.
inline LDP toLaserData(const ScanPoints& points)
{
  const int n = static_cast<int>(points.size());
  LDP ld = ld_alloc_new(n);
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector2d& p = points.points_m[static_cast<std::size_t>(i)];
    ld->theta[i] = std::atan2(p.y(), p.x());
    ld->readings[i] = p.norm();
    ld->valid[i] = 1;
  }
  ld->min_theta = n > 0 ? ld->theta[0] : 0.0;
  ld->max_theta = n > 0 ? ld->theta[n - 1] : 0.0;
  return ld;
}

/// sm_icp with its defaults on two prepared scans' points from a first guess (covariance as
/// asked), answered as our matcher answers: valid or not converged, the pose, the covariance.
/// For the pairing's matcher slot (pairing/match_queue.h, ScanMatcher).
inline PlicpResult matchPreparedWithCsm(const PreparedScan& reference, const PreparedScan& current,
                                        const Pose2& guess, bool covariance)
{
  PlicpResult answer;
  answer.T_ref_new = guess;
  if (reference.points.size() < 20 || current.points.size() < 20) {
    answer.status = PlicpStatus::kTooFewPoints;
    return answer;
  }
  Scan limits;  // the points are already within the scan's range limits
  limits.range_min_m = 0.0;
  limits.range_max_m = 1e3;
  sm_params params = csmDefaults(limits, covariance);
  params.laser_ref = toLaserData(reference.points);
  params.laser_sens = toLaserData(current.points);
  params.first_guess[0] = guess.x();
  params.first_guess[1] = guess.y();
  params.first_guess[2] = guess.theta();
  const sm_result result = runCsm(&params, covariance ? &answer.covariance : nullptr);
  answer.status = result.valid != 0 ? PlicpStatus::kValid : PlicpStatus::kNoConvergence;
  if (result.valid != 0) {
    answer.T_ref_new = Pose2(result.x[0], result.x[1], result.x[2]);
    answer.iterations = result.iterations;
    answer.correspondence_count = result.nvalid;
  }
  return answer;
}

}  // namespace csm_reference
}  // namespace odometry_calibration
