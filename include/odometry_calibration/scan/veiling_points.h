// Veiling points (mixed pixels) at depth discontinuities, removed before the line fits.
//
// Where a beam's footprint straddles a depth step (the edge of a desk in front of a wall), a
// phase-measuring scanner averages the two echoes and returns a range somewhere between the two
// surfaces (Tang et al., "Characterizing the URG-04LX", 2009; Ye & Borenstein, ICRA 2002). Such a
// point lies on no surface: it bends the line fitted at the near surface's end, stretches that
// surface's extent, and as a new point it is matched to whichever line is nearest. It moves with
// the viewpoint (the step's apparent position does), so it biases the match.
//
// The test is the geometric one of the shadow filters used with ROS lasers (laser_filters'
// ScanShadowsFilter): seen from a point, the segment to its neighbour along the scan makes an
// angle with the ray back to the sensor; on any real surface that angle is the surface's
// inclination to the ray, while a veiling point and its neighbours line up almost along the ray.
// When the angle is below min_angle (or above pi - min_angle) the farther of the two points is a
// veiling point: a mixed pixel behind the near surface, or the first point of the far surface
// beyond the step, whose apparent end moves with the viewpoint as well. Surfaces seen at less than
// min_angle from their ray (grazing walls, whose points are far apart and whose range noise acts
// along the wall) lose their points too, as in those filters.
#pragma once

#include <cstdint>
#include <vector>

#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

/// Marks (1) the veiling points of `points`: for every two points of neighbouring rays (ray
/// indices at most `max_ray_gap` apart, consecutive in `points`) whose connecting segment makes
/// an angle below `min_angle_rad` with the ray of the nearer one, the farther one. min_angle_rad
/// in [0, pi/2) (0 marks nothing), max_ray_gap >= 1.
std::vector<std::uint8_t> findVeilingPoints(const ScanPoints& points, double min_angle_rad,
                                            int max_ray_gap);

/// The points whose `remove` entry is 0, in order (every per-point vector filtered alike).
ScanPoints removePoints(const ScanPoints& points, const std::vector<std::uint8_t>& remove);

}  // namespace odometry_calibration
