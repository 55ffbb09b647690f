#include "odometry_calibration/session/input_publishers.h"

namespace odometry_calibration {

std::string publisherName(const std::string& publisher)
{
  return publisher.empty() ? "(unnamed)" : "'" + publisher + "'";
}

InputPublishers::InputPublishers(const std::array<std::string, 2>& topics,
                                 const std::array<std::string, 2>& chosen,
                                 const std::array<std::string, 2>& keys)
{
  for (std::size_t i = 0; i < topics.size(); ++i) {
    inputs_[i].topic = topics[i];
    inputs_[i].chosen = chosen[i];
    inputs_[i].key = keys[i];
  }
}

std::string InputPublishers::conflictText(SessionInput input, const std::string& second) const
{
  const Input& entry = inputs_[index(input)];
  const bool encoders = input == SessionInput::kEncoders;
  std::string text =
      "two nodes publish " + std::string(encoders ? "the configured joints" : "the ego-motion") +
      " on " + entry.topic + ": " + publisherName(entry.owner) + " and " + publisherName(second) +
      "; their messages interleaved would give a wrong calibration, so " + entry.topic +
      " is refused. ";
  const std::string example = !entry.owner.empty() ? entry.owner
                              : encoders           ? "the driver"
                                                   : "the laser's driver";
  text += "Set " + entry.key + ": <node> in the configuration (e.g. " + example +
          ") to use one and ignore the other, or remap or stop the other publisher";
  return text;
}

PublisherVerdict InputPublishers::check(SessionInput input, const std::string& publisher,
                                        bool carries_data)
{
  Input& entry = inputs_[index(input)];
  if (!entry.chosen.empty()) {
    if (publisher == entry.chosen) {
      entry.owner = publisher;
      entry.has_owner = true;
      ++entry.used;
      return PublisherVerdict::kUse;
    }
    if (entry.other.empty())
      entry.other = publisher;
    ++entry.ignored;
    return PublisherVerdict::kIgnore;
  }
  if (entry.refused) {
    ++entry.ignored;
    return PublisherVerdict::kConflict;
  }
  if (!carries_data)
    return PublisherVerdict::kUse;
  if (!entry.has_owner) {
    entry.owner = publisher;
    entry.has_owner = true;
  }
  if (publisher == entry.owner) {
    ++entry.used;
    return PublisherVerdict::kUse;
  }
  entry.other = publisher;
  entry.refused = true;
  ++entry.ignored;
  if (conflict_.empty())
    conflict_ = conflictText(input, publisher);
  return PublisherVerdict::kConflict;
}

}  // namespace odometry_calibration
