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
  // Paired again at the estimated time offset by calibrate() when the configured one is off.
  source.run = runBags(options.bags, source.config, options.start_s, options.end_s, nullptr,
                       source.config.fit_intervals_s);
  CalibrateOutcome outcome = source.run.session->calibrate({});
  takeSessionPairs(&source.run);
  source.pairing = outcome.offset_pairing;
  if (source.pairing.paired_again)
    source.config.collector.time_offset_s = source.pairing.estimate_s;
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

/// The joint run's own files in <output> (beside each source's source_<k>/): those to write
/// (name, text) and an earlier run's to remove.
struct JointFiles
{
  std::vector<std::pair<std::string, std::string>> written;
  std::vector<std::string> removed;
};

/// The joint fit's files: result.yaml, laser_joints.urdf (one fixed joint per sensor, as the
/// node's ~save), controller.yaml (the joint wheels; removed when the model has none) and
/// joint_report.txt (`text`). Made before any file is written: what fails here (a diverged
/// solve's model) is a failure of the joint fit.
JointFiles jointFiles(const BagCalibrationOptions& options, const CalibrationConfig& config,
                      const JointFitReport& joint, const std::vector<JointSourceInput>& inputs,
                      const std::string& text)
{
  JointFiles files;
  files.written.emplace_back(kResultFileName,
                             jointResultYaml(config, joint, inputs, options.bags.front()));
  std::string urdf;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s)
    urdf += laserJointUrdf(joint.sensors[s].T_base_sensor, "base_link", inputs[s].frame);
  files.written.emplace_back("laser_joints.urdf", urdf);
  addControllerFile(jointControllerYaml(joint, options.bags.front()), &files.written,
                    &files.removed);
  files.written.emplace_back("joint_report.txt", text);
  return files;
}

/// The files of a run whose joint fit failed after every source was fitted alone:
/// joint_report.txt (`text`: each source's fit alone and the failure); an earlier run's joint
/// result.yaml, laser_joints.urdf and controller.yaml removed, so that none passes for this
/// run's beside its source_<k>/.
JointFiles failedJointFiles(const std::string& text)
{
  return {{{"joint_report.txt", text}}, {kResultFileName, "laser_joints.urdf", "controller.yaml"}};
}

/// The joint run's `files` and each source's under source_<k>/ written into `output_dir` as one
/// set (common/staged_file_set.h): all replaced, or none when one cannot be written. Returns
/// their names.
std::vector<std::string> writeJointFiles(const BagCalibrationOptions& options,
                                         const std::vector<SourceRun>& sources,
                                         const std::vector<std::string>& source_texts,
                                         const JointFiles& files, const std::string& output_dir)
{
  std::filesystem::create_directories(output_dir);
  StagedFileSet set(output_dir);
  std::vector<std::string> names;
  for (const auto& [name, content] : files.written) {
    writeFileAtomically(set.stagedPath(name), content);
    names.push_back(name);
  }
  for (std::size_t s = 0; s < sources.size(); ++s) {
    names.push_back("source_" + std::to_string(s));
    writeResultFiles(set.stagedPath(names.back()),
                     sourceFiles(options, sources[s], source_texts[s]));
  }
  set.commit(names, files.removed);
  return names;
}

}  // namespace

int calibrateBagsJointly(const BagCalibrationOptions& options, CalibrationConfig config,
                         std::ostream& out, const JointFitFunction& fit_jointly)
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
  JointFiles files;
  std::string failure;
  int status = 0;
  try {
    const JointFitReport joint = fit_jointly(config, inputs);
    // The joint table joins the text only once its files are made (a diverged solve's model
    // can still fail there, and a failed fit's report shows no table of it).
    std::string joint_text = text + "\n=== joint fit ===\n" + formatJointFitReport(joint, names);
    files = jointFiles(options, config, joint, inputs, joint_text);
    text = std::move(joint_text);
    for (std::size_t s = 0; s < joint.sensors.size(); ++s)
      status = std::max(status, calibrationExitStatus(sensorModelReport(joint, s)));
  } catch (const std::exception& error) {  // every source's fit alone is still written
    failure = "the joint " + config.model +
              " fit failed after every source was fitted alone: " + error.what();
    text += "\n=== joint fit ===\n" + failure + "\n";
    files = failedJointFiles(text);
  }
  out << text;
  // Written only once everything is fitted, as one set.
  const std::vector<std::string> written =
      writeJointFiles(options, sources, source_texts, files, output_dir);
  out << "\nwritten: " << output_dir << "/{";
  for (std::size_t k = 0; k < written.size(); ++k)
    out << (k == 0 ? "" : ", ") << written[k] << (written[k].rfind("source_", 0) == 0 ? "/" : "");
  out << "}\n";
  if (!failure.empty()) {
    throw std::runtime_error(failure + " (each source's fit alone is in " + output_dir +
                             "/source_<k>/; no joint result.yaml)");
  }
  return status;
}

}  // namespace odometry_calibration
