// Fuzz target: a bag file's bytes, read as calibrate_bag reads them (runBags: rosbag opens it,
// checkBagRecords walks its records, the reading thread deserialises each message after the
// wire length check, the pair collector pairs them) with the diff_drive.yaml configuration.
// Every outcome but a clean run must be an exception: corrupted bags are reported, never read
// outside their buffers. The seed (test/fuzz/bag/) is a short simulated recording.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <exception>
#include <string>

#include "odometry_calibration/bag_tools/bag_runner.h"
#include "odometry_calibration/config/calibration_config.h"

#include "support/fuzz_config.h"

using namespace odometry_calibration;

namespace {

/// The file the input is written to: one per process, removed at exit.
const std::string& bagPath()
{
  static const std::string path = [] {
    char pattern[] = "/tmp/bag_fuzz.XXXXXX";
    const int fd = ::mkstemp(pattern);
    if (fd < 0)
      std::abort();
    ::close(fd);
    static std::string name = pattern;
    std::atexit([] { ::unlink(name.c_str()); });
    return name;
  }();
  return path;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size)
{
  const int fd = ::open(bagPath().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
  if (fd < 0)
    std::abort();
  for (std::size_t done = 0; done < size;) {
    const ssize_t wrote = ::write(fd, data + done, size - done);
    if (wrote <= 0)
      std::abort();
    done += static_cast<std::size_t>(wrote);
  }
  ::close(fd);
  try {
    runBags({bagPath()}, test::diffDriveFuzzConfig());
  } catch (const std::exception&) {
    // Reported to the user as "bag '...' is corrupted: ..." (or another clear error).
  }
  return 0;
}
