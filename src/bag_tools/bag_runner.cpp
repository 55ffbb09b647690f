#include "odometry_calibration/bag_tools/bag_runner.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <future>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "odometry_calibration/bag/bag_message_reader.h"
#include "odometry_calibration/bag/bag_record_check.h"
#include "odometry_calibration/bag/mcap_messages.h"
#include "odometry_calibration/bag/rosbag2_sqlite_messages.h"
#include "odometry_calibration/bag/rosbag_messages.h"

namespace odometry_calibration {
namespace {

using Clock = std::chrono::steady_clock;

double seconds(Clock::duration duration)
{
  return std::chrono::duration<double>(duration).count();
}

/// "bag 'a.bag'" or "one of the bags 'a.bag', 'b.bag'", for messages.
std::string bagNames(const std::vector<std::string>& bag_paths)
{
  std::string names;
  for (const std::string& path : bag_paths)
    names += (names.empty() ? "'" : ", '") + path + "'";
  return (bag_paths.size() == 1 ? "bag " : "one of the bags ") + names;
}

/// The bags, each checked record by record before rosbag reads it, then opened.
std::vector<std::unique_ptr<rosbag::Bag>> openBags(const std::vector<std::string>& bag_paths)
{
  std::vector<std::unique_ptr<rosbag::Bag>> bags;
  // A process's first rosbag::Bag looks up rosbag's encryptor plugins (pluginlib crawls the
  // package paths for package.xml files, 0.1 s on the benchmark machine; later ones reuse it):
  // constructed on another thread while the first bag's records are checked (at get() on this
  // one when no thread can be made).
  std::future<std::unique_ptr<rosbag::Bag>> first_bag = std::async(
      std::launch::async | std::launch::deferred, [] { return std::make_unique<rosbag::Bag>(); });
  for (const std::string& path : bag_paths) {
    std::error_code error_code;
    if (!std::filesystem::is_regular_file(path, error_code)) {
      throw std::runtime_error("no bag file '" + path + "'");
    }
    // rosbag trusts the lengths a bag states (of records, header fields, index entries): one
    // flipped byte makes it read outside its buffers, already while opening. Refuse such a bag
    // before rosbag reads any of it.
    try {
      checkBagRecords(path);
    } catch (const UnsupportedBagFormat& error) {
      throw std::runtime_error("bag '" + path + "' cannot be read: " + error.what());
    } catch (const std::runtime_error& error) {
      throw std::runtime_error("bag '" + path + "' is corrupted or cut off: " + error.what() +
                               " (check it with 'rosbag check'; 'rosbag reindex' repairs a bag "
                               "whose index is lost or cut off)");
    }
    auto bag = first_bag.valid() ? first_bag.get() : std::make_unique<rosbag::Bag>();
    try {
      bag->open(path, rosbag::bagmode::Read);
    } catch (const rosbag::BagException& error) {
      throw std::runtime_error("cannot read bag '" + path + "': " + error.what() +
                               " (a truncated or unindexed bag can be repaired with "
                               "'rosbag reindex')");
    }
    bags.push_back(std::move(bag));
  }
  return bags;
}

/// The topics in words: "'/joint_states', '/scan'".
std::string topicList(const std::vector<std::string>& topics)
{
  std::string list;
  for (const std::string& topic : topics)
    list += (list.empty() ? "'" : ", '") + topic + "'";
  return list;
}

/// Refuses an empty time window [start_offset_s, end_offset_s] of bags holding `span_s`.
void requireWindow(double start_offset_s, double end_offset_s, double span_s)
{
  if (start_offset_s >= span_s || (end_offset_s > 0.0 && end_offset_s <= start_offset_s)) {
    throw std::runtime_error("the time window [" + std::to_string(start_offset_s) + ", " +
                             (end_offset_s > 0.0 ? std::to_string(end_offset_s) : "end") +
                             "] s is empty: the bags hold " + std::to_string(span_s) + " s");
  }
}

/// The time window [begin, end] of the bags' messages on the configured topics.
std::pair<ros::Time, ros::Time> timeWindow(const std::vector<std::unique_ptr<rosbag::Bag>>& bags,
                                           const CalibrationConfig& config, double start_offset_s,
                                           double end_offset_s)
{
  rosbag::View all;
  for (const auto& bag : bags)
    all.addQuery(*bag, rosbag::TopicQuery(readTopics(config)));
  if (all.size() == 0)
    throw std::runtime_error("the bags hold no message on " + topicList(readTopics(config)));
  const double span_s = (all.getEndTime() - all.getBeginTime()).toSec();
  requireWindow(start_offset_s, end_offset_s, span_s);
  const ros::Time begin = all.getBeginTime() + ros::Duration(start_offset_s);
  const ros::Time end = end_offset_s > 0.0 && end_offset_s < span_s
                            ? all.getBeginTime() + ros::Duration(end_offset_s)
                            : all.getEndTime();
  return {begin, end};
}

/// The recording a run reads: its messages on the configured topics within the time window,
/// and what holds them open.
struct OpenRecording
{
  std::vector<std::unique_ptr<rosbag::Bag>> bags;
  std::unique_ptr<rosbag::View> view;
  std::unique_ptr<RecordedMessages> messages;
  double span_s = 0.0;  ///< the window's length [s]
};

OpenRecording openRosbag1(const std::vector<std::string>& bag_paths,
                          const CalibrationConfig& config, double start_offset_s,
                          double end_offset_s)
{
  OpenRecording recording;
  recording.bags = openBags(bag_paths);
  const auto [begin, end] = timeWindow(recording.bags, config, start_offset_s, end_offset_s);
  recording.view = std::make_unique<rosbag::View>();
  for (const auto& bag : recording.bags)
    recording.view->addQuery(*bag, rosbag::TopicQuery(readTopics(config)), begin, end);
  recording.messages = std::make_unique<RosbagMessages>(*recording.view);
  recording.span_s = (end - begin).toSec();
  return recording;
}

/// The rosbag2 recordings (`Messages`: Rosbag2SqliteMessages or McapMessages) opened for the
/// configured topics within the time window.
template <typename Messages>
OpenRecording openRosbag2(const std::vector<std::string>& bag_paths,
                          const CalibrationConfig& config, double start_offset_s,
                          double end_offset_s)
{
  auto messages = std::make_unique<Messages>(bag_paths, readTopics(config));
  if (const std::vector<std::string> missing = messages->missingTopics(); !missing.empty()) {
    throw std::runtime_error("the bags record no topic " + topicList(missing) +
                             " (set the topic names in the config); they record " +
                             messages->describeTopics());
  }
  if (messages->empty()) {
    throw std::runtime_error("the bags hold no message on " + topicList(readTopics(config)) +
                             "; they record " + messages->describeTopics());
  }
  const std::int64_t first_ns = messages->firstTime_ns(), last_ns = messages->lastTime_ns();
  const double span_s = static_cast<double>(last_ns - first_ns) * 1e-9;
  requireWindow(start_offset_s, end_offset_s, span_s);
  const std::int64_t begin_ns = first_ns + std::llround(start_offset_s * 1e9);
  const std::int64_t end_ns = end_offset_s > 0.0 && end_offset_s < span_s
                                  ? first_ns + std::llround(end_offset_s * 1e9)
                                  : last_ns;
  messages->restrictTo(begin_ns, end_ns);
  OpenRecording recording;
  recording.messages = std::move(messages);
  recording.span_s = static_cast<double>(end_ns - begin_ns) * 1e-9;
  return recording;
}

/// The bags opened by their format: all ROS 1 bags, all rosbag2 recordings in SQLite storage
/// (bag folders, .db3 or .db3.zstd files) or all in MCAP storage (bag folders, .mcap files). A
/// mix is refused.
OpenRecording openRecording(const std::vector<std::string>& bag_paths,
                            const CalibrationConfig& config, double start_offset_s,
                            double end_offset_s)
{
  std::size_t rosbag2 = 0, mcap = 0;
  for (const std::string& path : bag_paths) {
    rosbag2 += isRosbag2Path(path) ? 1 : 0;
    mcap += isMcapPath(path) ? 1 : 0;
  }
  if (rosbag2 == 0)
    return openRosbag1(bag_paths, config, start_offset_s, end_offset_s);
  if (rosbag2 < bag_paths.size()) {
    throw std::runtime_error("ROS 1 bags and rosbag2 recordings cannot be read in one run (" +
                             bagNames(bag_paths) + "): convert them to one format");
  }
  if (mcap == bag_paths.size())
    return openRosbag2<McapMessages>(bag_paths, config, start_offset_s, end_offset_s);
  if (mcap > 0) {
    throw std::runtime_error(
        "rosbag2 recordings in SQLite and in MCAP storage cannot be read in "
        "one run (" +
        bagNames(bag_paths) + "): convert them to one storage with 'ros2 bag convert'");
  }
  return openRosbag2<Rosbag2SqliteMessages>(bag_paths, config, start_offset_s, end_offset_s);
}

/// A session as calibrate_bag uses it: no files, no odometry, no assistant (the report says
/// what they would), every encoder sample kept for the time offset and the nominal's re-cut.
std::shared_ptr<JointCalibrationSession> bagSession(
    const CalibrationConfig& config, const std::vector<double>& candidate_intervals_s,
    const std::string& source, const JointFitFunction& fit_jointly)
{
  SessionOptions options;
  options.load_saved_calibration = false;
  options.resume_pairs = false;
  options.min_pairs = 1;
  options.odometry = false;
  options.assistant = false;
  options.candidate_intervals_s = candidate_intervals_s;
  options.keep_encoder_history = true;
  options.compare_trajectories = true;
  options.adopt_fits = false;
  options.min_pairs_name.clear();
  options.source = source;
  return std::make_shared<JointCalibrationSession>(config, "", "", options, nullptr, fit_jointly);
}

/// A publisher chosen by `key` (`chosen`, empty: none) that published nothing of `what` in the
/// bags, where `ignored` messages came from `other`: refused, naming both.
void requireChosenPublisher(const std::string& key, const std::string& chosen,
                            const std::string& what, const std::string& used, std::size_t ignored,
                            const std::string& other)
{
  if (chosen.empty() || !used.empty())
    return;
  throw std::runtime_error(key + " '" + chosen + "' published no " + what + " in the bags (" +
                           std::to_string(ignored) + " came from " + publisherName(other) + ")");
}

/// Source `config`'s counts checked: the bags held usable data of it, from the chosen
/// publishers.
void requireUsableData(const SessionCounts& counts, const CalibrationConfig& config)
{
  const std::string ego_topic = egoMotionSources(config).front().topic;
  const std::string ego_type = egoMessageType(config.ego_motion);
  const std::string wheel_input = wheelInputName(config.wheels, config.joint_state_topic);
  requireChosenPublisher("joint_state_publisher", config.joint_state_publisher, wheel_input,
                         counts.encoder_publisher, counts.ignored_encoder_messages,
                         counts.ignored_encoder_publisher);
  requireChosenPublisher(config.ego_motion_publisher_key, config.ego_motion_publisher,
                         ego_type + " on '" + ego_topic + "'", counts.ego_publisher,
                         counts.ignored_ego_messages, counts.ignored_ego_publisher);
  if (counts.encoder_messages == 0) {
    throw std::runtime_error(
        "no " + wheel_input + " in the bags" +
        (config.wheels.source == WheelSource::kTicks
             ? " (or no instant where every wheel's topic had a sample around it)"
             : ""));
  }
  if (counts.ego_messages == 0)
    throw std::runtime_error("no ego-motion message (" + ego_topic + ") in the bags");
  if (counts.bad_ego_messages > 0 && counts.bad_ego_messages == counts.ego_messages) {
    throw std::runtime_error("no usable " + ego_type + " on '" + ego_topic +
                             "': all were skipped, first: " + counts.first_bad_ego_message);
  }
  if (counts.bad_encoder_messages == counts.encoder_messages)
    throw std::runtime_error("no usable " + wheel_input + ": " + counts.first_bad_encoder_message);
  // Ticks and velocities are made positions from a wheel's whole history (a refused counter
  // stays refused): most of them refused is a setting to fix, not data to fit around.
  if (config.wheels.source != WheelSource::kJointState &&
      2 * counts.bad_encoder_messages > counts.encoder_messages) {
    throw std::runtime_error(
        wheel_input + ": " + std::to_string(counts.bad_encoder_messages) + " of " +
        std::to_string(counts.encoder_messages) +
        " messages could not be used, first: " + counts.first_bad_encoder_message);
  }
}

BagRunResult runBagsUnchecked(const std::vector<std::string>& bag_paths,
                              const CalibrationConfig& config, double start_offset_s,
                              double end_offset_s,
                              const std::function<void(const BagProgress&)>& progress,
                              const std::vector<double>& candidate_intervals_s,
                              const JointFitFunction& fit_jointly)
{
  const auto run_start = Clock::now();
  OpenRecording recording = openRecording(bag_paths, config, start_offset_s, end_offset_s);
  BagRunResult result;
  result.bag_span_s = recording.span_s;
  // Offline: the keyframe matches' events may come a few messages late (pair_collector.h), so
  // that both cores match while this thread feeds the session.
  CalibrationConfig session_config = config;
  session_config.collector.defer_keyframe_matches = true;
  result.session =
      bagSession(session_config, candidate_intervals_s, bag_paths.front(), fit_jointly);
  // Reading and converting run ahead on their own thread; this one feeds the session.
  BagMessageReader reader(*recording.messages, config, bagNames(bag_paths));
  std::size_t messages = 0;
  Clock::duration pairing{};
  for (std::vector<BagInput> batch = reader.next(); !batch.empty(); batch = reader.next()) {
    for (const BagInput& input : batch) {
      const auto start = Clock::now();
      feedInput(*result.session, input.input);
      pairing += Clock::now() - start;
      if (progress && ++messages % 500 == 0)
        progress({input.fraction, messages, seconds(Clock::now() - run_start)});
    }
    // Two publishers of one input, or a configured value the data contradicts: refused as
    // soon as it shows.
    for (std::size_t k = 0; k < result.session->sourceCount(); ++k) {
      if (const std::string conflict = result.session->source(k).inputConflict(); !conflict.empty())
        throw std::runtime_error(conflict);
    }
  }
  result.session->flush();
  if (progress)
    progress({1.0, messages, seconds(Clock::now() - run_start)});
  for (std::size_t k = 0; k < result.session->sourceCount(); ++k)
    requireUsableData(result.session->source(k).counts(), configForSource(config, k));
  result.counts = result.session->source(0).counts();
  result.pairs = result.session->source(0).pairs();
  result.encoder_history = result.session->source(0).encoderHistory();
  result.wall_time_s = seconds(Clock::now() - run_start);
  result.pairing_time_s = seconds(pairing);
  result.conversion_time_s = reader.conversionTime();
  result.filtering_time_s = reader.filteringTime();
  result.read_time_s = reader.readTime();
  result.partial_reads = recording.messages->partialReads();
  return result;
}

}  // namespace

BagRunResult runBags(const std::vector<std::string>& bag_paths, const CalibrationConfig& config,
                     double start_offset_s, double end_offset_s,
                     const std::function<void(const BagProgress&)>& progress,
                     const std::vector<double>& candidate_intervals_s,
                     const JointFitFunction& fit_jointly)
{
  // rosbag and the message deserialisation throw these for a corrupted or cut-off bag (a
  // chunk or record that does not parse, a length beyond the data, a compressed chunk that
  // does not decompress); the run's own errors are plain std::runtime_error and pass as they are.
  auto corrupted = [&](const char* what) {
    return std::runtime_error(
        bagNames(bag_paths) + " is corrupted or cut off: " + what +
        " (check it with 'rosbag check'; 'rosbag reindex' repairs a bag whose index is lost)");
  };
  const BagReadScope reading(bagNames(bag_paths));
  try {
    return runBagsUnchecked(bag_paths, config, start_offset_s, end_offset_s, progress,
                            candidate_intervals_s, fit_jointly);
  } catch (const ros::Exception& error) {
    throw corrupted(error.what());
  } catch (const std::logic_error& error) {
    throw corrupted(error.what());
  } catch (const std::bad_alloc&) {
    throw corrupted("a record claims more memory than there is");
  }
}

std::string formatBagRunSummary(const BagRunResult& run, const SessionCounts& counts,
                                const std::vector<std::string>& notes)
{
  // "+0.44 % (± 0.31)": the scale check and its standard error (none with one pair).
  auto formatScaleCheck = [](const CollectorStatistics& s) {
    char text[64];
    const double error_pct = s.keyframeVersusChainStandardErrorPercent();
    if (std::isfinite(error_pct))
      std::snprintf(text, sizeof(text), "%+.2f %% (± %.2f)", s.keyframeVersusChainPercent(),
                    error_pct);
    else
      std::snprintf(text, sizeof(text), "%+.2f %%", s.keyframeVersusChainPercent());
    return std::string(text);
  };
  std::ostringstream text;
  text << "bags: " << run.bag_span_s << " s of data in " << run.wall_time_s << " s ("
       << (run.wall_time_s > 0 ? run.bag_span_s / run.wall_time_s : 0.0) << "x real time; reading "
       << run.read_time_s << " s, conversion " << run.conversion_time_s << " s, ";
  if (run.filtering_time_s > 0.0)
    text << "cloud filtering " << run.filtering_time_s << " s, ";
  text << "pairing " << run.pairing_time_s << " s)\n";
  for (const std::string& partial : run.partial_reads)
    text << "warning: " << partial << "\n";
  const CollectorStatistics& s = counts.statistics;
  text << "keyframe pairs: " << s.pairs << " from " << s.scans << " scans, " << s.keyframes
       << " keyframes";
  if (s.consecutive_matches > 0) {
    text << ", " << s.consecutive_failures << " of " << s.consecutive_matches
         << " consecutive matches failed, " << s.unverified_pairs << " pairs unverified";
  }
  text << "\n";
  if (s.scale_check_pairs > 0) {
    text << "scale check: keyframe matches " << formatScaleCheck(s)
         << " against the chained consecutive matches over " << s.scale_check_pairs
         << " pairs (docs/scan_matching.md)\n";
  }
  for (const auto& [reason, count] : s.rejected) {
    text << "  rejected " << count << ": " << reason << "\n";
  }
  for (const std::string& note : notes)
    text << note << "\n";
  return text.str();
}

}  // namespace odometry_calibration
