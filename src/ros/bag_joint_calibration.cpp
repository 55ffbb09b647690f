#include "odometry_calibration/ros/bag_joint_calibration.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/joint_source_fit.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/eval/joint_fit_text.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/report/controller_yaml.h"
#include "odometry_calibration/report/result_files.h"
#include "odometry_calibration/ros/bag_runner.h"

namespace odometry_calibration {
namespace {

/// One source's run of the bags and its fit alone.
struct SourceRun
{
  EgoMotionSourceConfig source;
  CalibrationConfig config;
  BagRunResult run;
  OffsetPairing pairing;
  std::optional<SessionFit> fit;
};

/// Source `index` paired on its own (at its estimated time offset when the configuration
/// estimates it) and fitted alone by its session.
SourceRun pairAndFitSource(const BagCalibrationOptions& options, const CalibrationConfig& config,
                           std::size_t index)
{
  SourceRun source;
  source.source = egoMotionSources(config).at(index);
  source.config = configForSource(config, index);
  // Paired also at keyframes.fit_intervals_s, the interval chosen among them, as the live
  // node's session of this source does (joint_calibration_session.h).
  source.run =
      runBagsAtEstimatedOffset(options.bags, &source.config, options.start_s, options.end_s,
                               nullptr, &source.pairing, 0.01, source.config.fit_intervals_s);
  CalibrationRequest request;
  request.offset_search = source.pairing.search;
  CalibrateOutcome outcome = source.run.session->calibrate(request);
  if (!outcome.fit)
    throw std::runtime_error("source '" + source.source.topic + "': " + outcome.message);
  source.fit = std::move(outcome.fit);
  return source;
}

/// What the joint fit takes from source `source`'s run and fit alone.
JointSourceInput jointInput(const SourceRun& source)
{
  return {source.source.topic,           source.run.session->sensorFrame(),
          source.fit->job.pairs,         source.fit->job.report.T_base_sensor,
          source.fit->job.time_offset_s, source.fit->fit_interval_s};
}

/// Each source's run and fit alone in words, its files under <output>/source_<k>/.
std::string describeSource(const BagCalibrationOptions& options, const SourceRun& source,
                           std::size_t index, const std::string& output_dir)
{
  const CalibrationJobResult& job = source.fit->job;
  std::string text = "\n=== source " + std::to_string(index) + ": " + source.source.topic +
                     " ===\n" + formatBagRunSummary(source.run) + source.pairing.text +
                     (job.time_offset ? formatTimeOffset(*job.time_offset) : "") + "\n" +
                     formatModelReport(job.report);
  ResultFiles files = resultFilesForJob(jointLayout(source.config), job, options.bags.front());
  files.gnuplot = options.gnuplot;
  files.markdown.bags = options.bags;
  files.markdown.data_span_s = source.run.bag_span_s;
  files.markdown.run_time_s = source.run.wall_time_s;
  files.markdown.statistics = source.run.statistics;
  files.markdown.collection_notes = bagRunNotes(source.run);
  files.text_report = text;
  writeResultFiles(output_dir + "/source_" + std::to_string(index), std::move(files));
  return text;
}

}  // namespace

int calibrateBagsJointly(const BagCalibrationOptions& options, CalibrationConfig config,
                         std::ostream& out)
{
  if (const std::string problem = jointFitModelProblem(config.model); !problem.empty())
    throw std::runtime_error(problem);
  const std::string output_dir =
      options.output_dir.empty() ? config.output_directory : options.output_dir;
  std::vector<SourceRun> sources;
  std::vector<JointSourceInput> inputs;
  std::vector<std::string> names;
  std::string text;
  for (std::size_t s = 0; s < config.ego_motion_sources.size(); ++s) {
    sources.push_back(pairAndFitSource(options, config, s));
    text += describeSource(options, sources.back(), s, output_dir);
    inputs.push_back(jointInput(sources.back()));
    names.push_back(sources.back().source.topic);
  }
  const JointFitReport joint = fitSourcesJointly(config, inputs);
  text += "\n=== joint fit ===\n" + formatJointFitReport(joint, names);
  out << text;
  std::filesystem::create_directories(output_dir);
  writeFileAtomically(output_dir + "/" + kResultFileName,
                      jointResultYaml(config, joint, inputs, options.bags.front()));
  writeFileAtomically(output_dir + "/joint_report.txt", text);
  // As the node's ~save: one fixed joint per sensor, the joint wheels for the controller.
  std::string urdf;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s)
    urdf += laserJointUrdf(joint.sensors[s].T_base_sensor, "base_link", inputs[s].frame);
  writeFileAtomically(output_dir + "/laser_joints.urdf", urdf);
  const std::string controller = controllerYaml(sensorModelReport(joint, 0), options.bags.front());
  if (!controller.empty())
    writeFileAtomically(output_dir + "/controller.yaml", controller);
  out << "\nwritten: " << output_dir << "/{" << kResultFileName << ", laser_joints.urdf, "
      << (controller.empty() ? "" : "controller.yaml, ") << "joint_report.txt, source_<k>/}\n";
  int status = 0;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s)
    status = std::max(status, calibrationExitStatus(sensorModelReport(joint, s)));
  return status;
}

}  // namespace odometry_calibration
