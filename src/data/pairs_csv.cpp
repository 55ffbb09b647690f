#include "odometry_calibration/data/pairs_csv.h"

#include <fcntl.h>
#include <unistd.h>

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <functional>
#include <iterator>
#include <sstream>

#include <Eigen/Cholesky>

#include "odometry_calibration/common/atomic_file.h"

namespace odometry_calibration {
namespace {

const char* kMagic = "# odometry_calibration pairs v1";
const char* kColumns =
    "start_stamp_s,end_stamp_s,x_m,y_m,theta_rad,cov_xx,cov_xy,cov_xtheta,cov_yy,cov_ytheta,"
    "cov_thetatheta,samples";

/// Appends `value` as printf's "%.17g" writes it (round trip exact), through std::to_chars:
/// a 60-minute bag's pairs file holds half a million numbers, and snprintf took 0.5 s of them.
void appendNumber(std::string& text, double value)
{
  char buffer[40];
  const std::to_chars_result written =
      std::to_chars(buffer, buffer + sizeof(buffer), value, std::chars_format::general, 17);
  text.append(buffer, written.ptr);
}

bool parseNumber(const std::string& text, double* value)
{
  char* end = nullptr;
  errno = 0;
  *value = std::strtod(text.c_str(), &end);
  return !text.empty() && errno == 0 && end == text.c_str() + text.size() && std::isfinite(*value);
}

std::vector<std::string> split(const std::string& text, char separator)
{
  std::vector<std::string> parts;
  std::string part;
  std::istringstream stream(text);
  while (std::getline(stream, part, separator))
    parts.push_back(part);
  if (!text.empty() && text.back() == separator)
    parts.emplace_back();
  return parts;
}

}  // namespace

std::string pairsCsvHeader(const JointLayout& joints)
{
  std::string header = std::string(kMagic) + "\n# joints:";
  for (std::size_t j = 0; j < joints.names.size(); ++j) {
    header += " " + joints.names[j] + ":" +
              (joints.kinds[j] == EncoderKind::kIncremental ? "incremental" : "absolute");
  }
  return header + "\n" + kColumns + "\n";
}

std::string pairsCsvRow(const MotionPair& pair)
{
  std::string row;
  const Eigen::Matrix3d& c = pair.covariance;
  for (const double value :
       {pair.start_stamp_s, pair.end_stamp_s, pair.sensor_motion.x(), pair.sensor_motion.y(),
        pair.sensor_motion.theta(), c(0, 0), c(0, 1), c(0, 2), c(1, 1), c(1, 2), c(2, 2)}) {
    appendNumber(row, value);
    row += ',';
  }
  for (std::size_t k = 0; k < pair.encoder_samples.size(); ++k) {
    const EncoderSample& sample = pair.encoder_samples[k];
    if (k > 0)
      row += ';';
    appendNumber(row, sample.stamp_s);
    for (Eigen::Index j = 0; j < sample.values.size(); ++j) {
      row += ' ';
      appendNumber(row, sample.values(j));
    }
  }
  return row + "\n";
}

namespace {

/// Reports a malformed line (throws, naming the file and the line).
using LineFailure = std::function<void(const std::string& what)>;

/// The joints of a '# joints: <name>:<kind> ...' line into `joints`.
void parseJointsLine(const std::string& line, const LineFailure& fail, JointLayout& joints)
{
  std::istringstream entries(line.substr(9));
  std::string entry;
  while (entries >> entry) {
    const std::size_t colon = entry.rfind(':');
    const std::string kind = colon == std::string::npos ? "" : entry.substr(colon + 1);
    if (kind != "incremental" && kind != "absolute") {
      fail("joints: expected <name>:incremental or <name>:absolute, got '" + entry + "'");
    }
    joints.names.push_back(entry.substr(0, colon));
    joints.kinds.push_back(kind == "incremental" ? EncoderKind::kIncremental
                                                 : EncoderKind::kAbsolute);
  }
}

/// The samples field: ';'-separated samples, each a stamp and `joint_count` values.
std::vector<EncoderSample> parseSamples(const std::string& field, std::size_t joint_count,
                                        const LineFailure& fail)
{
  std::vector<EncoderSample> samples;
  for (const std::string& text : split(field, ';')) {
    std::istringstream stream(text);
    std::vector<double> numbers;
    std::string token;
    while (stream >> token) {
      double value = 0.0;
      if (!parseNumber(token, &value))
        fail("samples: '" + token + "' is not a number");
      numbers.push_back(value);
    }
    if (numbers.size() != joint_count + 1) {
      fail("samples: each sample needs a stamp and " + std::to_string(joint_count) +
           " joint values, got '" + text + "'");
    }
    samples.push_back(
        {numbers[0], Eigen::Map<const Eigen::VectorXd>(numbers.data() + 1,
                                                       static_cast<Eigen::Index>(joint_count))});
  }
  return samples;
}

/// Refuses values no real pair has, which a fit would take for data: a keyframe
/// motion beyond kMaxMotionM, a covariance that is not positive definite or beyond
/// kMaxVarianceUnits (its whitening would be NaN or nothing), a joint value beyond
/// kMaxJointValue (a raw 32-bit counter reaches 4.3e9).
void checkPairValues(const MotionPair& pair, const LineFailure& fail)
{
  constexpr double kMaxMotionM = 1e3, kMaxVarianceUnits = 1e6, kMaxJointValue = 1e15;
  const Pose2& motion = pair.sensor_motion;
  if (std::abs(motion.x()) > kMaxMotionM || std::abs(motion.y()) > kMaxMotionM ||
      std::abs(motion.theta()) > kMaxMotionM) {
    fail("the sensor motion (" + std::to_string(motion.x()) + ", " + std::to_string(motion.y()) +
         ", " + std::to_string(motion.theta()) + ") is beyond 1000 m or rad: no keyframe pair");
  }
  if (pair.covariance.llt().info() != Eigen::Success ||
      !(pair.covariance.diagonal().minCoeff() > 0.0) ||
      pair.covariance.diagonal().maxCoeff() > kMaxVarianceUnits) {
    fail("the covariance is not positive definite with variances up to 1e6");
  }
  for (const EncoderSample& sample : pair.encoder_samples) {
    if (sample.values.size() > 0 && sample.values.cwiseAbs().maxCoeff() > kMaxJointValue)
      fail("a joint value beyond 1e15 at stamp " + std::to_string(sample.stamp_s));
  }
}

/// One row: stamps, motion, covariance (upper triangle) and the samples.
MotionPair parsePairRow(const std::string& line, std::size_t joint_count, const LineFailure& fail)
{
  const auto fields = split(line, ',');
  if (fields.size() != 12) {
    fail("expected 12 comma-separated fields, found " + std::to_string(fields.size()));
  }
  double values[11];
  for (int i = 0; i < 11; ++i) {
    if (!parseNumber(fields[static_cast<std::size_t>(i)], &values[i])) {
      fail("field " + std::to_string(i + 1) + ": expected a finite number, got '" +
           fields[static_cast<std::size_t>(i)] + "'");
    }
  }
  MotionPair pair;
  pair.start_stamp_s = values[0];
  pair.end_stamp_s = values[1];
  pair.sensor_motion = Pose2(values[2], values[3], values[4]);
  pair.covariance << values[5], values[6], values[7], values[6], values[8], values[9], values[7],
      values[9], values[10];
  pair.encoder_samples = parseSamples(fields[11], joint_count, fail);
  if (pair.encoder_samples.size() < 2)
    fail("a pair needs at least two encoder samples");
  checkPairValues(pair, fail);
  return pair;
}

}  // namespace

PairsFile parsePairsCsv(std::istream& input, const std::string& source)
{
  PairsFile file;
  bool has_joints = false;
  std::string line;
  std::size_t number_of_line = 0;
  const LineFailure fail = [&](const std::string& what) {
    throw std::runtime_error(source + ":" + std::to_string(number_of_line) + ": " + what);
  };
  while (std::getline(input, line)) {
    ++number_of_line;
    if (!line.empty() && line.back() == '\r')
      line.pop_back();
    if (line.empty() || line == kColumns)
      continue;
    if (line[0] == '#') {
      if (line.rfind("# joints:", 0) == 0) {
        parseJointsLine(line, fail, file.joints);
        has_joints = true;
      }
      continue;
    }
    if (!has_joints)
      fail("a '# joints: ...' line must come before the rows");
    file.pairs.push_back(parsePairRow(line, file.joints.names.size(), fail));
  }
  if (!has_joints) {
    throw std::runtime_error(source + (number_of_line == 0
                                           ? ": the file is empty"
                                           : ": not a pairs file: the '# joints: ...' line is "
                                             "missing"));
  }
  return file;
}

PairsFile readPairsCsv(const std::string& path)
{
  std::ifstream input(path);
  if (!input)
    throw std::runtime_error("cannot open pairs file '" + path + "'");
  return parsePairsCsv(input, path);
}

PairsFile readPairsCsvFiles(const std::vector<std::string>& paths)
{
  PairsFile all;
  for (const std::string& path : paths) {
    PairsFile file = readPairsCsv(path);
    if (all.joints.names.empty()) {
      all.joints = file.joints;
    } else if (file.joints.names != all.joints.names) {
      throw std::invalid_argument("'" + path + "' has other joints than the first file");
    }
    all.pairs.insert(all.pairs.end(), file.pairs.begin(), file.pairs.end());
  }
  return all;
}

TrainTestPairs readTrainTestPairsCsv(const std::vector<std::string>& training_paths,
                                     const std::vector<std::string>& testing_paths)
{
  TrainTestPairs pairs{readPairsCsvFiles(training_paths), readPairsCsvFiles(testing_paths)};
  if (pairs.testing.joints.names != pairs.training.joints.names) {
    throw std::invalid_argument("the test pairs have other joints than the training pairs");
  }
  return pairs;
}

void writePairsCsv(const std::string& path, const PairsFile& file)
{
  std::string text = pairsCsvHeader(file.joints);
  for (const MotionPair& pair : file.pairs)
    text += pairsCsvRow(pair);
  writeFileAtomically(path, text);
}

PairsCsvAppender::PairsCsvAppender(const std::string& path, const JointLayout& joints) : path_(path)
{
  std::ifstream existing(path, std::ios::binary);
  if (existing) {
    std::string content((std::istreambuf_iterator<char>(existing)), {});
    existing.close();
    if (!content.empty() && content.back() != '\n') {
      // A row cut off by a crash: drop it, keep everything before.
      content.erase(
          content.find_last_of('\n') == std::string::npos ? 0 : content.find_last_of('\n') + 1);
      dropped_partial_line_ = true;
      writeFileAtomically(path, content);
    }
    if (!content.empty()) {
      std::istringstream stream(content);
      PairsFile file = parsePairsCsv(stream, path);
      if (file.joints.names != joints.names || file.joints.kinds != joints.kinds) {
        throw std::runtime_error("pairs file '" + path +
                                 "' was collected with other joints; use another file");
      }
      existing_ = std::move(file.pairs);
    }
  }
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
  if (fd_ < 0) {
    throw std::runtime_error("cannot write pairs file '" + path + "': " + std::strerror(errno));
  }
  if (existing_.empty() && ::lseek(fd_, 0, SEEK_END) == 0) {
    try {
      appendText(pairsCsvHeader(joints));
    } catch (...) {
      ::close(fd_);
      throw;
    }
  }
}

void PairsCsvAppender::append(const MotionPair& pair)
{
  appendText(pairsCsvRow(pair));
}

void PairsCsvAppender::appendText(const std::string& text)
{
  // A failed write (full disk, a file size limit, a read-only remount) is cut back to where the
  // file ended, so that the file never keeps half a row.
  const off_t end = ::lseek(fd_, 0, SEEK_END);
  std::size_t written = 0;
  int error = 0;
  while (end >= 0 && written < text.size()) {
    const ssize_t n = ::write(fd_, text.data() + written, text.size() - written);
    if (n < 0 && errno == EINTR)
      continue;
    if (n <= 0) {
      error = n < 0 ? errno : ENOSPC;
      break;
    }
    written += static_cast<std::size_t>(n);
  }
  if (end < 0)
    error = errno;
  else if (error == 0 && ::fdatasync(fd_) != 0)
    error = errno;
  if (error != 0) {
    if (end >= 0 && ::ftruncate(fd_, end) != 0) {
      // Nothing more to do: the reader drops a last row without a line end.
    }
    throw std::runtime_error("cannot append to pairs file '" + path_ +
                             "': " + std::strerror(error));
  }
}

PairsCsvAppender::~PairsCsvAppender()
{
  if (fd_ >= 0)
    ::close(fd_);
}

}  // namespace odometry_calibration
