#include "odometry_calibration/ros/bag_joint_calibration.h"

#include <cstdio>
#include <filesystem>
#include <stdexcept>

#include <yaml-cpp/yaml.h>

#include "odometry_calibration/calibration/calibration_result.h"
#include "odometry_calibration/common/atomic_file.h"
#include "odometry_calibration/eval/joint_fit_text.h"
#include "odometry_calibration/eval/model_report.h"
#include "odometry_calibration/models/joint_fits.h"
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
  source.run = runBagsAtEstimatedOffset(options.bags, &source.config, options.start_s,
                                        options.end_s, nullptr, &source.pairing);
  CalibrationRequest request;
  request.offset_search = source.pairing.search;
  CalibrateOutcome outcome = source.run.session->calibrate(request);
  if (!outcome.fit)
    throw std::runtime_error("source '" + source.source.topic + "': " + outcome.message);
  source.fit = std::move(outcome.fit);
  return source;
}

/// The joint wheels with sensor `index`'s pose as a model (what result.yaml's `model` holds).
std::shared_ptr<MotionModel> jointModel(const CalibrationConfig& config,
                                        const JointFitReport& joint, std::size_t index)
{
  if (config.model == "mecanum") {
    MecanumOptions options = config.models.mecanum;
    for (std::size_t wheel = 0; wheel < 4; ++wheel)
      options.initial_radius_m[wheel] = joint.intrinsics.at(wheel).value;
    options.initial_lx_plus_ly_m = joint.intrinsics.at(4).value;
    options.initial_T_base_sensor = joint.sensors.at(index).T_base_sensor;
    return std::make_shared<MecanumModel>(options);
  }
  DiffDriveOptions options = config.models.diff_drive;
  options.initial_left_radius_m = joint.intrinsics.at(0).value;
  options.initial_right_radius_m = joint.intrinsics.at(1).value;
  options.initial_separation_m = joint.intrinsics.at(2).value;
  options.initial_T_base_sensor = joint.sensors.at(index).T_base_sensor;
  return std::make_shared<DiffDriveModel>(options);
}

/// result.yaml of the joint fit: the first sensor's view as the one-sensor result (so that the
/// node loads it), then `sensors`: every sensor's topic, frame, pose with σ and time offset.
std::string jointResultYaml(const CalibrationConfig& config, const JointFitReport& joint,
                            const std::vector<SourceRun>& sources, const std::string& bag)
{
  std::string text =
      calibrationResultYaml(sensorModelReport(joint, 0), *jointModel(config, joint, 0), bag,
                            sources.front().fit->job.time_offset_s, jointLayout(config).names);
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap << YAML::Key << "sensors" << YAML::Value << YAML::BeginSeq;
  for (std::size_t s = 0; s < sources.size(); ++s) {
    const JointSensorReport& sensor = joint.sensors[s];
    out << YAML::BeginMap;
    out << YAML::Key << "topic" << YAML::Value << sources[s].source.topic;
    out << YAML::Key << "frame" << YAML::Value << sources[s].run.session->sensorFrame();
    out << YAML::Key << "T_base_sensor" << YAML::Value << YAML::BeginMap;
    const char* keys[3] = {"x_m", "y_m", "theta_rad"};
    for (int i = 0; i < 3; ++i) {
      out << YAML::Key << keys[i] << YAML::Value << sensor.pose[i].value;
      out << YAML::Key << (std::string(keys[i]) + "_sigma") << YAML::Value << sensor.pose[i].sigma;
    }
    out << YAML::EndMap;
    out << YAML::Key << "time_offset_s" << YAML::Value << sources[s].fit->job.time_offset_s;
    out << YAML::Key << "pairs" << YAML::Value << sensor.pairs;
    out << YAML::EndMap;
  }
  out << YAML::EndSeq << YAML::EndMap;
  return text + out.c_str() + "\n";
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
  if (config.model != "diff_drive" && config.model != "mecanum") {
    throw std::runtime_error(
        "ego_motion.sources: the joint fit of several sources supports "
        "models diff_drive and mecanum so far, not '" +
        config.model + "' (calibrate each source alone with a one-source configuration)");
  }
  const std::string output_dir =
      options.output_dir.empty() ? config.output_directory : options.output_dir;
  std::vector<SourceRun> sources;
  std::vector<std::vector<MotionPair>> pairs;
  std::vector<Pose2> starts;
  std::vector<std::string> names;
  std::string text;
  for (std::size_t s = 0; s < config.ego_motion_sources.size(); ++s) {
    sources.push_back(pairAndFitSource(options, config, s));
    text += describeSource(options, sources.back(), s, output_dir);
    pairs.push_back(sources.back().fit->job.pairs);
    starts.push_back(sources.back().fit->job.report.T_base_sensor);
    names.push_back(sources.back().source.topic);
  }
  const JointFitReport joint = config.model == "mecanum"
                                   ? fitJointMecanum(config.models.mecanum, pairs, starts)
                                   : fitJointDiffDrive(config.models.diff_drive, pairs, starts);
  text += "\n=== joint fit ===\n" + formatJointFitReport(joint, names);
  out << text;
  std::filesystem::create_directories(output_dir);
  writeFileAtomically(output_dir + "/" + kResultFileName,
                      jointResultYaml(config, joint, sources, options.bags.front()));
  writeFileAtomically(output_dir + "/joint_report.txt", text);
  out << "\nwritten: " << output_dir << "/{" << kResultFileName
      << ", joint_report.txt, source_<k>/}\n";
  int status = 0;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s)
    status = std::max(status, calibrationExitStatus(sensorModelReport(joint, s)));
  return status;
}

}  // namespace odometry_calibration
