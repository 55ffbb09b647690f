// A set of result files that replaces the previous set whole or not at all (on a full disk,
// never part of a new set or a mix of an earlier run's files and the new one's). Every file is
// written into a temporary folder beside the targets first; only when all are written does commit()
// move them into place, each by a rename (which needs no space). A rename that fails puts
// everything back: the old set stays as it was and no new file remains.
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace odometry_calibration {

class StagedFileSet
{
public:
  /// Renames `from` to `to` (0 on success, else -1 with errno set), as std::rename; a test
  /// injects failures through it.
  using Rename = std::function<int(const std::string& from, const std::string& to)>;

  /// Stages into `directory/.result_set.tmp.XXXXXX` (`directory` must exist). Throws
  /// std::runtime_error naming the path and the system error.
  explicit StagedFileSet(const std::string& directory, Rename rename = nullptr);
  ~StagedFileSet();  ///< uncommitted: the staged files are removed, the old set untouched
  StagedFileSet(const StagedFileSet&) = delete;
  StagedFileSet& operator=(const StagedFileSet&) = delete;

  /// Where to write the set's entry `name` (a file or a folder) now. `name` may lie in a
  /// subfolder of `directory` ("source_0/result.yaml"), which must exist at commit().
  std::string stagedPath(const std::string& name) const;

  /// Moves the staged entries `names` into `directory`, replacing the old ones, and removes
  /// the old entries `removed` (an earlier set's file this set has not). On a failure every
  /// entry is put back as it was and std::runtime_error names the path and the system error.
  void commit(const std::vector<std::string>& names, const std::vector<std::string>& removed = {});

private:
  std::string directory_, staging_;
  Rename rename_;
  bool done_ = false;
};

}  // namespace odometry_calibration
