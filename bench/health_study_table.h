// What the health-monitor studies (study_health_changes, study_health_changes_scans,
// study_health_sensors) share: their seed-sweep options and the cell naming a verdict.
//
// Header-only study helper; not part of the library.
#pragma once

#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <string>
#include <vector>

#include "odometry_calibration/assistant/change_attribution.h"
#include "odometry_calibration/common/arguments.h"

namespace odometry_calibration {
namespace health_study {

/// Reads `--seeds a,b,...` and `--within S` into `seed_texts` and `within_s` (their defaults as
/// given). Returns -1 to go on, else the exit status: 0 after printing the usage (with the
/// defaults, whatever the other options said, e.g. `--seeds '' --help`), 2 after naming a bad
/// option.
inline int parseSeedSweep(int argc, char** argv, const std::string& tool,
                          std::vector<std::string>* seed_texts, double* within_s)
{
  std::string default_seeds;  // taken before parsing overwrites them
  for (const std::string& seed : *seed_texts)
    default_seeds += (default_seeds.empty() ? "" : ",") + seed;
  const double default_within_s = *within_s;
  try {
    ArgumentParser parser;
    parser.listOption("--seeds", seed_texts).positiveNumber("--within", within_s);
    if (!parser.parse(argc, argv)) {
      std::cout << "usage: " << tool << " [--seeds a,b,...] [--within S]\n(defaults: --seeds "
                << default_seeds << " --within " << default_within_s << ")\n";
      return 0;
    }
    if (seed_texts->empty())
      throw std::invalid_argument("option --seeds: expected at least one seed, e.g. --seeds " +
                                  default_seeds);
  } catch (const std::exception& error) {
    std::cerr << tool << ": " << error.what() << "\n";
    return 2;
  }
  return -1;
}

/// The verdict in a table cell: "right wheel radius (+2.01 +- 0.10 %)", "wheels: cannot tell
/// which", "nothing significant"... With `sensor_names` (one per laser), a mounting change whose
/// quantity is open names the laser it is on, when told.
inline std::string verdictCell(const ChangeVerdict& verdict,
                               const std::vector<std::string>& sensor_names = {})
{
  if (!verdict.significant)
    return "nothing significant";
  if (!verdict.kind_told)
    return "wheel or mounting: cannot tell";
  if (!verdict.quantity_told) {
    if (verdict.kind == ChangeKind::kWheel)
      return "wheels: cannot tell which";
    if (sensor_names.empty())
      return "mounting: cannot tell which";
    return verdict.sensor >= 0 && static_cast<std::size_t>(verdict.sensor) < sensor_names.size()
               ? sensor_names[static_cast<std::size_t>(verdict.sensor)] +
                     " mounting: cannot tell which"
               : "mounting: cannot tell which laser";
  }
  const ChangeCandidate& best = verdict.candidates.front();
  char value[64];
  std::snprintf(value, sizeof(value), " (%+.2f +- %.2f %s)", best.estimate, best.sigma,
                best.hypothesis.unit.c_str());
  return best.hypothesis.name + value;
}

}  // namespace health_study
}  // namespace odometry_calibration
