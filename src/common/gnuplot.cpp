#include "odometry_calibration/common/gnuplot.h"

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>
#include <vector>

extern char** environ;

namespace odometry_calibration {
namespace {

/// The last `count` non-empty lines of a file, joined by "; ".
std::string lastLines(const std::string& path, std::size_t count)
{
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) {
    if (line.find_first_not_of(" \t^") != std::string::npos)
      lines.push_back(line);
  }
  std::string text;
  for (std::size_t i = lines.size() > count ? lines.size() - count : 0; i < lines.size(); ++i)
    text += (text.empty() ? "" : "; ") + lines[i];
  return text;
}

/// Starts `program` with the scripts in `directory`: no input, no output, its errors into
/// log_path. Returns posix_spawnp's error (0: started, *pid set).
int spawnInDirectory(const std::string& program, const std::vector<std::string>& scripts,
                     const std::string& directory, const std::string& log_path, pid_t* pid)
{
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, STDIN_FILENO, "/dev/null", O_RDONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDOUT_FILENO, "/dev/null", O_WRONLY, 0);
  posix_spawn_file_actions_addopen(&actions, STDERR_FILENO, log_path.c_str(),
                                   O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
  std::vector<char*> argv = {const_cast<char*>(program.c_str())};
  for (const std::string& script : scripts)
    argv.push_back(const_cast<char*>(script.c_str()));
  argv.push_back(nullptr);
  const int spawn_error =
      posix_spawnp(pid, program.c_str(), &actions, nullptr, argv.data(), environ);
  posix_spawn_file_actions_destroy(&actions);
  return spawn_error;
}

/// Waits for the child until timeout_s [s]; kills it then. Returns false on the timeout, else
/// true with waitpid's answer in *waited and the status in *status.
bool waitWithin(pid_t pid, double timeout_s, int* status, pid_t* waited)
{
  const auto deadline =
      std::chrono::steady_clock::now() + std::chrono::duration<double>(std::max(0.0, timeout_s));
  while ((*waited = waitpid(pid, status, WNOHANG)) == 0) {
    if (std::chrono::steady_clock::now() > deadline) {
      kill(pid, SIGKILL);
      waitpid(pid, status, 0);
      return false;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return true;
}

/// Why a finished run failed: its exit status or signal, and the last lines it printed.
std::string failureText(const std::string& command, int status, const std::string& printed)
{
  std::ostringstream text;
  text << "'" << command << "' failed ("
       << (WIFEXITED(status) ? "exit status " + std::to_string(WEXITSTATUS(status))
                             : "signal " + std::to_string(WTERMSIG(status)))
       << ")";
  if (!printed.empty())
    text << ": " << printed;
  return text.str();
}

}  // namespace

std::string runGnuplot(const std::vector<std::string>& scripts, const std::string& directory,
                       const GnuplotOptions& options)
{
  std::string command = options.program;
  for (const std::string& script : scripts)
    command += " " + script;
  std::error_code error_code;
  if (!std::filesystem::is_directory(directory, error_code))
    return "the plot folder '" + directory + "' does not exist";
  // Absolute: the child opens its files after changing into the folder.
  const std::string log_path =
      std::filesystem::absolute(directory, error_code).string() + "/.gnuplot_stderr";
  pid_t pid = 0;
  const int spawn_error = spawnInDirectory(options.program, scripts, directory, log_path, &pid);
  if (spawn_error == ENOENT) {
    return "the plotting program '" + options.program +
           "' was not found (install the Debian package gnuplot-nox; scripts/setup does)";
  }
  if (spawn_error != 0) {
    return "cannot run '" + options.program + "': " + std::strerror(spawn_error);
  }
  int status = 0;
  pid_t waited = 0;
  if (!waitWithin(pid, options.timeout_s, &status, &waited)) {
    std::remove(log_path.c_str());
    std::ostringstream text;
    text << "'" << command << "' did not finish within " << options.timeout_s
         << " s and was stopped";
    return text.str();
  }
  const std::string printed = lastLines(log_path, 3);
  std::remove(log_path.c_str());
  if (waited < 0)
    return "cannot wait for '" + options.program + "': " + std::strerror(errno);
  if (WIFEXITED(status) && WEXITSTATUS(status) == 0)
    return "";
  return failureText(command, status, printed);
}

}  // namespace odometry_calibration
