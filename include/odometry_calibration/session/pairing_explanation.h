// Why a collection holds fewer pairs than a fit needs, in the data's own numbers: the keyframe
// intervals' rejections by reason, the configuration key that decides the leading one and the
// value the data asks for; advice about driving only when the driving is the cause.
#pragma once

#include <cstddef>
#include <string>

#include "odometry_calibration/pairing/pair_collector.h"

namespace odometry_calibration {

/// The explanation of `pairs` pairs where `needed` are needed, from the collector's counts
/// (`statistics`) and its options (`options`, as configured). One paragraph, no newline.
std::string explainTooFewPairs(const CollectorStatistics& statistics,
                               const CollectorOptions& options, std::size_t pairs,
                               std::size_t needed);

}  // namespace odometry_calibration
