#include "odometry_calibration/session/input_record.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <filesystem>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// Scans are written to the file in blocks of about this size [bytes].
constexpr std::size_t kWriteBlockBytes = 1 << 20;

/// The numbers of a scan that are not arrays, in the file's order.
constexpr std::size_t kScanHeaderValues = 5;

template <typename T>
void appendBytes(const T* values, std::size_t count, std::vector<char>* out)
{
  const char* bytes = reinterpret_cast<const char*>(values);
  out->insert(out->end(), bytes, bytes + count * sizeof(T));
}

template <typename T>
const char* takeBytes(const char* in, std::size_t count, std::vector<T>* values)
{
  values->resize(count);
  std::memcpy(values->data(), in, count * sizeof(T));
  return in + count * sizeof(T);
}

/// Whether every range survives float and back exactly (NaN stays NaN).
bool rangesFitFloat(const std::vector<double>& ranges_m)
{
  for (const double range_m : ranges_m) {
    const double back = static_cast<double>(static_cast<float>(range_m));
    if (!(back == range_m) && !(std::isnan(range_m) && std::isnan(back)))
      return false;
  }
  return true;
}

/// `scan` as the file holds it: header values, array sizes, a float flag, then the arrays.
void encodeScan(const Scan& scan, std::vector<char>* out)
{
  const double header[kScanHeaderValues] = {scan.angle_min_rad, scan.angle_increment_rad,
                                            scan.range_min_m, scan.range_max_m,
                                            scan.time_increment_s};
  const std::uint64_t sizes[4] = {scan.ranges_m.size(), scan.valid.size(), scan.ray_times_s.size(),
                                  scan.ray_angles_rad.size()};
  const std::uint8_t as_float = rangesFitFloat(scan.ranges_m) ? 1 : 0;
  appendBytes(header, kScanHeaderValues, out);
  appendBytes(sizes, 4, out);
  appendBytes(&as_float, 1, out);
  if (as_float) {
    const std::vector<float> ranges(scan.ranges_m.begin(), scan.ranges_m.end());
    appendBytes(ranges.data(), ranges.size(), out);
  } else {
    appendBytes(scan.ranges_m.data(), scan.ranges_m.size(), out);
  }
  appendBytes(scan.valid.data(), scan.valid.size(), out);
  appendBytes(scan.ray_times_s.data(), scan.ray_times_s.size(), out);
  appendBytes(scan.ray_angles_rad.data(), scan.ray_angles_rad.size(), out);
}

Scan decodeScan(const std::vector<char>& bytes)
{
  Scan scan;
  std::vector<double> header;
  std::vector<std::uint64_t> sizes;
  std::vector<std::uint8_t> as_float;
  const char* in = takeBytes(bytes.data(), kScanHeaderValues, &header);
  in = takeBytes(in, 4, &sizes);
  in = takeBytes(in, 1, &as_float);
  scan.angle_min_rad = header[0];
  scan.angle_increment_rad = header[1];
  scan.range_min_m = header[2];
  scan.range_max_m = header[3];
  scan.time_increment_s = header[4];
  if (as_float[0]) {
    std::vector<float> ranges;
    in = takeBytes(in, sizes[0], &ranges);
    scan.ranges_m.assign(ranges.begin(), ranges.end());
  } else {
    in = takeBytes(in, sizes[0], &scan.ranges_m);
  }
  in = takeBytes(in, sizes[1], &scan.valid);
  in = takeBytes(in, sizes[2], &scan.ray_times_s);
  takeBytes(in, sizes[3], &scan.ray_angles_rad);
  return scan;
}

}  // namespace

/// The scans' scratch file: unlinked as soon as it is made (nothing is left behind, also after
/// a crash), appended through a write buffer, read back at any written offset.
class ScanSpillFile
{
public:
  explicit ScanSpillFile(const std::string& directory)
  {
    const std::string base =
        directory.empty() ? std::filesystem::temp_directory_path().string() : directory;
    std::string path = base + "/.odometry_calibration_inputs-XXXXXX";
    fd_ = ::mkostemp(path.data(), O_CLOEXEC);  // not inherited by gnuplot and the like
    if (fd_ < 0) {
      throw std::runtime_error("cannot make the input record's scratch file in " + base + ": " +
                               std::strerror(errno));
    }
    ::unlink(path.c_str());
    buffer_.reserve(kWriteBlockBytes);
  }
  ~ScanSpillFile() { ::close(fd_); }
  ScanSpillFile(const ScanSpillFile&) = delete;
  ScanSpillFile& operator=(const ScanSpillFile&) = delete;

  /// Appends `bytes` (written once the buffer is full, or by sync()).
  void append(const std::vector<char>& bytes)
  {
    if (buffer_.size() + bytes.size() > kWriteBlockBytes)
      sync();  // the buffer keeps its one block of capacity
    buffer_.insert(buffer_.end(), bytes.begin(), bytes.end());
  }
  /// Writes the buffer to the file.
  void sync()
  {
    std::size_t done = 0;
    while (done < buffer_.size()) {
      const ssize_t wrote = ::pwrite(fd_, buffer_.data() + done, buffer_.size() - done,
                                     static_cast<off_t>(written_ + done));
      if (wrote < 0 && errno == EINTR)
        continue;
      if (wrote <= 0) {
        throw std::runtime_error(std::string("cannot write the input record's scratch file: ") +
                                 std::strerror(errno));
      }
      done += static_cast<std::size_t>(wrote);
    }
    written_ += buffer_.size();
    buffer_.clear();
  }
  /// The bytes [offset, offset + length), written by sync() already.
  std::vector<char> read(std::uint64_t offset, std::size_t length) const
  {
    std::vector<char> bytes(length);
    std::size_t done = 0;
    while (done < length) {
      const ssize_t got =
          ::pread(fd_, bytes.data() + done, length - done, static_cast<off_t>(offset + done));
      if (got < 0 && errno == EINTR)
        continue;
      if (got <= 0)
        throw std::runtime_error("cannot read the input record's scratch file back");
      done += static_cast<std::size_t>(got);
    }
    return bytes;
  }
  std::size_t bufferBytes() const { return buffer_.capacity(); }

private:
  int fd_ = -1;
  std::uint64_t written_ = 0;
  std::vector<char> buffer_;
};

InputRecord::InputRecord(const std::string& spill_directory)
    : spill_directory_(spill_directory), spill_(std::make_shared<ScanSpillFile>(spill_directory))
{
}

InputRecord::~InputRecord() = default;

void InputRecord::addEncoders(double stamp_s, const Eigen::VectorXd& raw)
{
  if (encoder_values_.empty())
    channels_ = static_cast<std::size_t>(raw.size());
  if (static_cast<std::size_t>(raw.size()) != channels_)
    throw std::invalid_argument("an encoder reading of another number of joints");
  const std::size_t readings = channels_ == 0 ? 0 : encoder_values_.size() / channels_;
  inputs_.push_back(
      {stamp_s, static_cast<std::uint32_t>(readings), RecordedInput::Kind::kEncoders});
  encoder_values_.insert(encoder_values_.end(), raw.data(), raw.data() + raw.size());
}

void InputRecord::addScan(double stamp_s, const Scan& scan)
{
  std::vector<char> bytes;
  encodeScan(scan, &bytes);
  spill_->append(bytes);
  inputs_.push_back(
      {stamp_s, static_cast<std::uint32_t>(scan_offsets_.size() - 1), RecordedInput::Kind::kScan});
  scan_offsets_.push_back(scan_offsets_.back() + bytes.size());
}

void InputRecord::addSensorPose(double stamp_s, const Pose2& T_world_sensor,
                                const Eigen::Matrix3d& covariance)
{
  inputs_.push_back(
      {stamp_s, static_cast<std::uint32_t>(poses_.size()), RecordedInput::Kind::kSensorPose});
  poses_.push_back(T_world_sensor);
  covariances_.push_back(covariance);
}

void InputRecord::addFlush()
{
  inputs_.push_back({0.0, 0, RecordedInput::Kind::kFlush});
}

void InputRecord::clear()
{
  spill_ = std::make_shared<ScanSpillFile>(spill_directory_);
  // Moved-from empty vectors: their memory is given back (assigning {} would keep it).
  inputs_ = std::vector<RecordedInput>();
  encoder_values_ = std::vector<double>();
  channels_ = 0;
  scan_offsets_ = std::vector<std::uint64_t>{0};
  poses_ = std::vector<Pose2>();
  covariances_ = std::vector<Eigen::Matrix3d>();
}

std::size_t InputRecord::memoryBytes() const
{
  return inputs_.capacity() * sizeof(RecordedInput) + encoder_values_.capacity() * sizeof(double) +
         scan_offsets_.capacity() * sizeof(std::uint64_t) + poses_.capacity() * sizeof(Pose2) +
         covariances_.capacity() * sizeof(Eigen::Matrix3d) + spill_->bufferBytes();
}

std::uint64_t InputRecord::spilledBytes() const
{
  return scan_offsets_.back();
}

InputRecordView InputRecord::view(std::size_t first)
{
  spill_->sync();
  InputRecordView view;
  view.end_ = inputs_.size();
  first = std::min(first, inputs_.size());
  view.inputs_.assign(inputs_.begin() + static_cast<std::ptrdiff_t>(first), inputs_.end());
  view.channels_ = channels_;
  view.spill_ = spill_;
  // Each kind's first index in the view, so that only its part of the data is copied.
  view.first_encoder_ =
      channels_ == 0 ? 0 : static_cast<std::uint32_t>(encoder_values_.size() / channels_);
  view.first_pose_ = static_cast<std::uint32_t>(poses_.size());
  view.first_scan_ = static_cast<std::uint32_t>(scan_offsets_.size() - 1);
  for (const RecordedInput& input : view.inputs_) {
    std::uint32_t& kind_first = input.kind == RecordedInput::Kind::kEncoders ? view.first_encoder_
                                : input.kind == RecordedInput::Kind::kSensorPose ? view.first_pose_
                                                                                 : view.first_scan_;
    if (input.kind != RecordedInput::Kind::kFlush)
      kind_first = std::min(kind_first, input.index);
  }
  view.encoder_values_.assign(encoder_values_.begin() + view.first_encoder_ * channels_,
                              encoder_values_.end());
  view.poses_.assign(poses_.begin() + view.first_pose_, poses_.end());
  view.covariances_.assign(covariances_.begin() + view.first_pose_, covariances_.end());
  view.scan_offsets_.assign(scan_offsets_.begin() + view.first_scan_, scan_offsets_.end());
  return view;
}

void InputRecordView::replay(const RecordedInputVisitor& visitor) const
{
  Eigen::VectorXd raw(static_cast<Eigen::Index>(channels_));
  for (const RecordedInput& input : inputs_) {
    switch (input.kind) {
      case RecordedInput::Kind::kEncoders: {
        const double* values = encoder_values_.data() + (input.index - first_encoder_) * channels_;
        raw = Eigen::Map<const Eigen::VectorXd>(values, static_cast<Eigen::Index>(channels_));
        visitor.encoders(input.stamp_s, raw);
        break;
      }
      case RecordedInput::Kind::kScan: {
        const std::size_t k = input.index - first_scan_;
        const std::uint64_t offset = scan_offsets_[k];
        visitor.scan(input.stamp_s,
                     decodeScan(spill_->read(offset, scan_offsets_[k + 1] - offset)));
        break;
      }
      case RecordedInput::Kind::kSensorPose:
        visitor.sensor_pose(input.stamp_s, poses_[input.index - first_pose_],
                            covariances_[input.index - first_pose_]);
        break;
      case RecordedInput::Kind::kFlush:
        visitor.flush();
        break;
    }
  }
}

}  // namespace odometry_calibration
