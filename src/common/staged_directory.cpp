#include "odometry_calibration/common/staged_directory.h"

#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>
#include <vector>

namespace odometry_calibration {
namespace {

std::string systemError(const std::string& what, const std::string& path, int error)
{
  return what + " '" + path + "': " + std::strerror(error);
}

}  // namespace

StagedDirectory::StagedDirectory(const std::string& parent, const std::string& name)
    : final_path_(parent + "/" + name)
{
  std::string pattern = parent + "/." + name + ".tmp.XXXXXX";
  std::vector<char> buffer(pattern.begin(), pattern.end());
  buffer.push_back('\0');
  if (!mkdtemp(buffer.data())) {
    throw std::runtime_error(systemError("cannot create a temporary folder in", parent, errno));
  }
  temporary_path_ = buffer.data();
  // mkdtemp makes it 0700; results are meant to be shared like any other folder.
  std::filesystem::permissions(temporary_path_, std::filesystem::perms::owner_all |
                                                    std::filesystem::perms::group_read |
                                                    std::filesystem::perms::group_exec |
                                                    std::filesystem::perms::others_read |
                                                    std::filesystem::perms::others_exec);
}

StagedDirectory::~StagedDirectory()
{
  if (!committed_) {
    std::error_code ignored;
    std::filesystem::remove_all(temporary_path_, ignored);
  }
}

void StagedDirectory::commit()
{
  std::error_code error_code;
  const bool exists = std::filesystem::exists(final_path_, error_code);
  int result = 0;
  if (exists) {
    // One step: readers see the old folder or the new one, never none or a mix.
    result = renameat2(AT_FDCWD, temporary_path_.c_str(), AT_FDCWD, final_path_.c_str(),
                       RENAME_EXCHANGE);
    if (result != 0 && (errno == EINVAL || errno == ENOSYS)) {
      // A file system without the exchange: move the old folder aside first (a moment
      // without the folder, never a mix), then give the old one the temporary name, so the
      // clean-up below removes it.
      const std::string aside = temporary_path_ + ".old";
      result = std::rename(final_path_.c_str(), aside.c_str());
      if (result == 0) {
        result = std::rename(temporary_path_.c_str(), final_path_.c_str());
        const int error = errno;
        if (result != 0)
          std::rename(aside.c_str(), final_path_.c_str());  // put the old one back
        else
          std::rename(aside.c_str(), temporary_path_.c_str());
        errno = error;
      }
    }
  } else {
    result = std::rename(temporary_path_.c_str(), final_path_.c_str());
  }
  if (result != 0) {
    const int error = errno;
    std::filesystem::remove_all(temporary_path_, error_code);
    committed_ = true;
    throw std::runtime_error(systemError("cannot move the new folder to", final_path_, error));
  }
  committed_ = true;
  if (exists)  // the old content now sits under the temporary name
    std::filesystem::remove_all(temporary_path_, error_code);
}

}  // namespace odometry_calibration
