// Helpers of the live node's rostests: waiting on ROS time-outs in wall time, the player's
// end, the node's log lines, its process id.
#pragma once

#include <chrono>
#include <functional>
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
