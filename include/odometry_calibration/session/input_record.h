// What a session's pair collectors were given (after admission), in arrival order: raw encoder
// readings with their stamps, scans, sensor poses and the ends of the data (flush), so that
// the session can pair them again at another time offset (calibration_session.h, calibrate()).
// Lossless: every value is kept exactly (a scan's ranges as float when every one round-trips,
// else as double). Bounded memory: the scans, the bulk, are spilled to an unlinked scratch file
// (in the session's output directory, else in the system's temporary directory), so that the
// memory holds only the small inputs and one index entry per input (about 6 MB per hour of
// 10 Hz scans and 50 Hz encoder readings of two joints; the file 2 953 bytes per 720-ray
// LaserScan, 106 MB per hour at 10 Hz; a scan made from a cloud keeps its double ranges, ray
// times and bearings, 24 bytes per ray).
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/geometry/se2.h"
#include "odometry_calibration/scan/scan.h"

namespace odometry_calibration {

class ScanSpillFile;

/// One recorded input: what it is, its stamp [s] and where its data is.
struct RecordedInput
{
  enum class Kind : std::uint8_t
  {
    kEncoders,
    kScan,
    kSensorPose,
    kFlush,  ///< the end of the data: waiting scans were paired
  };
  double stamp_s = 0.0;
  std::uint32_t index = 0;  ///< into the encoder readings, the scans or the poses of its kind
  Kind kind = Kind::kFlush;
};

/// What a replay calls for each recorded input, in arrival order (all must be set).
struct RecordedInputVisitor
{
  std::function<void(double stamp_s, const Eigen::VectorXd& raw)> encoders;
  std::function<void(double stamp_s, const Scan& scan)> scan;
  std::function<void(double stamp_s, const Pose2& T_world_sensor,
                     const Eigen::Matrix3d& covariance)>
      sensor_pose;
  std::function<void()> flush;
};

/// A copy of a record's inputs [first, end) taken at one instant: replayed without the
/// record's owner's lock (the scans are read back from the spill file, which only grows).
class InputRecordView
{
public:
  /// Calls `visitor` for each input in order. Throws std::runtime_error when the spill file
  /// cannot be read back.
  void replay(const RecordedInputVisitor& visitor) const;
  std::size_t end() const { return end_; }  ///< the record's size when the view was taken
  std::size_t size() const { return inputs_.size(); }

private:
  friend class InputRecord;
  std::size_t end_ = 0;
  std::vector<RecordedInput> inputs_;
  std::vector<double> encoder_values_;  ///< `channels_` per reading
  std::size_t channels_ = 0;
  std::uint32_t first_encoder_ = 0, first_pose_ = 0, first_scan_ = 0;
  std::vector<std::uint64_t> scan_offsets_;  ///< into the spill file, one more than scans
  std::vector<Pose2> poses_;
  std::vector<Eigen::Matrix3d> covariances_;
  std::shared_ptr<const ScanSpillFile> spill_;
};

/// The record itself (not thread-safe: its owner locks it).
class InputRecord
{
public:
  /// `spill_directory`: where the scans' scratch file is made (empty: the system's temporary
  /// directory). Throws std::runtime_error when it cannot be made.
  explicit InputRecord(const std::string& spill_directory);
  ~InputRecord();
  InputRecord(const InputRecord&) = delete;
  InputRecord& operator=(const InputRecord&) = delete;

  void addEncoders(double stamp_s, const Eigen::VectorXd& raw);
  /// Throws std::runtime_error when the spill file cannot be written (the disk is full).
  void addScan(double stamp_s, const Scan& scan);
  void addSensorPose(double stamp_s, const Pose2& T_world_sensor,
                     const Eigen::Matrix3d& covariance);
  void addFlush();
  /// Forgets everything (a new, empty spill file).
  void clear();
  std::size_t size() const { return inputs_.size(); }
  /// The memory the record holds [bytes] (its vectors' capacity and the write buffer).
  std::size_t memoryBytes() const;
  /// The scans' bytes in the spill file [bytes].
  std::uint64_t spilledBytes() const;
  /// The inputs [first, size()) as they are now. Throws std::runtime_error when the spill
  /// file cannot be written.
  InputRecordView view(std::size_t first = 0);

private:
  std::string spill_directory_;
  std::vector<RecordedInput> inputs_;
  std::vector<double> encoder_values_;
  std::size_t channels_ = 0;
  std::vector<std::uint64_t> scan_offsets_{0};
  std::vector<Pose2> poses_;
  std::vector<Eigen::Matrix3d> covariances_;
  std::shared_ptr<ScanSpillFile> spill_;
};

}  // namespace odometry_calibration
