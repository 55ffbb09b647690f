#include "odometry_calibration/common/text_file.h"

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// "the configuration" -> "configuration": the role without its article.
std::string bareNoun(const std::string& what)
{
  return what.rfind("the ", 0) == 0 ? what.substr(4) : what;
}

/// A file type in words, for one that is neither a regular file nor a directory.
std::string kindOf(std::filesystem::file_type type)
{
  switch (type) {
    case std::filesystem::file_type::fifo:
      return "named pipe";
    case std::filesystem::file_type::socket:
      return "socket";
    case std::filesystem::file_type::character:
    case std::filesystem::file_type::block:
      return "device";
    default:
      return "special file";
  }
}

}  // namespace

std::string readTextFile(const std::string& path, const std::string& what)
{
  const std::string noun = bareNoun(what);
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (status.type() == std::filesystem::file_type::not_found)
    throw std::runtime_error(path + " does not exist: give the path of the " + noun + " file");
  if (status.type() == std::filesystem::file_type::directory)
    throw std::runtime_error(path + " is a directory, not a " + noun + " file");
  if (status.type() != std::filesystem::file_type::regular &&
      status.type() != std::filesystem::file_type::unknown) {
    // A FIFO would block the read until a writer comes, a device may never end.
    throw std::runtime_error(path + " is a " + kindOf(status.type()) + ", not a " + noun +
                             " file: give the path of the file itself");
  }
  errno = 0;
  std::ifstream file(path);
  if (!file) {
    const int reason = errno;
    throw std::runtime_error("cannot read " + what + " " + path + ": " +
                             (reason != 0 ? std::strerror(reason) : "the file cannot be opened"));
  }
  std::ostringstream text;
  text << file.rdbuf();
  if (file.bad())
    throw std::runtime_error("cannot read " + what + " " + path + ": a read error");
  if (text.str().empty())
    throw std::runtime_error(path + " is empty: the " + noun + " file holds nothing to read");
  return text.str();
}

}  // namespace odometry_calibration
