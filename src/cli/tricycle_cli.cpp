#include "odometry_calibration/cli/tricycle_cli.h"

#include <cmath>

#include "odometry_calibration/common/arguments.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/data/keyframes.h"
#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "odometry_calibration/eval/tricycle_report.h"
#include "odometry_calibration/report/tricycle_result_yaml.h"

namespace odometry_calibration {
std::string tricycleCliUsage()
{
  return "usage: calibrate_tricycle DATASET [options]\n"
         "\n"
         "Calibrates a front-wheel-drive tricycle (Ksteer, Ktraction, axis_length, steer_offset)\n"
         "and its sensor's pose on base_link from a log in the tricycle dataset format, starting\n"
         "from the nominal values in the log's header. Prints a report, writes a YAML result.\n"
         "\n"
         "options:\n"
         "  --output PATH            result YAML, written atomically (default\n"
         "                           tricycle_calibration.yaml; '' to skip)\n"
         "  --interval S             keyframe spacing T [s] (default 0.5)\n"
         "  --translation-sigma M    assumed sigma of a measured displacement's x, y [m]\n"
         "                           (default 0.01)\n"
         "  --rotation-sigma RAD     assumed sigma of a measured heading change [rad]\n"
         "                           (default 0.01)\n"
         "  --huber K                Huber threshold [sigma] (default 3; 0 = plain least squares)\n"
         "  --max-iterations N       solver iteration cap per solve (default 500)\n"
         "  -h, --help               this text\n"
         "\n"
         "exit status: 0 success; 1 bad input; 2 bad usage; 3 the solver did not converge;\n"
         "4 the fit converged but the report warns that some parameter is not determined by\n"
         "this drive (see WARNINGS): the YAML is written, do not use those numbers blindly\n";
}

TricycleCliOptions parseTricycleCliArguments(const std::vector<std::string>& arguments)
{
  TricycleCliOptions options;
  std::vector<std::string> datasets;
  double max_iterations = options.calibration.max_iterations;
  ArgumentParser parser;
  parser.option("--output", &options.output_path)
      .number("--interval", &options.keyframe_interval_s)
      .number("--translation-sigma", &options.calibration.translation_sigma_m)
      .number("--rotation-sigma", &options.calibration.rotation_sigma_rad)
      .number("--huber", &options.calibration.huber_threshold)
      .number("--max-iterations", &max_iterations)
      .positionals(&datasets);
  if (!parser.parse(arguments)) {
    options.help = true;
    return options;
  }
  if (!(options.keyframe_interval_s > 0.0)) {
    throw ArgumentError("option --interval: the keyframe spacing must be > 0 s");
  }
  if (!(options.calibration.translation_sigma_m > 0.0)) {
    throw ArgumentError("option --translation-sigma: expected a standard deviation > 0 m");
  }
  if (!(options.calibration.rotation_sigma_rad > 0.0)) {
    throw ArgumentError("option --rotation-sigma: expected a standard deviation > 0 rad");
  }
  if (options.calibration.huber_threshold < 0.0) {
    throw ArgumentError("option --huber: expected a threshold >= 0 (0 = no robust loss)");
  }
  if (max_iterations < 1 || max_iterations > 1e6 || std::floor(max_iterations) != max_iterations) {
    throw ArgumentError("option --max-iterations: expected a whole number in [1, 1e6]");
  }
  options.calibration.max_iterations = static_cast<int>(max_iterations);
  if (datasets.empty()) {
    throw ArgumentError("missing the dataset file");
  }
  if (datasets.size() > 1) {
    throw ArgumentError("only one dataset file is accepted, got '" + datasets[0] + "' and '" +
                        datasets[1] + "'");
  }
  options.dataset_path = datasets[0];
  try {
    validate(options.calibration);
  } catch (const std::invalid_argument& error) {
    throw ArgumentError(error.what());
  }
  return options;
}

int runTricycleCli(const TricycleCliOptions& options, std::ostream& out, std::ostream& err)
{
  try {
    const TricycleDataset dataset = loadTricycleDataset(options.dataset_path);
    if (dataset.last_line_unterminated) {
      err << "warning: " << options.dataset_path
          << " does not end with a line end: the file may be truncated (its last sample, line "
          << dataset.rows.back().line << ", is used as read)\n";
    }
    if (dataset.rows.size() < 2) {
      err << "error: " << options.dataset_path << " holds "
          << (dataset.rows.empty() ? "no samples" : "a single sample")
          << "; a calibration needs a drive of many samples\n";
      return 1;
    }
    const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
    const TricycleParameters nominal = tricycleNominalFromHeader(dataset.header);
    const std::vector<EncoderSample> samples = decodeTricycleEncoders(dataset, layout);
    Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
    covariance.diagonal() << std::pow(options.calibration.translation_sigma_m, 2),
        std::pow(options.calibration.translation_sigma_m, 2),
        std::pow(options.calibration.rotation_sigma_rad, 2);
    const std::vector<MotionPair> pairs =
        tricyclePairs(dataset, samples, options.keyframe_interval_s, covariance);

    const TricycleCalibrationResult result =
        calibrateTricycle(pairs, layout, nominal, options.calibration);

    std::vector<Pose2> reference;
    reference.reserve(dataset.rows.size());
    for (const TricycleDatasetRow& row : dataset.rows) {
      reference.push_back(row.T_world_sensor);
    }
    std::vector<double> stamps_s;
    for (const EncoderSample& sample : samples) {
      stamps_s.push_back(sample.stamp_s);
    }
    std::vector<std::size_t> keyframes = {0};
    for (const KeyframeWindow& window :
         selectKeyframeWindows(stamps_s, options.keyframe_interval_s)) {
      keyframes.push_back(window.last);
    }
    const TricycleEvaluation evaluation =
        evaluateTricycle(result, layout, samples, reference, keyframes);

    out << "dataset: " << options.dataset_path << " (" << dataset.rows.size() << " samples, "
        << pairs.size() << " keyframe pairs at T = " << options.keyframe_interval_s << " s)\n\n";
    out << formatTricycleReport(result, evaluation);
    if (!options.output_path.empty()) {
      writeFileAtomically(options.output_path,
                          tricycleResultToYaml(result, evaluation, options.dataset_path));
      out << "\nresult written to " << options.output_path << "\n";
    }
    if (!result.converged)
      return 3;
    return result.warnings.empty() ? 0 : 4;
  } catch (const std::exception& error) {
    err << "error: " << error.what() << "\n";
    return 1;
  }
}

}  // namespace odometry_calibration
