// Whole files through zstd (Debian's libzstd), as rosbag2 compresses its storage files with
// compression_mode FILE: "<name>.db3" becomes "<name>.db3.zstd", one zstd stream.
#pragma once

#include <string>

namespace odometry_calibration {

/// Decompresses `from` (a zstd stream) into `to` (created or truncated). Throws
/// std::runtime_error naming the file: missing, not zstd, cut off, or a write failure.
void decompressZstdFile(const std::string& from, const std::string& to);

/// Compresses `from` into `to` (created or truncated) at zstd `level`. Throws
/// std::runtime_error naming the file that cannot be read or written.
void compressZstdFile(const std::string& from, const std::string& to, int level = 3);

}  // namespace odometry_calibration
