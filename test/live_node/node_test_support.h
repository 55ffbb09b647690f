// Helpers of the live node's rostests: waiting on ROS time-outs in wall time, the player's
// end, the node's log lines, its process id, the files it writes, calibrate_bag beside it.
#pragma once

#include <sys/wait.h>

#include <chrono>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <iterator>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include <ros/network.h>
#include <ros/ros.h>
#include <rosgraph_msgs/Log.h>
#include <xmlrpcpp/XmlRpc.h>

namespace odometry_calibration {
namespace test {

/// Spins until `done()` or `timeout_s` wall seconds; returns done().
inline bool waitFor(const std::function<bool()>& done, double timeout_s)
{
  const auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(timeout_s);
  while (!done() && std::chrono::steady_clock::now() < end && ros::ok()) {
    ros::spinOnce();
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  return done();
}

/// The whole text of a file ("" when it cannot be read).
inline std::string readText(const std::string& path)
{
  std::ifstream in(path);
  return std::string((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
}

/// The number of lines of a file (0 when it cannot be read).
inline std::size_t fileLines(const std::string& path)
{
  std::ifstream in(path);
  std::size_t count = 0;
  for (std::string line; std::getline(in, line);)
    ++count;
  return count;
}

/// Waits until `counts()` (e.g. pairs files' line counts, pairs published) stays the same for
/// `quiet_s` wall seconds in a row, or `timeout_s` have passed: the node's matching queue is done.
template <typename Counts>
void waitUntilSettled(const std::function<Counts()>& counts, int quiet_s, int timeout_s)
{
  Counts before = counts();
  for (int quiet = 0, waited = 0; quiet < quiet_s && waited < timeout_s; ++waited) {
    waitFor([] { return false; }, 1.0);
    const Counts now = counts();
    quiet = now == before ? quiet + 1 : 0;
    before = now;
  }
}

/// Runs calibrate_bag on `bag` with `config` into `output_directory` (its output into
/// `output_directory`.log); returns whether it succeeded: exit 0, or 4 (fitted with warnings).
inline bool runCalibrateBag(const std::string& config, const std::string& bag,
                            const std::string& output_directory)
{
  const std::string command = std::string(ODOMETRY_CALIBRATION_TOOLS_DIR) +
                              "/calibrate_bag --quiet --config " + config + " --output-dir " +
                              output_directory + " " + bag + " > " + output_directory + ".log 2>&1";
  const int status = std::system(command.c_str());
  return WIFEXITED(status) && (WEXITSTATUS(status) == 0 || WEXITSTATUS(status) == 4);
}

/// Whether a node of that name is registered with the master.
inline bool nodeRunning(const std::string& name)
{
  std::vector<std::string> nodes;
  ros::master::getNodes(nodes);
  for (const std::string& node : nodes)
    if (node == name)
      return true;
  return false;
}

/// The process id of a node, asked through its XML-RPC API (-1 if it cannot be reached).
inline int nodePid(const std::string& name)
{
  XmlRpc::XmlRpcValue request, response, payload;
  request[0] = ros::this_node::getName();
  request[1] = name;
  if (!ros::master::execute("lookupNode", request, response, payload, false))
    return -1;
  const std::string uri = payload;
  std::string host;
  uint32_t port = 0;
  if (!ros::network::splitURI(uri, host, port))
    return -1;
  XmlRpc::XmlRpcClient client(host.c_str(), port, "/");
  XmlRpc::XmlRpcValue args, result;
  args[0] = ros::this_node::getName();
  if (!client.execute("getPid", args, result) || result.size() < 3)
    return -1;
  return static_cast<int>(result[2]);
}

/// Collects the log lines (/rosout) of one node.
class LogCapture
{
public:
  LogCapture(ros::NodeHandle& handle, const std::string& node_name) : node_name_(node_name)
  {
    subscriber_ = handle.subscribe("/rosout", 1000, &LogCapture::onLog, this);
  }
  /// Whether a line containing `text` was logged.
  bool contains(const std::string& text)
  {
    std::lock_guard<std::mutex> lock(mutex_);
    for (const std::string& line : lines_)
      if (line.find(text) != std::string::npos)
        return true;
    return false;
  }
  std::string all()
  {
    std::lock_guard<std::mutex> lock(mutex_);
    std::string text;
    for (const std::string& line : lines_)
      text += line + "\n";
    return text;
  }

private:
  void onLog(const rosgraph_msgs::Log::ConstPtr& message)
  {
    if (message->name != node_name_)
      return;
    std::lock_guard<std::mutex> lock(mutex_);
    lines_.push_back(message->msg);
  }
  std::string node_name_;
  ros::Subscriber subscriber_;
  std::mutex mutex_;
  std::vector<std::string> lines_;
};

}  // namespace test
}  // namespace odometry_calibration
