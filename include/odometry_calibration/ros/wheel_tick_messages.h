// The std_msgs types a per-wheel tick topic may carry (wheels.message_type), in one list for the
// node's subscriptions, the bag readers and the input adapter: visitWheelTickType calls a
// function with a default-constructed message of the named type.
#pragma once

#include <stdexcept>
#include <string>

#include <std_msgs/Float32.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int16.h>
#include <std_msgs/Int32.h>
#include <std_msgs/Int64.h>
#include <std_msgs/UInt16.h>
#include <std_msgs/UInt32.h>

namespace odometry_calibration {

/// `visit(M{})` for the std_msgs type M named `type` ("std_msgs/Int16", ...); its result.
/// Throws std::invalid_argument for another name.
template <class Visit>
auto visitWheelTickType(const std::string& type, Visit&& visit)
{
  if (type == "std_msgs/Int16")
    return visit(std_msgs::Int16());
  if (type == "std_msgs/Int32")
    return visit(std_msgs::Int32());
  if (type == "std_msgs/Int64")
    return visit(std_msgs::Int64());
  if (type == "std_msgs/UInt16")
    return visit(std_msgs::UInt16());
  if (type == "std_msgs/UInt32")
    return visit(std_msgs::UInt32());
  if (type == "std_msgs/Float32")
    return visit(std_msgs::Float32());
  if (type == "std_msgs/Float64")
    return visit(std_msgs::Float64());
  throw std::invalid_argument("wheels.message_type '" + type + "' is not a wheel tick type");
}

}  // namespace odometry_calibration
