// Fuzz target: a .db3 file's bytes, read as calibrate_bag reads rosbag2's SQLite storage
// (Rosbag2SqliteMessages: the header's length check, SQLite's own checks, the topics and
// messages tables queried, each message on /joint_states and /scan deserialised from CDR).
// Every outcome but a clean read must be std::runtime_error (a damaged file refused, naming it)
// or UnreadableMessage (one message skipped); anything else escapes and is a finding. The seed
// (test/fuzz/rosbag2_sqlite/) is a short recording from the SQLite writer.
#include <fcntl.h>
#include <unistd.h>

#include <cstdint>
#include <cstdlib>
#include <stdexcept>
#include <string>

#include "odometry_calibration/bag/rosbag2_sqlite_messages.h"

using namespace odometry_calibration;

namespace {

/// The file the input is written to: one per process, removed at exit.
const std::string& db3Path()
{
  static const std::string path = [] {
    char pattern[] = "/tmp/rosbag2_sqlite_fuzz.XXXXXX.db3";
    const int fd = ::mkstemps(pattern, 4);
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
  const int fd = ::open(db3Path().c_str(), O_WRONLY | O_TRUNC | O_CLOEXEC);
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
    Rosbag2SqliteMessages messages({db3Path()}, {"/joint_states", "/scan"});
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
    // Reported to the user as "rosbag2 file '...': ..." (or another clear error).
  }
  return 0;
}
