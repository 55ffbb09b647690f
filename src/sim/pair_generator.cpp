#include "odometry_calibration/sim/pair_generator.h"

#include <cmath>
#include <random>
#include <stdexcept>

#include "odometry_calibration/data/encoder.h"
#include "odometry_calibration/data/keyframes.h"
#include "odometry_calibration/sim/simulator.h"

namespace odometry_calibration {
namespace sim {
namespace {

/// Keeps the joint states and the truth of each encoder instant.
struct Collector : SimulationSink
{
  std::vector<JointStateSample> joints;
  std::vector<Pose2> T_world_sensor;
  std::vector<ImuSample> imu;
  void onJointState(const JointStateSample& s) override { joints.push_back(s); }
  void onImu(const ImuSample& s) override { imu.push_back(s); }
  void onScan(const ScanSample&) override {}
  void onTruth(const TruthSample& s) override
  {
    T_world_sensor.push_back(s.T_world_base * s.T_base_laser);
  }
};

/// The run's encoder instants and truth: the options' robot driving in an open field (the
/// scans are not used: two rays, one scan).
Collector simulateInOpenField(const PairGeneratorOptions& options, const Robot& robot)
{
  Scenario scenario;
  scenario.seed = options.seed;
  scenario.duration_s = options.duration_s;
  scenario.robot = options.robot;
  scenario.motion = options.motion;
  scenario.encoders.rate_hz = options.encoder_rate_hz;
  scenario.changes = options.changes;
  scenario.imu = options.imu;
  scenario.laser.T_base_laser = options.T_base_sensor;
  scenario.laser.rays = 2;  // scans are not used here: keep them cheap
  scenario.laser.rate_hz = 1.0 / options.duration_s;
  const World field = parseWorldYaml(
      "polygons:\n  - [[-200, -200], [200, -200], [200, 200], [-200, 200]]\n", "open field");
  Collector collector;
  simulate(scenario, field, robot, collector);
  return collector;
}

/// The joint states decoded (incremental counters of 32 bits), into `samples` and `stamps`;
/// the joints' names and kinds into `joints`.
void decodeJointStates(const Robot& robot, const std::vector<JointStateSample>& joint_states,
                       JointLayout& joints, std::vector<EncoderSample>& samples,
                       std::vector<double>& stamps)
{
  std::vector<EncoderChannelOptions> channels;
  for (const JointEncoderSpec& spec : robot.joints()) {
    joints.names.push_back(spec.name);
    joints.kinds.push_back(spec.kind);
    channels.push_back({spec.name, spec.kind,
                        spec.kind == EncoderKind::kIncremental ? 4294967296.0 : 0.0,
                        spec.kind == EncoderKind::kAbsolute ? spec.ticks_per_rev : 0.0});
  }
  EncoderDecoder decoder(channels);
  for (const JointStateSample& joint : joint_states) {
    samples.push_back({joint.stamp_s, decoder.decode(Eigen::Map<const Eigen::VectorXd>(
                                          joint.positions.data(),
                                          static_cast<Eigen::Index>(joint.positions.size())))});
    stamps.push_back(joint.stamp_s);
  }
}

}  // namespace

GeneratedPairs generatePairs(const PairGeneratorOptions& options)
{
  if (!(options.interval_s > 0.0) || options.translation_noise_m < 0.0 ||
      options.rotation_noise_rad < 0.0) {
    throw std::invalid_argument("pair generator: interval_s must be > 0 and noise >= 0");
  }
  const auto robot = makeRobot(options.robot);
  const Collector collector = simulateInOpenField(options, *robot);
  GeneratedPairs generated;
  generated.imu = collector.imu;
  std::vector<EncoderSample> samples;
  std::vector<double> stamps;
  decodeJointStates(*robot, collector.joints, generated.joints, samples, stamps);
  std::mt19937_64 rng(options.seed ^ 0xfa1c0ULL);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  covariance.diagonal() << std::pow(options.translation_noise_m, 2),
      std::pow(options.translation_noise_m, 2), std::pow(options.rotation_noise_rad, 2);
  for (const KeyframeWindow& window : selectKeyframeWindows(stamps, options.interval_s)) {
    MotionPair pair;
    pair.start_stamp_s = stamps[window.first];
    pair.end_stamp_s = stamps[window.last];
    pair.encoder_samples.assign(samples.begin() + static_cast<std::ptrdiff_t>(window.first),
                                samples.begin() + static_cast<std::ptrdiff_t>(window.last) + 1);
    const Pose2 truth =
        between(collector.T_world_sensor[window.first], collector.T_world_sensor[window.last]);
    const double nx = options.translation_noise_m * normal(rng);
    const double ny = options.translation_noise_m * normal(rng);
    const double nt = options.rotation_noise_rad * normal(rng);
    pair.sensor_motion = Pose2(truth.x() + nx, truth.y() + ny, normalizeAngle(truth.theta() + nt));
    pair.covariance = covariance;
    generated.true_motions.push_back(truth);
    generated.pairs.push_back(std::move(pair));
  }
  return generated;
}

PairGeneratorOptions pairGeneratorOptions(const Scenario& scenario, PairGeneratorOptions options)
{
  options.robot = scenario.robot;
  options.T_base_sensor = scenario.laser.T_base_laser;
  options.motion = scenario.motion;
  options.encoder_rate_hz = scenario.encoders.rate_hz;
  options.duration_s = scenario.duration_s;
  options.seed = scenario.seed;
  options.changes = scenario.changes;
  options.imu = scenario.imu;
  return options;
}
}  // namespace sim
}  // namespace odometry_calibration
