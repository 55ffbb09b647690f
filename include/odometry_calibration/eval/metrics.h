// Trajectory accuracy metrics of the GP calibration paper (Nutalapati et al., Sec. IV-A).
#pragma once

#include <vector>

#include "odometry_calibration/geometry/se2.h"

namespace odometry_calibration {

/// Absolute trajectory error, paper eq. 11: RMS over k of |trans(⊖x̂_k ⊕ x_k)| [m], where x̂ is
/// the estimate and x the reference, both in the same world frame, sampled at the same times.
/// Throws std::invalid_argument if the sizes differ or are zero.
double absoluteTrajectoryError(const std::vector<Pose2>& estimated,
                               const std::vector<Pose2>& reference);

/// Relative pose error, paper eq. 10: RMS over consecutive k of
/// |trans(⊖(⊖x̂_k ⊕ x̂_k+1) ⊕ (⊖x_k ⊕ x_k+1))| [m]. Throws std::invalid_argument if the sizes
/// differ or are below two.
double relativePoseError(const std::vector<Pose2>& estimated, const std::vector<Pose2>& reference);

}  // namespace odometry_calibration
