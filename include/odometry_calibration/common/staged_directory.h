// A folder of result files that appears complete or not at all: filled under a temporary name
// next to its final place, then swapped in with one rename (the companion of atomic_file.h for
// folders, e.g. a report's plots).
#pragma once

#include <string>

namespace odometry_calibration {

/// A temporary folder that becomes `parent/name` on commit(), or disappears with its content
/// when destroyed uncommitted (an error before the end of a run).
class StagedDirectory
{
public:
  /// Creates `parent/.name.tmp.XXXXXX` (parent must exist). Throws std::runtime_error naming
  /// the path and the system error.
  StagedDirectory(const std::string& parent, const std::string& name);
  ~StagedDirectory();
  StagedDirectory(const StagedDirectory&) = delete;
  StagedDirectory& operator=(const StagedDirectory&) = delete;

  /// Where to write the files now.
  const std::string& path() const { return temporary_path_; }
  /// The final place, `parent/name`.
  const std::string& finalPath() const { return final_path_; }

  /// Puts the folder in place: atomically exchanged with an existing `parent/name` (whose old
  /// content is then removed), or renamed into place. Throws std::runtime_error on failure
  /// (the temporary folder is removed).
  void commit();

private:
  std::string temporary_path_;
  std::string final_path_;
  bool committed_ = false;
};

}  // namespace odometry_calibration
