// Who publishes a session's inputs. A robot where a second node also publishes the
// wheel joints (joint_state_publisher at zero beside the driver, a common misconfiguration) or
// the sensor topic interleaves two streams the pairing would take for one: a confident wrong
// calibration. Each input's publisher (a bag connection's callerid, a live message's publisher)
// is checked against the first one seen: a second one is a conflict, said once with both names
// and how to choose, after which that input is refused; with a chosen publisher
// (`joint_state_publisher` for the encoders, `ego_motion.publisher` for the sensor) the others'
// messages are ignored and counted.
#pragma once

#include <array>
#include <cstddef>
#include <string>

#include "odometry_calibration/session/input_monitor.h"

namespace odometry_calibration {

/// What to do with one message given its publisher.
enum class PublisherVerdict
{
  kUse,       ///< from the input's publisher
  kIgnore,    ///< from another than the chosen publisher: ignored and counted
  kConflict,  ///< a second publisher with none chosen (or after one): the input is refused
};

class InputPublishers
{
public:
  /// `topics`: the encoder and ego-motion topics' names (for messages); `chosen`: each input's
  /// configured publisher (empty: the first one seen, a second is a conflict); `keys`: the
  /// configuration keys that choose them (for messages).
  InputPublishers(const std::array<std::string, 2>& topics,
                  const std::array<std::string, 2>& chosen,
                  const std::array<std::string, 2>& keys = {"joint_state_publisher",
                                                            "ego_motion.publisher"});

  /// The verdict for a message of `input` from `publisher` ("" when the front end cannot tell:
  /// an unnamed publisher, still one publisher). Counts it. `carries_data` false: a message
  /// that could not be read (e.g. a JointState of other joints): it makes no publisher the
  /// input's and starts no conflict, but is ignored when another publisher is chosen.
  PublisherVerdict check(SessionInput input, const std::string& publisher,
                         bool carries_data = true);
  /// The first conflict in words (both publishers, how to choose); empty without one.
  const std::string& conflict() const { return conflict_; }
  /// Messages of `input` from publishers other than the chosen one (ignored), and after a
  /// conflict (refused).
  std::size_t ignored(SessionInput input) const { return inputs_[index(input)].ignored; }
  std::size_t used(SessionInput input) const { return inputs_[index(input)].used; }
  /// The publisher whose messages are used ("" before the first; "(unnamed)" shown for "").
  const std::string& publisher(SessionInput input) const { return inputs_[index(input)].owner; }
  /// The first ignored publisher of `input` ("" without one).
  const std::string& otherPublisher(SessionInput input) const
  {
    return inputs_[index(input)].other;
  }
  /// The configuration key choosing `input`'s publisher (joint_state_publisher,
  /// ego_motion.publisher or ego_motion.sources[k].publisher).
  const std::string& key(SessionInput input) const { return inputs_[index(input)].key; }

private:
  struct Input
  {
    std::string topic, chosen, key, owner, other;
    bool has_owner = false, refused = false;
    std::size_t used = 0, ignored = 0;
  };
  static std::size_t index(SessionInput input) { return static_cast<std::size_t>(input); }
  std::string conflictText(SessionInput input, const std::string& second) const;

  std::array<Input, 2> inputs_;
  std::string conflict_;
};

/// A publisher's name for messages: quoted, "(unnamed)" for "".
std::string publisherName(const std::string& publisher);

}  // namespace odometry_calibration
