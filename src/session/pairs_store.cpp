#include "odometry_calibration/session/pairs_store.h"

#include <ctime>
#include <filesystem>

namespace odometry_calibration {
namespace {

namespace fs = std::filesystem;

/// Local date and time for archived file names, e.g. 20261123-140312.
std::string wallClockTag()
{
  const std::time_t now = std::time(nullptr);
  char tag[32];
  std::strftime(tag, sizeof(tag), "%Y%m%d-%H%M%S", std::localtime(&now));
  return tag;
}

}  // namespace

PairsStore::PairsStore(const std::string& directory, const JointLayout& joints, bool resume,
                       SessionLog log)
    : directory_(directory), joints_(joints), log_(std::move(log))
{
  if (!directory_.empty())
    open(resume);
}

PairsStore::~PairsStore() = default;

std::string PairsStore::path() const
{
  return directory_.empty() ? std::string() : directory_ + "/pairs.csv";
}

void PairsStore::say(SessionLogLevel level, const std::string& text) const
{
  if (log_)
    log_(level, text);
}

void PairsStore::open(bool resume)
{
  fs::create_directories(directory_);
  const std::string pairs_path = path();
  if (!resume && fs::exists(pairs_path))
    archive("~resume_pairs is false");
  try {
    appender_ = std::make_unique<PairsCsvAppender>(pairs_path, joints_);
  } catch (const std::runtime_error& error) {
    // Another robot's or configuration's pairs: keep them aside, never delete them.
    say(SessionLogLevel::kWarn, error.what());
    archive("its joints differ from the configuration's");
    appender_ = std::make_unique<PairsCsvAppender>(pairs_path, joints_);
  }
  pairs_ = appender_->existing();
  resumed_ = pairs_.size();
  if (appender_->dropped_partial_line())
    say(SessionLogLevel::kWarn, pairs_path + ": dropped a last line cut off by a crash");
  if (!pairs_.empty())
    say(SessionLogLevel::kInfo,
        "resumed " + std::to_string(pairs_.size()) + " pairs from " + pairs_path);
}

void PairsStore::add(const MotionPair& pair)
{
  pairs_.push_back(pair);
  if (directory_.empty())
    return;
  ++unwritten_;
  writePending();
}

void PairsStore::writePending()
{
  if (unwritten_ == 0)
    return;
  try {
    if (rewrite_pending_)  // the pairs were made again: the whole file, then appended to
      rewrite();
    if (!appender_)  // a reset could not create the file
      appender_ = std::make_unique<PairsCsvAppender>(path(), joints_);
    for (; unwritten_ > 0; --unwritten_)
      appender_->append(pairs_[pairs_.size() - unwritten_]);
  } catch (const std::exception& error) {
    if (problem_.empty()) {
      say(SessionLogLevel::kError,
          std::string(error.what()) + ": the pairs stay in memory (" + std::to_string(unwritten_) +
              " not written yet) and are written when the disk takes them again (retried with "
              "every pair and every diagnostics period)");
    }
    problem_ = error.what();
    return;
  }
  if (!problem_.empty()) {
    say(SessionLogLevel::kInfo, "the pairs file " + path() + " is written again: no pair lost");
    problem_.clear();
  }
}

std::string PairsStore::reset()
{
  const std::size_t dropped = pairs_.size();
  std::string archived;
  if (!directory_.empty()) {
    // The file first: when it cannot be moved aside, the pairs stay (in memory and file).
    appender_.reset();
    if (fs::exists(path()) && dropped > 0)
      archived = archive("~reset");
    else
      fs::remove(path());  // only a header: nothing to keep
  }
  pairs_.clear();
  resumed_ = 0;
  unwritten_ = 0;
  if (directory_.empty())
    return std::to_string(dropped) + " pairs set aside";
  try {
    appender_ = std::make_unique<PairsCsvAppender>(path(), joints_);
    problem_.clear();
  } catch (const std::exception& error) {
    // New pairs stay in memory until the file can be created (writePending()).
    say(SessionLogLevel::kError,
        std::string(error.what()) + ": new pairs stay in memory until it can be written");
    problem_ = error.what();
  }
  return std::to_string(dropped) + " pairs set aside" +
         (archived.empty() ? std::string() : " in " + archived);
}

void PairsStore::replace(const std::vector<MotionPair>& pairs)
{
  pairs_ = pairs;
  resumed_ = 0;
  unwritten_ = 0;
  if (directory_.empty())
    return;
  rewrite_pending_ = true;
  unwritten_ = pairs_.size();
  writePending();
}

void PairsStore::rewrite()
{
  appender_.reset();
  writePairsCsv(path(), {joints_, pairs_});  // atomically: the old file or the new one
  appender_ = std::make_unique<PairsCsvAppender>(path(), joints_);
  rewrite_pending_ = false;
  unwritten_ = 0;
}

std::string PairsStore::archive(const std::string& why)
{
  std::string archived = directory_ + "/pairs-" + wallClockTag() + ".csv";
  for (int i = 1; fs::exists(archived); ++i)
    archived = directory_ + "/pairs-" + wallClockTag() + "-" + std::to_string(i) + ".csv";
  fs::rename(path(), archived);
  say(SessionLogLevel::kWarn, "moved " + path() + " to " + archived + " (" + why + ")");
  return archived;
}

}  // namespace odometry_calibration
