#include "odometry_calibration/ros/bag_runner.h"

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <new>
#include <sstream>
#include <stdexcept>

#include <rosbag/bag.h>
#include <rosbag/view.h>

#include "odometry_calibration/ros/bag_message_reader.h"
#include "odometry_calibration/ros/bag_record_check.h"

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

BagRunResult runBagsUnchecked(const std::vector<std::string>& bag_paths,
                              const CalibrationConfig& config, double start_offset_s,
                              double end_offset_s,
                              const std::function<void(const BagProgress&)>& progress)
{
  const auto run_start = Clock::now();
  std::vector<std::unique_ptr<rosbag::Bag>> bags;
  for (const std::string& path : bag_paths) {
    auto bag = std::make_unique<rosbag::Bag>();
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
    try {
      bag->open(path, rosbag::bagmode::Read);
    } catch (const rosbag::BagException& error) {
      throw std::runtime_error("cannot read bag '" + path + "': " + error.what() +
                               " (a truncated or unindexed bag can be repaired with "
                               "'rosbag reindex')");
    }
    bags.push_back(std::move(bag));
  }
  const std::string ego_topic =
      config.ego_motion == EgoMotionSource::kScan ? config.scan_topic : config.ego_motion_topic;
  rosbag::View all;
  for (const auto& bag : bags) {
    all.addQuery(*bag,
                 rosbag::TopicQuery(std::vector<std::string>{config.joint_state_topic, ego_topic}));
  }
  if (all.size() == 0) {
    throw std::runtime_error("the bags hold no message on '" + config.joint_state_topic + "' or '" +
                             ego_topic + "'");
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
  rosbag::View view;
  for (const auto& bag : bags) {
    view.addQuery(*bag,
                  rosbag::TopicQuery(std::vector<std::string>{config.joint_state_topic, ego_topic}),
                  begin, end);
  }

  BagRunResult result;
  result.bag_span_s = (end - begin).toSec();
  PairCollector collector(encoderChannels(config), config.collector, priorPredictor(config));
  std::vector<EncoderChannelOptions> channels = encoderChannels(config);
  EncoderDecoder history_decoder(channels);
  const Eigen::Matrix3d pose_covariance =
      Eigen::Vector3d(config.ego_motion_sigma_m * config.ego_motion_sigma_m,
                      config.ego_motion_sigma_m * config.ego_motion_sigma_m,
                      config.ego_motion_sigma_rad * config.ego_motion_sigma_rad)
          .asDiagonal();
  auto take = [&](const std::vector<CollectorEvent>& events, double stamp_s) {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair) {
        result.pairs.push_back(event.pair);
      } else if (event.type == CollectorEvent::Type::kRestarted) {
        result.restarts.push_back("at " + std::to_string(stamp_s) + " s: " + event.reason);
      }
    }
  };

  // Reading and converting run ahead on their own thread; this one feeds the collector.
  BagMessageReader reader(view, config, bagNames(bag_paths));
  std::size_t messages = 0;
  Clock::duration pairing{};
  for (std::vector<BagInput> batch = reader.next(); !batch.empty(); batch = reader.next()) {
    for (BagInput& input : batch) {
      ++messages;
      const auto start = Clock::now();
      switch (input.kind) {
        case BagInput::Kind::kBadJoints:
          ++result.joint_state_messages;
          if (result.bad_joint_states++ == 0)
            result.first_bad_joint_state = input.problem;
          break;
        case BagInput::Kind::kJoints:
          ++result.joint_state_messages;
          try {
            Eigen::VectorXd accepted;  // empty for an encoder glitch
            take(collector.addEncoders(input.stamp_s, input.raw, &accepted), input.stamp_s);
            if (accepted.size() > 0 && (result.encoder_history.empty() ||
                                        input.stamp_s > result.encoder_history.back().stamp_s)) {
              result.encoder_history.push_back({input.stamp_s, history_decoder.decode(accepted)});
            }
          } catch (const std::invalid_argument& error) {
            if (result.bad_joint_states++ == 0)
              result.first_bad_joint_state = error.what();
          }
          break;
        case BagInput::Kind::kBadScan:
          ++result.ego_motion_messages;
          if (result.bad_clouds++ == 0)
            result.first_bad_cloud = input.problem;
          break;
        case BagInput::Kind::kScan:
          ++result.ego_motion_messages;
          if (!input.problem.empty() && result.clouds_without_times++ == 0)
            result.first_cloud_time_problem = input.problem;
          take(collector.addScan(input.stamp_s, input.scan), input.stamp_s);
          break;
        case BagInput::Kind::kPose:
          ++result.ego_motion_messages;
          take(collector.addSensorPose(input.stamp_s, input.pose, pose_covariance), input.stamp_s);
          break;
      }
      pairing += Clock::now() - start;
      if (progress && messages % 500 == 0)
        progress({input.fraction, messages, seconds(Clock::now() - run_start)});
    }
  }
  take(collector.flush(), end.toSec());
  if (progress)
    progress({1.0, messages, seconds(Clock::now() - run_start)});
  if (result.joint_state_messages == 0) {
    throw std::runtime_error("no sensor_msgs/JointState on '" + config.joint_state_topic +
                             "' in the bags");
  }
  if (result.ego_motion_messages == 0) {
    throw std::runtime_error("no ego-motion message (" + ego_topic + ") in the bags");
  }
  if (result.bad_clouds > 0 && result.bad_clouds == result.ego_motion_messages) {
    throw std::runtime_error("no usable PointCloud2 on '" + ego_topic +
                             "': all were skipped, first: " + result.first_bad_cloud);
  }
  if (result.bad_joint_states == result.joint_state_messages) {
    throw std::runtime_error("no usable JointState: " + result.first_bad_joint_state);
  }
  result.statistics = collector.statistics();
  if (!result.restarts.empty())
    result.encoder_history.clear();
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
                     const std::function<void(const BagProgress&)>& progress)
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
    return runBagsUnchecked(bag_paths, config, start_offset_s, end_offset_s, progress);
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
    notes.push_back("skipped " + std::to_string(run.bad_clouds) +
                    " PointCloud2 messages, first: " + run.first_bad_cloud);
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
