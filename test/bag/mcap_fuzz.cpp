// Fuzz target: an MCAP file's bytes, read as calibrate_bag reads a .mcap (McapMessages: the
// footer, summary and CRCs checked, the records walked forward, chunks decompressed with zstd or
// lz4, each message on /joint_states and /scan deserialised from CDR). Every outcome but a
// clean read must be std::runtime_error (a damaged file refused, naming it) or UnreadableMessage
// (one message skipped); anything else escapes and is a finding. The seeds (test/fuzz/mcap/) are
// short recordings from the MCAP writer with zstd, lz4 and uncompressed chunks.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "odometry_calibration/bag/mcap_messages.h"

using namespace odometry_calibration;

namespace {

/// The file the input is written to: one per process, removed at exit.
const std::string& mcapPath()
{
  static const std::string path = [] {
    char pattern[] = "/tmp/mcap_fuzz.XXXXXX.mcap";
    const int fd = ::mkstemps(pattern, 5);
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
  const int fd = ::open(mcapPath().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
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
    McapMessages messages({mcapPath()}, {"/joint_states", "/scan"});
    messages.describeTopics();
    while (messages.next()) {
      sensor_msgs::JointState joints;
      sensor_msgs::LaserScan scan;
      try {
        if (!messages.read(joints))
          messages.read(scan);
      } catch (const UnreadableMessage&) {
        // Skipped and counted by the bag reader.
      }
    }
  } catch (const std::runtime_error&) {
    // Reported to the user as "MCAP file '...' is corrupted at byte N: ..." (or another
    // clear error).
  }
  return 0;
}
