// Running gnuplot (Debian package gnuplot-nox) on a script, for the reports' plots. A missing
// or failing gnuplot is an outcome to report, never an exception: plots are evidence next to a
// calibration, not part of it.
#pragma once

#include <string>
#include <vector>

namespace odometry_calibration {

/// How to run the plotting program.
struct GnuplotOptions
{
  /// Program name (looked up in PATH) or path.
  std::string program = "gnuplot";
  /// The run is stopped (and reported) after this long [s].
  double timeout_s = 60.0;
};

/// Runs `program script...` (the scripts one after the other, in one gnuplot) with `directory`
/// as working directory (a relative program path is taken from there), stdout discarded.
/// Returns an empty string on success, otherwise what went wrong in words: the program not
/// found (with the Debian package to install), a non-zero exit with the last lines gnuplot
/// printed, a timeout.
std::string runGnuplot(const std::vector<std::string>& scripts, const std::string& directory,
                       const GnuplotOptions& options = GnuplotOptions());

}  // namespace odometry_calibration
