// The CDR reader and writer (cdr_reader.h, cdr_writer.h): every message type round trip in both
// endiannesses and at every alignment a string before it can cause, the bytes as ROS 2 lays
// them out, and bad bytes refused without a crash or a large allocation.
#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>

#include <gtest/gtest.h>

#include "odometry_calibration/bag/cdr_reader.h"
#include "odometry_calibration/bag_writers/cdr_writer.h"

// The largest single allocation since the last reset: a corrupted count must not make one.
static std::atomic<std::size_t> g_largest_allocation{0};

void* operator new(std::size_t size)
{
  std::size_t largest = g_largest_allocation.load();
  while (size > largest && !g_largest_allocation.compare_exchange_weak(largest, size)) {
  }
  if (void* p = std::malloc(size == 0 ? 1 : size))
    return p;
  throw std::bad_alloc();
}

// GCC takes the pair for a mismatch once inlined (its memory came from the operator new above).
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
#endif
void operator delete(void* p) noexcept
{
  std::free(p);
}

void operator delete(void* p, std::size_t) noexcept
{
  std::free(p);
}
#if defined(__GNUC__) && !defined(__clang__)
#pragma GCC diagnostic pop
#endif

namespace odometry_calibration {
namespace {

std_msgs::Header header(const std::string& frame)
{
  std_msgs::Header h;
  h.stamp.sec = 1700000123;
  h.stamp.nsec = 456789012;
  h.frame_id = frame;
  return h;
}

sensor_msgs::JointState jointState(const std::string& frame)
{
  sensor_msgs::JointState m;
  m.header = header(frame);
  m.name = {"left_wheel_joint", "", "right"};
  m.position = {1.5, -2.25, 1e-300};
  m.velocity = {0.5};
  return m;  // effort empty: an empty sequence of doubles
}

sensor_msgs::LaserScan laserScan(const std::string& frame)
{
  sensor_msgs::LaserScan m;
  m.header = header(frame);
  m.angle_min = -3.1f;
  m.angle_max = 3.1f;
  m.angle_increment = 0.01f;
  m.time_increment = 1e-5f;
  m.scan_time = 0.1f;
  m.range_min = 0.05f;
  m.range_max = 30.0f;
  m.ranges = {1.0f, 2.5f, 0.0f, 29.9f, 7.0f};
  m.intensities = {100.0f};
  return m;
}

sensor_msgs::PointCloud2 pointCloud(const std::string& frame)
{
  sensor_msgs::PointCloud2 m;
  m.header = header(frame);
  m.height = 1;
  m.width = 2;
  for (const char* name : {"x", "ring"}) {
    sensor_msgs::PointField f;
    f.name = name;
    f.offset = name[0] == 'x' ? 0 : 4;
    f.datatype = name[0] == 'x' ? 7 : 4;
    f.count = 1;
    m.fields.push_back(f);
  }
  m.is_bigendian = 0;
  m.point_step = 6;
  m.row_step = 12;
  m.data = {1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12};
  m.is_dense = 1;
  return m;
}

nav_msgs::Odometry odometry(const std::string& frame)
{
  nav_msgs::Odometry m;
  m.header = header(frame);
  m.child_frame_id = "base_link";
  m.pose.pose.position.x = 1.25;
  m.pose.pose.position.y = -3.5;
  m.pose.pose.orientation.z = 0.6;
  m.pose.pose.orientation.w = 0.8;
  for (std::size_t k = 0; k < 36; ++k) {
    m.pose.covariance[k] = 0.1 * static_cast<double>(k);
    m.twist.covariance[k] = -0.2 * static_cast<double>(k);
  }
  m.twist.twist.linear.x = 0.4;
  m.twist.twist.angular.z = -0.7;
  return m;
}

geometry_msgs::PoseStamped poseStamped(const std::string& frame)
{
  geometry_msgs::PoseStamped m;
  m.header = header(frame);
  m.pose.position.x = 2.0;
  m.pose.position.z = -1.0;
  m.pose.orientation.w = 1.0;
  return m;
}

sensor_msgs::Imu imu(const std::string& frame)
{
  sensor_msgs::Imu m;
  m.header = header(frame);
  m.orientation.w = 1.0;
  m.angular_velocity.z = 0.3;
  m.linear_acceleration.z = 9.81;
  for (std::size_t k = 0; k < 9; ++k) {
    m.orientation_covariance[k] = static_cast<double>(k);
    m.angular_velocity_covariance[k] = 2.0 * static_cast<double>(k);
    m.linear_acceleration_covariance[k] = 3.0 * static_cast<double>(k);
  }
  return m;
}

tf2_msgs::TFMessage tfMessage(const std::string& frame)
{
  tf2_msgs::TFMessage m;
  for (const char* child : {"base_link", "laser"}) {
    geometry_msgs::TransformStamped t;
    t.header = header(frame);
    t.child_frame_id = child;
    t.transform.translation.x = 0.25;
    t.transform.rotation.w = 1.0;
    m.transforms.push_back(t);
  }
  return m;
}

/// Frames of 0 to 8 characters: every alignment the fields after the header can fall on.
std::vector<std::string> frames()
{
  std::vector<std::string> result;
  for (std::size_t n = 0; n <= 8; ++n)
    result.push_back(std::string(n, 'f'));
  return result;
}

template <typename M>
void expectRoundTrip(const M& original)
{
  for (const bool big_endian : {false, true}) {
    const std::vector<std::uint8_t> bytes = writeCdr(original, big_endian);
    ASSERT_EQ(bytes[1], big_endian ? 0 : 1);
    M read;
    readCdr(bytes.data(), bytes.size(), read);
    EXPECT_TRUE(read == original) << ros::message_traits::datatype<M>() << " frame '"
                                  << original.header.frame_id << "' big-endian " << big_endian;
  }
}

TEST(Cdr, EveryTypeRoundTripsInBothEndiannessesAtEveryAlignment)
{
  for (const std::string& frame : frames()) {
    expectRoundTrip(jointState(frame));
    expectRoundTrip(laserScan(frame));
    expectRoundTrip(pointCloud(frame));
    expectRoundTrip(odometry(frame));
    expectRoundTrip(poseStamped(frame));
    expectRoundTrip(imu(frame));
    for (const bool big_endian : {false, true}) {
      const tf2_msgs::TFMessage original = tfMessage(frame);
      const std::vector<std::uint8_t> bytes = writeCdr(original, big_endian);
      tf2_msgs::TFMessage read;
      readCdr(bytes.data(), bytes.size(), read);
      EXPECT_TRUE(read == original) << "TFMessage frame '" << frame << "'";
    }
  }
}

TEST(Cdr, StdMsgsNumbersRoundTrip)
{
  for (const bool big_endian : {false, true}) {
    std_msgs::Float64 f;
    f.data = -1.25e-7;
    std::vector<std::uint8_t> bytes = writeCdr(f, big_endian);
    ASSERT_EQ(bytes.size(), 12u);  // the header, then the float64 aligned to 8 from byte 4
    std_msgs::Float64 read_f;
    readCdr(bytes.data(), bytes.size(), read_f);
    EXPECT_EQ(read_f.data, f.data);
    std_msgs::Int32 i;
    i.data = -123456;
    bytes = writeCdr(i, big_endian);
    std_msgs::Int32 read_i;
    readCdr(bytes.data(), bytes.size(), read_i);
    EXPECT_EQ(read_i.data, i.data);
    std_msgs::Bool b;
    b.data = 1;
    bytes = writeCdr(b, big_endian);
    EXPECT_EQ(bytes.size(), 5u);
    std_msgs::UInt16 cut;
    EXPECT_THROW(readCdr(bytes.data(), bytes.size(), cut), CdrError);
  }
}

TEST(Cdr, PoseStampedHasRos2sLayout)
{
  // Little-endian; the header's int32 sec and uint32 nanosec, the frame "ab" with its NUL
  // (length 3), padding to 8 from the end of the encapsulation header (byte 20), 7 float64.
  geometry_msgs::PoseStamped m;
  m.header.stamp.sec = 0x01020304;
  m.header.stamp.nsec = 0x05060708;
  m.header.frame_id = "ab";
  m.pose.position.x = 1.0;
  const std::vector<std::uint8_t> bytes = writeCdr(m);
  const std::vector<std::uint8_t> start = {0, 1, 0, 0, 4, 3, 2,   1,   8, 7,
                                           6, 5, 3, 0, 0, 0, 'a', 'b', 0, 0};
  ASSERT_EQ(bytes.size(), 4u + 16u + 7u * 8u);
  EXPECT_TRUE(std::equal(start.begin(), start.end(), bytes.begin()));
  EXPECT_EQ(bytes[20 + 7], 0x3f);  // 1.0 = 3ff0000000000000, little-endian
  EXPECT_EQ(bytes[20 + 6], 0xf0);
  const std::vector<std::uint8_t> big = writeCdr(m, true);
  const std::vector<std::uint8_t> big_start = {0, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 0, 0, 0, 3};
  EXPECT_TRUE(std::equal(big_start.begin(), big_start.end(), big.begin()));
  EXPECT_EQ(big[20], 0x3f);
}

TEST(Cdr, EmptySequencesAreNotAlignedToTheirElements)
{
  // JointState, frame "" (length 1): names count at 12, count 0 of float64 at 16, not padded.
  sensor_msgs::JointState m;
  const std::vector<std::uint8_t> bytes = writeCdr(m);
  EXPECT_EQ(bytes.size(), 4u + 8u + 5u + 3u + 4u * 4u);
}

template <typename M>
void expectEveryCutRefused(const M& original)
{
  for (const bool big_endian : {false, true}) {
    const std::vector<std::uint8_t> bytes = writeCdr(original, big_endian);
    for (std::size_t size = 0; size < bytes.size(); ++size) {
      const std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + size);
      M read;
      EXPECT_THROW(readCdr(cut.data(), cut.size(), read), CdrError)
          << ros::message_traits::datatype<M>() << " cut to " << size << " bytes";
    }
  }
}

TEST(Cdr, EveryCutMessageIsRefused)
{
  expectEveryCutRefused(jointState("odom"));
  expectEveryCutRefused(laserScan("laser"));
  expectEveryCutRefused(pointCloud("velodyne"));
  expectEveryCutRefused(odometry("odom"));
  expectEveryCutRefused(poseStamped("map"));
  expectEveryCutRefused(imu("imu"));
  expectEveryCutRefused(tfMessage("odom"));
}

TEST(Cdr, TheErrorNamesWhatWasCutAndWhere)
{
  // A pose cut in its last float64 (the 8 bytes before the end), and a scan cut in its ranges,
  // whose count then claims more than the bytes hold.
  const std::vector<std::uint8_t> pose = writeCdr(poseStamped("map"));
  geometry_msgs::PoseStamped read_pose;
  try {
    readCdr(pose.data(), pose.size() - 3, read_pose);
    FAIL() << "a cut pose was read";
  } catch (const CdrError& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("geometry_msgs/PoseStamped of " + std::to_string(pose.size() - 3) +
                        " bytes is cut off at byte " + std::to_string(pose.size() - 8)),
              std::string::npos)
        << text;
  }
  const std::vector<std::uint8_t> scan = writeCdr(laserScan("laser"));
  sensor_msgs::LaserScan read_scan;
  try {
    readCdr(scan.data(), scan.size() - 12, read_scan);
    FAIL() << "a cut scan was read";
  } catch (const CdrError& error) {
    const std::string text = error.what();
    EXPECT_NE(text.find("claims 5 elements at byte"), std::string::npos) << text;
  }
}

TEST(Cdr, ACountBeyondTheBytesIsRefusedBeforeAllocating)
{
  for (const bool big_endian : {false, true}) {
    sensor_msgs::LaserScan scan = laserScan("laser");
    std::vector<std::uint8_t> bytes = writeCdr(scan, big_endian);
    // The ranges' count sits before the 5 ranges and the intensities (count 1, one float).
    const std::size_t count_at = bytes.size() - 4 - 4 - 5 * 4 - 4;
    for (std::size_t k = 0; k < 4; ++k)
      bytes[count_at + k] = k == (big_endian ? 0 : 3) ? 0x7f : 0xff;
    sensor_msgs::LaserScan read;
    g_largest_allocation = 0;
    EXPECT_THROW(readCdr(bytes.data(), bytes.size(), read), CdrError);
    EXPECT_LT(g_largest_allocation.load(), 4096u);
    // The same for a sequence of strings (each at least 4 bytes).
    sensor_msgs::JointState joints = jointState("");
    bytes = writeCdr(joints, big_endian);
    for (std::size_t k = 0; k < 4; ++k)  // names' count: after the stamp and frame ""
      bytes[4 + 8 + 8 + k] = 0xff;
    sensor_msgs::JointState read_joints;
    g_largest_allocation = 0;
    EXPECT_THROW(readCdr(bytes.data(), bytes.size(), read_joints), CdrError);
    EXPECT_LT(g_largest_allocation.load(), 4096u);
  }
}

TEST(Cdr, OtherEncapsulationsAndBrokenStringsAreRefused)
{
  std::vector<std::uint8_t> bytes = writeCdr(poseStamped("map"));
  geometry_msgs::PoseStamped read;
  for (const std::uint8_t kind : {2, 3, 7}) {  // PL_CDR_BE, PL_CDR_LE, unknown
    bytes[1] = kind;
    EXPECT_THROW(readCdr(bytes.data(), bytes.size(), read), CdrError);
  }
  bytes[1] = 1;
  bytes[16 + 3] = 'x';  // the frame's NUL ("map" + NUL at 16..19)
  EXPECT_THROW(readCdr(bytes.data(), bytes.size(), read), CdrError);
  bytes = writeCdr(poseStamped("map"));
  bytes[7] = 0x80;  // a negative stamp: ROS 1's time cannot hold it
  EXPECT_THROW(readCdr(bytes.data(), bytes.size(), read), CdrError);
}

}  // namespace
}  // namespace odometry_calibration
