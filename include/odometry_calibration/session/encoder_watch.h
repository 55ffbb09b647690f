// Stuck and glitching encoders, for the session's status: a reading stuck at an
// absurd value (1e300) is skipped as a glitch at every message and stops the odometry, a wheel
// encoder that stopped counting reads the same value while the other wheels turn; both used to
// leave /diagnostics OK. The watch names the joint.
#pragma once

#include <cstddef>
#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/encoder.h"

namespace odometry_calibration {

class EncoderWatch
{
public:
  /// `channels`: the configured joints; `stuck_readings`: an incremental joint reading the same
  /// value this many readings in a row while another incremental joint changes is stuck.
  explicit EncoderWatch(std::vector<EncoderChannelOptions> channels,
                        std::size_t stuck_readings = 250);

  /// One reading of the joints (encoderChannels order).
  void add(const Eigen::VectorXd& raw);
  /// The encoder problems now, each naming its joint: joints stuck, and joints with readings
  /// skipped as glitches since the previous call (`glitches`: the collector's counts per joint).
  std::vector<std::string> problems(const std::map<std::string, std::size_t>& glitches);

private:
  struct Joint
  {
    double last = 0.0;
    std::size_t unchanged = 0;  ///< readings in a row without change while another joint moved
    std::size_t glitches_seen = 0;
  };
  std::vector<EncoderChannelOptions> channels_;
  std::size_t stuck_readings_;
  std::vector<Joint> joints_;
  bool has_reading_ = false;
};

}  // namespace odometry_calibration
