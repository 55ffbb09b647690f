// The field layout of the ROS 2 messages calibrate_bag reads, in CDR order, for the ROS 1 C++
// message types that hold them (ROS 2's Header has no seq; its stamp is int32 sec, uint32
// nanosec). One layout serves both directions: `S` is a CdrReader (cdr_reader.h), which fills
// the message, or a CdrWriter (cdr_writer.h), which writes it (then `M` is const). S provides
//   value(x)             a primitive, aligned to its size
//   text(s)              a string (uint32 length with the terminating NUL, the bytes, the NUL)
//   stamp(t)             builtin_interfaces/Time into a ros::Time
//   array(a)             a fixed-size array of primitives (no count)
//   sequence(v)          a sequence of primitives (uint32 count, the elements)
//   sequence(v, f)       a sequence of strings or structures: f(element) for each
#pragma once

#include <geometry_msgs/PoseStamped.h>
#include <geometry_msgs/TransformStamped.h>
#include <nav_msgs/Odometry.h>
#include <sensor_msgs/Imu.h>
#include <sensor_msgs/JointState.h>
#include <sensor_msgs/LaserScan.h>
#include <sensor_msgs/PointCloud2.h>
#include <std_msgs/Bool.h>
#include <std_msgs/Float32.h>
#include <std_msgs/Float64.h>
#include <std_msgs/Int16.h>
#include <std_msgs/Int32.h>
#include <std_msgs/Int64.h>
#include <std_msgs/Int8.h>
#include <std_msgs/UInt16.h>
#include <std_msgs/UInt32.h>
#include <std_msgs/UInt64.h>
#include <std_msgs/UInt8.h>
#include <tf2_msgs/TFMessage.h>

#include <type_traits>

namespace odometry_calibration {
namespace cdr {

template <class S, class Header>
void headerLayout(S& s, Header& header)
{
  s.stamp(header.stamp);
  s.text(header.frame_id);
}

template <class S, class Vector>
void vector3Layout(S& s, Vector& v)
{
  s.value(v.x);
  s.value(v.y);
  s.value(v.z);
}

template <class S, class Quaternion>
void quaternionLayout(S& s, Quaternion& q)
{
  s.value(q.x);
  s.value(q.y);
  s.value(q.z);
  s.value(q.w);
}

template <class S, class Pose>
void poseLayout(S& s, Pose& pose)
{
  vector3Layout(s, pose.position);
  quaternionLayout(s, pose.orientation);
}

template <class S, class Twist>
void twistLayout(S& s, Twist& twist)
{
  vector3Layout(s, twist.linear);
  vector3Layout(s, twist.angular);
}

template <class S, class M>
void jointStateLayout(S& s, M& m)
{
  headerLayout(s, m.header);
  s.sequence(m.name, [&](auto& name) { s.text(name); });
  s.sequence(m.position);
  s.sequence(m.velocity);
  s.sequence(m.effort);
}

template <class S, class M>
void laserScanLayout(S& s, M& m)
{
  headerLayout(s, m.header);
  s.value(m.angle_min);
  s.value(m.angle_max);
  s.value(m.angle_increment);
  s.value(m.time_increment);
  s.value(m.scan_time);
  s.value(m.range_min);
  s.value(m.range_max);
  s.sequence(m.ranges);
  s.sequence(m.intensities);
}

template <class S, class M>
void pointCloud2Layout(S& s, M& m)
{
  headerLayout(s, m.header);
  s.value(m.height);
  s.value(m.width);
  s.sequence(m.fields, [&](auto& field) {
    s.text(field.name);
    s.value(field.offset);
    s.value(field.datatype);
    s.value(field.count);
  });
  s.value(m.is_bigendian);
  s.value(m.point_step);
  s.value(m.row_step);
  s.sequence(m.data);
  s.value(m.is_dense);
}

template <class S, class M>
void odometryLayout(S& s, M& m)
{
  headerLayout(s, m.header);
  s.text(m.child_frame_id);
  poseLayout(s, m.pose.pose);
  s.array(m.pose.covariance);
  twistLayout(s, m.twist.twist);
  s.array(m.twist.covariance);
}

template <class S, class M>
void poseStampedLayout(S& s, M& m)
{
  headerLayout(s, m.header);
  poseLayout(s, m.pose);
}

template <class S, class M>
void imuLayout(S& s, M& m)
{
  headerLayout(s, m.header);
  quaternionLayout(s, m.orientation);
  s.array(m.orientation_covariance);
  vector3Layout(s, m.angular_velocity);
  s.array(m.angular_velocity_covariance);
  vector3Layout(s, m.linear_acceleration);
  s.array(m.linear_acceleration_covariance);
}

template <class S, class M>
void tfMessageLayout(S& s, M& m)
{
  s.sequence(m.transforms, [&](auto& transform) {
    headerLayout(s, transform.header);
    s.text(transform.child_frame_id);
    vector3Layout(s, transform.transform.translation);
    quaternionLayout(s, transform.transform.rotation);
  });
}

// The layouts by message type (const or not: the writer's messages are const).
template <class S>
void layout(S& s, sensor_msgs::JointState& m)
{
  jointStateLayout(s, m);
}
template <class S>
void layout(S& s, const sensor_msgs::JointState& m)
{
  jointStateLayout(s, m);
}
template <class S>
void layout(S& s, sensor_msgs::LaserScan& m)
{
  laserScanLayout(s, m);
}
template <class S>
void layout(S& s, const sensor_msgs::LaserScan& m)
{
  laserScanLayout(s, m);
}
template <class S>
void layout(S& s, sensor_msgs::PointCloud2& m)
{
  pointCloud2Layout(s, m);
}
template <class S>
void layout(S& s, const sensor_msgs::PointCloud2& m)
{
  pointCloud2Layout(s, m);
}
template <class S>
void layout(S& s, nav_msgs::Odometry& m)
{
  odometryLayout(s, m);
}
template <class S>
void layout(S& s, const nav_msgs::Odometry& m)
{
  odometryLayout(s, m);
}
template <class S>
void layout(S& s, geometry_msgs::PoseStamped& m)
{
  poseStampedLayout(s, m);
}
template <class S>
void layout(S& s, const geometry_msgs::PoseStamped& m)
{
  poseStampedLayout(s, m);
}
template <class S>
void layout(S& s, sensor_msgs::Imu& m)
{
  imuLayout(s, m);
}
template <class S>
void layout(S& s, const sensor_msgs::Imu& m)
{
  imuLayout(s, m);
}
template <class S>
void layout(S& s, tf2_msgs::TFMessage& m)
{
  tfMessageLayout(s, m);
}
template <class S>
void layout(S& s, const tf2_msgs::TFMessage& m)
{
  tfMessageLayout(s, m);
}

// The std_msgs number types (Bool, Float32/64, Int8..64, UInt8..64): their one field, `data`.
template <class M>
struct IsStdNumber : std::false_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Bool_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Float32_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Float64_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Int8_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Int16_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Int32_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::Int64_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::UInt8_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::UInt16_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::UInt32_<A>> : std::true_type
{
};
template <class A>
struct IsStdNumber<std_msgs::UInt64_<A>> : std::true_type
{
};

template <class S, class M>
std::enable_if_t<IsStdNumber<std::remove_const_t<M>>::value> layout(S& s, M& m)
{
  s.value(m.data);
}

}  // namespace cdr
}  // namespace odometry_calibration
