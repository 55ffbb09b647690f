#include "odometry_calibration/common/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <stdexcept>
#include <vector>

namespace odometry_calibration {
namespace {

std::string systemError(const std::string& what, const std::string& path)
{
  return what + " '" + path + "': " + std::strerror(errno);
}

}  // namespace

void writeFileAtomically(const std::string& path, const std::string& content)
{
  std::vector<char> temporary(path.begin(), path.end());
  const std::string suffix = ".tmp.XXXXXX";
  temporary.insert(temporary.end(), suffix.begin(), suffix.end());
  temporary.push_back('\0');
  const int fd = mkstemp(temporary.data());
  if (fd < 0) {
    throw std::runtime_error(systemError("cannot create a temporary file next to", path));
  }
  const std::string temporary_path(temporary.data());
  std::size_t written = 0;
  while (written < content.size()) {
    const ssize_t n = ::write(fd, content.data() + written, content.size() - written);
    if (n < 0) {
      if (errno == EINTR)
        continue;
      const std::string message = systemError("cannot write", temporary_path);
      ::close(fd);
      std::remove(temporary_path.c_str());
      throw std::runtime_error(message);
    }
    written += static_cast<std::size_t>(n);
  }
  // mkstemp creates the file 0600; results are meant to be shared like any other file.
  if (::fchmod(fd, 0644) != 0 || ::fsync(fd) != 0) {
    const std::string message = systemError("cannot flush", temporary_path);
    ::close(fd);
    std::remove(temporary_path.c_str());
    throw std::runtime_error(message);
  }
  ::close(fd);
  if (std::rename(temporary_path.c_str(), path.c_str()) != 0) {
    const std::string message = systemError("cannot rename the temporary file to", path);
    std::remove(temporary_path.c_str());
    throw std::runtime_error(message);
  }
}

}  // namespace odometry_calibration
