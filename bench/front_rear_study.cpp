// Issue 35's acceptance on simulated runs: a differential drive with a front and a rear laser
// (config/sim/scenarios/diff_drive_front_rear.yaml), each laser's scans paired against the same
// encoder track by a pair collector of its own, each laser's time offset estimated from its own
// pairs (when asked), then one joint fit of the wheels and both poses. Not a timing benchmark:
// an accuracy study on whole simulated runs (sim::simulate in process, no bag), printing per
// seed the errors of the joint fit, its radius sigma against each laser's fit alone, and the
// agreement of the fits alone.
//
// Usage: study_front_rear [--seeds 101,102] [--duration S] [--rear-offset S]
//                         [--estimate-offsets]   (each laser's time offset from its pairs)
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "odometry_calibration/calibration/time_offset.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/joint_fits.h"
#include "odometry_calibration/pairing/pair_collector.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/scenario.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/world.h"
#include "support/sim_recording.h"

namespace odometry_calibration {
namespace {

/// The nominal robot a user would configure: equal radii, a rounded separation, each laser's
/// pose as drawn (no 0.03 rad, no 2 cm).
DiffDriveOptions nominal(const Pose2& T_base_sensor)
{
  DiffDriveOptions options;
  options.layout = {0, 1, 2000.0};
  options.initial_left_radius_m = 0.077;
  options.initial_right_radius_m = 0.077;
  options.initial_separation_m = 0.33;
  options.initial_T_base_sensor = T_base_sensor;
  return options;
}

const std::vector<Pose2> kNominalPoses = {Pose2(0.3, 0.0, 0.0), Pose2(-0.3, 0.0, M_PI)};

/// Feeds each laser's scans to its own collector, the encoders to all of them.
struct TwoLaserFeeder : sim::SimulationSink
{
  std::vector<std::unique_ptr<PairCollector>> collectors;
  std::vector<std::vector<MotionPair>> pairs;
  std::vector<EncoderSample> history;
  EncoderDecoder decoder{channels()};

  static std::vector<EncoderChannelOptions> channels()
  {
    return {{"left_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0},
            {"right_wheel", EncoderKind::kIncremental, 4294967296.0, 0.0}};
  }

  TwoLaserFeeder()
  {
    for (const Pose2& pose : kNominalPoses) {
      auto prior = std::make_shared<DiffDriveModel>(nominal(pose));
      collectors.push_back(std::make_unique<PairCollector>(
          channels(), CollectorOptions(), [prior](const std::vector<EncoderSample>& samples) {
            return prior->predict(samples).mean;
          }));
    }
    pairs.resize(collectors.size());
  }
  void onJointState(const sim::JointStateSample& s) override
  {
    const Eigen::Map<const Eigen::VectorXd> raw(s.positions.data(), 2);
    history.push_back({s.stamp_s, decoder.decode(raw)});
    for (std::size_t k = 0; k < collectors.size(); ++k)
      take(k, collectors[k]->addEncoders(s.stamp_s, raw));
  }
  void onScan(const sim::ScanSample& s) override
  {
    take(s.laser_index, collectors.at(s.laser_index)->addScan(s.stamp_s, test::toScan(s)));
  }
  void onTruth(const sim::TruthSample&) override {}
  void finish()
  {
    for (std::size_t k = 0; k < collectors.size(); ++k)
      take(k, collectors[k]->flush());
  }
  void take(std::size_t k, const std::vector<CollectorEvent>& events)
  {
    for (const CollectorEvent& event : events) {
      if (event.type == CollectorEvent::Type::kPair)
        pairs[k].push_back(event.pair);
    }
  }
};

struct StudyOptions
{
  std::vector<unsigned> seeds = {101, 102, 103};
  double duration_s = 180.0;
  double rear_offset_s = 0.0;
  bool estimate_offsets = false;
};

/// Each laser's time offset estimated from its own pairs (its own model alone), the pairs
/// rewindowed at it; prints the estimates.
void estimateOffsets(TwoLaserFeeder& feeder)
{
  for (std::size_t k = 0; k < feeder.pairs.size(); ++k) {
    TimeOffsetOptions options;
    options.min_s = -0.2;
    options.max_s = 0.2;
    const Pose2 pose = kNominalPoses[k];
    const TimeOffsetResult offset = estimateTimeOffset(
        feeder.pairs[k], feeder.history,
        [pose]() { return std::make_unique<DiffDriveModel>(nominal(pose)); }, options);
    std::printf("  laser %zu: time offset %+.4f s (sigma %.4f s)\n", k, offset.offset_s,
                offset.sigma_s);
    feeder.pairs[k] = rewindowPairs(feeder.pairs[k], feeder.history, offset.offset_s);
  }
}

void printSeed(const sim::Scenario& scenario, const JointFitReport& report)
{
  const double truth[] = {scenario.robot.parameters.at("wheel_radius_left_m"),
                          scenario.robot.parameters.at("wheel_radius_right_m"),
                          scenario.robot.parameters.at("wheel_separation_m")};
  for (int i = 0; i < 3; ++i) {
    const ParameterEstimate& joint = report.intrinsics[i];
    std::printf("  %-20s error %+.4f %%  sigma joint %.3g  alone %.3g / %.3g\n", joint.name.c_str(),
                100.0 * (joint.value / truth[i] - 1.0), joint.sigma,
                report.alone[0].parameters[i].sigma, report.alone[1].parameters[i].sigma);
  }
  const std::vector<sim::LaserOptions> lasers = sim::allLasers(scenario);
  for (std::size_t k = 0; k < report.sensors.size(); ++k) {
    const Pose2& fit = report.sensors[k].T_base_sensor;
    const Pose2& true_pose = lasers[k].T_base_laser;
    std::printf("  laser %zu (%zu pairs): x %+.2f mm  y %+.2f mm  theta %+.4f deg\n", k,
                report.sensors[k].pairs, 1e3 * (fit.x() - true_pose.x()),
                1e3 * (fit.y() - true_pose.y()),
                normalizeAngle(fit.theta() - true_pose.theta()) * 180.0 / M_PI);
  }
  std::printf("  alone fits' largest relative spread: %.4f %%\n",
              100.0 * aloneIntrinsicsSpread(report));
}

void runSeed(const StudyOptions& options, unsigned seed)
{
  sim::Scenario scenario = sim::loadScenarioYaml(
      std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/scenarios/diff_drive_front_rear.yaml",
      sim::shippedWorldsDirectory());
  scenario.seed = seed;
  scenario.duration_s = options.duration_s;
  scenario.extra_lasers.at(0).time_offset_s = options.rear_offset_s;
  const sim::World world = sim::loadWorldYaml(scenario.world_path);
  const auto robot = sim::makeRobot(scenario.robot);
  TwoLaserFeeder feeder;
  sim::simulate(scenario, world, *robot, feeder);
  feeder.finish();
  std::printf("seed %u:\n", seed);
  if (options.estimate_offsets)
    estimateOffsets(feeder);
  const JointFitReport report = fitJointDiffDrive(nominal(Pose2()), feeder.pairs, kNominalPoses);
  printSeed(scenario, report);
}

StudyOptions parse(int argc, char** argv)
{
  StudyOptions options;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--seeds" && has_value) {
      options.seeds.clear();
      std::stringstream list(argv[++i]);
      for (std::string seed; std::getline(list, seed, ',');)
        options.seeds.push_back(static_cast<unsigned>(std::stoul(seed)));
    } else if (arg == "--duration" && has_value) {
      options.duration_s = std::stod(argv[++i]);
    } else if (arg == "--rear-offset" && has_value) {
      options.rear_offset_s = std::stod(argv[++i]);
    } else if (arg == "--estimate-offsets") {
      options.estimate_offsets = true;
    } else {
      throw std::invalid_argument("unknown argument '" + arg + "' (see the file comment)");
    }
  }
  return options;
}

}  // namespace
}  // namespace odometry_calibration

int main(int argc, char** argv)
{
  try {
    const odometry_calibration::StudyOptions options = odometry_calibration::parse(argc, argv);
    for (unsigned seed : options.seeds)
      odometry_calibration::runSeed(options, seed);
  } catch (const std::exception& error) {
    std::fprintf(stderr, "study_front_rear: %s\n", error.what());
    return 1;
  }
  return 0;
}
