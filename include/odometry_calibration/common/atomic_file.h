// Writing result files so that a crash never leaves a half-written file behind.
#pragma once

#include <string>

namespace odometry_calibration {

/// Writes `content` to `path` atomically: into a temporary file in the same directory, flushed
/// to disk, then renamed over `path`. Readers see the old file or the new one, never a mix.
/// Throws std::runtime_error naming the path and the system error on failure (the temporary
/// file is removed).
void writeFileAtomically(const std::string& path, const std::string& content);

}  // namespace odometry_calibration
