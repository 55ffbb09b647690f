#include "odometry_calibration/common/staged_file_set.h"

#include <stdlib.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <utility>

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// An entry moved during commit(): where it was and where it went (undone in reverse order).
struct Move
{
  std::string from, to;
};

/// `name` as one file name in the staging folder: '%' and '/' escaped ("a/b" -> "a%2Fb"), so
/// that an entry in a subfolder is staged beside the others and no two names collide.
std::string flatName(const std::string& name)
{
  std::string flat;
  for (const char c : name)
    flat += c == '%' ? std::string("%25") : c == '/' ? std::string("%2F") : std::string(1, c);
  return flat;
}

}  // namespace

StagedFileSet::StagedFileSet(const std::string& directory, Rename rename)
    : directory_(directory), rename_(std::move(rename))
{
  if (!rename_) {
    rename_ = [](const std::string& from, const std::string& to) {
      return std::rename(from.c_str(), to.c_str());
    };
  }
  std::string pattern = directory + "/.result_set.tmp.XXXXXX";
  if (!mkdtemp(pattern.data())) {
    throw std::runtime_error("cannot create a temporary folder in '" + directory +
                             "': " + std::strerror(errno));
  }
  staging_ = pattern;
  fs::permissions(staging_, fs::perms::owner_all | fs::perms::group_read | fs::perms::group_exec |
                                fs::perms::others_read | fs::perms::others_exec);
  fs::create_directory(staging_ + "/old");
}

StagedFileSet::~StagedFileSet()
{
  std::error_code ignored;
  fs::remove_all(staging_, ignored);
}

std::string StagedFileSet::stagedPath(const std::string& name) const
{
  return staging_ + "/new." + flatName(name);
}

void StagedFileSet::commit(const std::vector<std::string>& names,
                           const std::vector<std::string>& removed)
{
  if (done_)
    throw std::logic_error("StagedFileSet::commit called twice");
  done_ = true;
  std::vector<Move> moves;
  auto move = [&](const std::string& from, const std::string& to) {
    if (rename_(from, to) != 0) {
      const int error = errno;
      for (auto undo = moves.rbegin(); undo != moves.rend(); ++undo)
        std::rename(undo->to.c_str(), undo->from.c_str());
      throw std::runtime_error("cannot move '" + from + "' to '" + to +
                               "': " + std::strerror(error) + " (the previous files are kept)");
    }
    moves.push_back({from, to});
  };
  std::error_code error_code;
  // The old entries aside first (a rename needs no space), then the new ones in.
  std::vector<std::string> old_names = names;
  old_names.insert(old_names.end(), removed.begin(), removed.end());
  for (const std::string& name : old_names) {
    const std::string target = directory_ + "/" + name;
    if (fs::symlink_status(target, error_code).type() != fs::file_type::not_found)
      move(target, staging_ + "/old/" + flatName(name));
  }
  for (const std::string& name : names)
    move(stagedPath(name), directory_ + "/" + name);
}

}  // namespace odometry_calibration
