#include "odometry_calibration/ros/bag_joint_calibration.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/calibration/joint_source_fit.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/common/staged_file_set.h"
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

/// Each source's run and fit alone in words.
std::string describeSource(const SourceRun& source, std::size_t index)
{
  const CalibrationJobResult& job = source.fit->job;
  return "\n=== source " + std::to_string(index) + ": " + source.source.topic + " ===\n" +
         formatBagRunSummary(source.run) + source.pairing.text +
         (job.time_offset ? formatTimeOffset(*job.time_offset) : "") + "\n" +
         formatModelReport(job.report);
}

/// Source `index`'s files (its pairs, result, reports and plots, as a one-source run writes
/// them), `text` its part of the terminal's report.
ResultFiles sourceFiles(const BagCalibrationOptions& options, const SourceRun& source,
                        const std::string& text)
{
  ResultFiles files =
      resultFilesForJob(jointLayout(source.config), source.fit->job, options.bags.front());
  files.gnuplot = options.gnuplot;
  files.markdown.bags = options.bags;
  files.markdown.data_span_s = source.run.bag_span_s;
  files.markdown.run_time_s = source.run.wall_time_s;
  files.markdown.statistics = source.run.statistics;
  files.markdown.collection_notes = bagRunNotes(source.run);
  files.text_report = text;
  return files;
}

/// The options a joint run does not take (it fits every source's pairs at its own fit interval
/// and tests nothing): named, so that none is silently ignored.
void refuseSingleSourceOptions(const BagCalibrationOptions& options)
{
  const char* option = !options.test_bags.empty()  ? "--test"
                       : options.holdout > 0.0     ? "--holdout"
                       : !options.interval.empty() ? "--interval"
                                                   : nullptr;
  if (option) {
    throw std::invalid_argument(
        std::string("option ") + option +
        " is not supported with several ego-motion sources (ego_motion.sources): calibrate one "
        "source at a time with a one-source configuration to use it");
  }
}

/// The joint run's files written into `output_dir` as one set (common/staged_file_set.h): each
/// source's under source_<k>/, the joint result.yaml, joint_report.txt, laser_joints.urdf and
/// controller.yaml (removed when the model has none); all replaced, or none when one cannot be
/// written. Returns their names.
std::vector<std::string> writeJointFiles(const BagCalibrationOptions& options,
                                         const CalibrationConfig& config,
                                         const std::vector<SourceRun>& sources,
                                         const std::vector<std::string>& source_texts,
                                         const JointFitReport& joint,
                                         const std::vector<JointSourceInput>& inputs,
                                         const std::string& text, const std::string& output_dir)
{
  std::filesystem::create_directories(output_dir);
  StagedFileSet set(output_dir);
  std::vector<std::string> names, removed;
  auto add = [&](const std::string& name, const std::string& content) {
    writeFileAtomically(set.stagedPath(name), content);
    names.push_back(name);
  };
  add(kResultFileName, jointResultYaml(config, joint, inputs, options.bags.front()));
  // As the node's ~save: one fixed joint per sensor, the joint wheels for the controller.
  std::string urdf;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s)
    urdf += laserJointUrdf(joint.sensors[s].T_base_sensor, "base_link", inputs[s].frame);
  add("laser_joints.urdf", urdf);
  const std::string controller = jointControllerYaml(joint, options.bags.front());
  if (!controller.empty())
    add("controller.yaml", controller);
  else  // an earlier calibration's controller values must not pass for this one's
    removed.push_back("controller.yaml");
  add("joint_report.txt", text);
  for (std::size_t s = 0; s < sources.size(); ++s) {
    names.push_back("source_" + std::to_string(s));
    writeResultFiles(set.stagedPath(names.back()),
                     sourceFiles(options, sources[s], source_texts[s]));
  }
  set.commit(names, removed);
  return names;
}

}  // namespace

int calibrateBagsJointly(const BagCalibrationOptions& options, CalibrationConfig config,
                         std::ostream& out)
{
  if (const std::string problem = jointFitModelProblem(config.model); !problem.empty())
    throw std::runtime_error(problem);
  refuseSingleSourceOptions(options);
  if (!config.compare_models.empty()) {
    out << "note: compare_models is not fitted with several ego-motion sources (the joint fit is "
           "of "
        << config.model << " only)\n";
  }
  const std::string output_dir =
      options.output_dir.empty() ? config.output_directory : options.output_dir;
  std::vector<SourceRun> sources;
  std::vector<JointSourceInput> inputs;
  std::vector<std::string> names, source_texts;
  std::string text;
  for (std::size_t s = 0; s < config.ego_motion_sources.size(); ++s) {
    sources.push_back(pairAndFitSource(options, config, s));
    source_texts.push_back(describeSource(sources.back(), s));
    text += source_texts.back();
    inputs.push_back(jointInput(sources.back()));
    names.push_back(sources.back().source.topic);
  }
  const JointFitReport joint = fitSourcesJointly(config, inputs);
  text += "\n=== joint fit ===\n" + formatJointFitReport(joint, names);
  out << text;
  // Written only once everything is fitted, as one set.
  const std::vector<std::string> written =
      writeJointFiles(options, config, sources, source_texts, joint, inputs, text, output_dir);
  out << "\nwritten: " << output_dir << "/{";
  for (std::size_t k = 0; k < written.size(); ++k)
    out << (k == 0 ? "" : ", ") << written[k] << (written[k].rfind("source_", 0) == 0 ? "/" : "");
  out << "}\n";
  int status = 0;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s)
    status = std::max(status, calibrationExitStatus(sensorModelReport(joint, s)));
  return status;
}

}  // namespace odometry_calibration
