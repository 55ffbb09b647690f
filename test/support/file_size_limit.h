// A full disk, simulated for one test: while a FileSizeLimit lives, this process cannot make
// any file larger than `bytes` (RLIMIT_FSIZE; writes beyond it fail with EFBIG, and SIGXFSZ is
// ignored so that they fail instead of killing the test). Works as root, unlike a read-only
// directory, and needs no tmpfs.
#pragma once

#include <sys/resource.h>

#include <csignal>

namespace odometry_calibration {
namespace test {

class FileSizeLimit
{
public:
  explicit FileSizeLimit(rlim_t bytes)
  {
    ::getrlimit(RLIMIT_FSIZE, &saved_);
    previous_handler_ = std::signal(SIGXFSZ, SIG_IGN);
    rlimit limited = saved_;
    limited.rlim_cur = bytes;
    ::setrlimit(RLIMIT_FSIZE, &limited);
  }
  ~FileSizeLimit()
  {
    ::setrlimit(RLIMIT_FSIZE, &saved_);
    std::signal(SIGXFSZ, previous_handler_);
  }
  FileSizeLimit(const FileSizeLimit&) = delete;
  FileSizeLimit& operator=(const FileSizeLimit&) = delete;

private:
  rlimit saved_{};
  void (*previous_handler_)(int) = SIG_DFL;
};

}  // namespace test
}  // namespace odometry_calibration
