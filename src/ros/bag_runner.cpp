#include "odometry_calibration/ros/bag_runner.h"

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

#include "odometry_calibration/ros/bag_message_reader.h"
#include "odometry_calibration/ros/bag_record_check.h"
#include "odometry_calibration/ros/rosbag_messages.h"

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

std::string egoTopic(const CalibrationConfig& config)
{
  return config.ego_motion == EgoMotionSource::kScan ? config.scan_topic : config.ego_motion_topic;
}

/// The time window [begin, end] of the bags' messages on the configured topics.
std::pair<ros::Time, ros::Time> timeWindow(const std::vector<std::unique_ptr<rosbag::Bag>>& bags,
                                           const CalibrationConfig& config, double start_offset_s,
                                           double end_offset_s)
{
  rosbag::View all;
  for (const auto& bag : bags) {
    all.addQuery(*bag, rosbag::TopicQuery(readTopics(config)));
  }
  if (all.size() == 0) {
    throw std::runtime_error("the bags hold no message on '" + config.joint_state_topic + "' or '" +
                             egoTopic(config) + "'");
  }
  const double span_s = (all.getEndTime() - all.getBeginTime()).toSec();
  if (start_offset_s >= span_s || (end_offset_s > 0.0 && end_offset_s <= start_offset_s)) {
    throw std::runtime_error("the time window [" + std::to_string(start_offset_s) + ", " +
                             (end_offset_s > 0.0 ? std::to_string(end_offset_s) : "end") +
                             "] s is empty: the bags hold " + std::to_string(span_s) + " s");
  }
  const ros::Time begin = all.getBeginTime() + ros::Duration(start_offset_s);
  const ros::Time end = end_offset_s > 0.0 && end_offset_s < span_s
                            ? all.getBeginTime() + ros::Duration(end_offset_s)
                            : all.getEndTime();
  return {begin, end};
}

/// A session as calibrate_bag uses it: no files, no odometry, no assistant (the report says
/// what they would), every encoder sample kept for the time offset and the nominal's re-cut.
std::shared_ptr<CalibrationSession> bagSession(const CalibrationConfig& config,
                                               const std::vector<double>& candidate_intervals_s)
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
  options.source = "calibrate_bag";
  return std::make_shared<CalibrationSession>(config, "", "", options);
}

/// The ego-motion messages' type, for messages.
std::string egoMessageType(EgoMotionSource source)
{
  return source == EgoMotionSource::kScan    ? "LaserScan"
         : source == EgoMotionSource::kCloud ? "PointCloud2"
                                             : "pose";
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

/// The session's counts as the run's, and the checks that the bags held usable data.
void takeCounts(const CalibrationSession& session, const std::string& ego_topic,
                const CalibrationConfig& config, BagRunResult* result)
{
  const SessionCounts counts = session.counts();
  result->pairs = session.pairs();
  result->encoder_history = session.encoderHistory();
  result->statistics = counts.statistics;
  result->joint_state_messages = counts.encoder_messages;
  result->ego_motion_messages = counts.ego_messages;
  result->bad_joint_states = counts.bad_encoder_messages;
  result->first_bad_joint_state = counts.first_bad_encoder_message;
  result->bad_clouds = counts.bad_ego_messages;
  result->ego_message_type = egoMessageType(config.ego_motion);
  result->first_bad_cloud = counts.first_bad_ego_message;
  result->clouds_without_times = counts.clouds_without_times;
  result->first_cloud_time_problem = counts.first_cloud_time_problem;
  result->restarts = counts.restarts;
  result->ignored_joint_states = counts.ignored_encoder_messages;
  result->joint_state_publisher = counts.encoder_publisher;
  result->ignored_joint_state_publisher = counts.ignored_encoder_publisher;
  result->ignored_ego_messages = counts.ignored_ego_messages;
  result->ego_publisher = counts.ego_publisher;
  result->ignored_ego_publisher = counts.ignored_ego_publisher;
  result->ego_publisher_key = config.ego_motion_publisher_key;
  requireChosenPublisher("joint_state_publisher", config.joint_state_publisher,
                         "JointState on '" + config.joint_state_topic + "'",
                         counts.encoder_publisher, counts.ignored_encoder_messages,
                         counts.ignored_encoder_publisher);
  requireChosenPublisher(config.ego_motion_publisher_key, config.ego_motion_publisher,
                         egoMessageType(config.ego_motion) + " on '" + ego_topic + "'",
                         counts.ego_publisher, counts.ignored_ego_messages,
                         counts.ignored_ego_publisher);
  if (result->joint_state_messages == 0) {
    throw std::runtime_error("no sensor_msgs/JointState on '" + config.joint_state_topic +
                             "' in the bags");
  }
  if (result->ego_motion_messages == 0)
    throw std::runtime_error("no ego-motion message (" + ego_topic + ") in the bags");
  if (result->bad_clouds > 0 && result->bad_clouds == result->ego_motion_messages) {
    throw std::runtime_error("no usable " + egoMessageType(config.ego_motion) + " on '" +
                             ego_topic + "': all were skipped, first: " + result->first_bad_cloud);
  }
  if (result->bad_joint_states == result->joint_state_messages)
    throw std::runtime_error("no usable JointState: " + result->first_bad_joint_state);
}

BagRunResult runBagsUnchecked(const std::vector<std::string>& bag_paths,
                              const CalibrationConfig& config, double start_offset_s,
                              double end_offset_s,
                              const std::function<void(const BagProgress&)>& progress,
                              const std::vector<double>& candidate_intervals_s)
{
  const auto run_start = Clock::now();
  const std::vector<std::unique_ptr<rosbag::Bag>> bags = openBags(bag_paths);
  const auto [begin, end] = timeWindow(bags, config, start_offset_s, end_offset_s);
  rosbag::View view;
  for (const auto& bag : bags) {
    view.addQuery(*bag, rosbag::TopicQuery(readTopics(config)), begin, end);
  }
  BagRunResult result;
  result.bag_span_s = (end - begin).toSec();
  // Offline: the keyframe matches' events may come a few messages late (pair_collector.h), so
  // that both cores match while this thread feeds the session.
  CalibrationConfig session_config = config;
  session_config.collector.defer_keyframe_matches = true;
  result.session = bagSession(session_config, candidate_intervals_s);
  // Reading and converting run ahead on their own thread; this one feeds the session.
  RosbagMessages recorded(view);
  BagMessageReader reader(recorded, config, bagNames(bag_paths));
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
    // Two publishers of one input: refused as soon as the second one shows.
    if (const std::string conflict = result.session->publisherConflict(); !conflict.empty())
      throw std::runtime_error(conflict);
  }
  result.session->flush();
  if (progress)
    progress({1.0, messages, seconds(Clock::now() - run_start)});
  takeCounts(*result.session, egoTopic(config), config, &result);
  result.wall_time_s = seconds(Clock::now() - run_start);
  result.pairing_time_s = seconds(pairing);
  result.conversion_time_s = reader.conversionTime();
  result.filtering_time_s = reader.filteringTime();
  result.read_time_s = reader.readTime();
  return result;
}

}  // namespace

BagRunResult runBags(const std::vector<std::string>& bag_paths, const CalibrationConfig& config,
                     double start_offset_s, double end_offset_s,
                     const std::function<void(const BagProgress&)>& progress,
                     const std::vector<double>& candidate_intervals_s)
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
                            candidate_intervals_s);
  } catch (const ros::Exception& error) {
    throw corrupted(error.what());
  } catch (const std::logic_error& error) {
    throw corrupted(error.what());
  } catch (const std::bad_alloc&) {
    throw corrupted("a record claims more memory than there is");
  }
}

std::vector<std::string> bagRunNotes(const BagRunResult& run)
{
  std::vector<std::string> notes;
  if (run.ignored_joint_states > 0) {
    notes.push_back("ignored " + std::to_string(run.ignored_joint_states) +
                    " JointState messages from " +
                    publisherName(run.ignored_joint_state_publisher) +
                    " (joint_state_publisher: " + publisherName(run.joint_state_publisher) + ")");
  }
  if (run.ignored_ego_messages > 0) {
    notes.push_back("ignored " + std::to_string(run.ignored_ego_messages) + " " +
                    run.ego_message_type + " messages from " +
                    publisherName(run.ignored_ego_publisher) + " (" + run.ego_publisher_key + ": " +
                    publisherName(run.ego_publisher) + ")");
  }
  if (run.bad_joint_states > 0) {
    notes.push_back("skipped " + std::to_string(run.bad_joint_states) +
                    " JointState messages, first: " + run.first_bad_joint_state);
  }
  if (run.clouds_without_times > 0) {
    notes.push_back(std::to_string(run.clouds_without_times) +
                    " PointCloud2 messages used without their per-point times, first: " +
                    run.first_cloud_time_problem);
  }
  if (run.bad_clouds > 0) {
    notes.push_back("skipped " + std::to_string(run.bad_clouds) + " " + run.ego_message_type +
                    " messages, first: " + run.first_bad_cloud);
  }
  for (const auto& [joint, count] : run.statistics.glitches) {
    notes.push_back("skipped " + std::to_string(count) + " encoder glitches on joint '" + joint +
                    "' (increments beyond its max_turns_per_s)");
  }
  for (const std::string& restart : run.restarts)
    notes.push_back("restart " + restart);
  return notes;
}

std::string formatBagRunSummary(const BagRunResult& run)
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
  const CollectorStatistics& s = run.statistics;
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
  for (const std::string& note : bagRunNotes(run))
    text << note << "\n";
  return text.str();
}

}  // namespace odometry_calibration
