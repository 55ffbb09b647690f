#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/assistant/excitation_guidance.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/tricycle_model.h"
#include "odometry_calibration/sim/pair_generator.h"

namespace odometry_calibration {
namespace {

/// Named motions of the scripted drives.
enum class Drive
{
  kStraight,
  kReverse,
  kSpotLeft,
  kSpotRight,
  kArcLeft,
  kArcRight,
  kFullLeft,  ///< tricycle: a tight arc that saturates the steering
  kFullRight,
  kStrafeLeft,  ///< mecanum: sideways
  kStrafeRight,
};

sim::ScriptedMotion motion(Drive drive, bool tricycle)
{
  sim::ScriptedMotion m;
  m.duration_s = 3.0;
  switch (drive) {
    case Drive::kStraight:
      m.twist.vx_mps = 0.4;
      break;
    case Drive::kReverse:
      m.twist.vx_mps = -0.3;
      break;
    case Drive::kSpotLeft:
      m.twist.omega_radps = 1.0;
      break;
    case Drive::kSpotRight:
      m.twist.omega_radps = -1.0;
      break;
    case Drive::kArcLeft:
      m.twist.vx_mps = 0.4;
      m.twist.omega_radps = tricycle ? 0.15 : 0.6;  // tricycle: about 0.5 rad of steering
      break;
    case Drive::kArcRight:
      m.twist.vx_mps = 0.4;
      m.twist.omega_radps = tricycle ? -0.15 : -0.6;
      break;
    case Drive::kFullLeft:
      m.twist.vx_mps = 0.3;
      m.twist.omega_radps = 0.6;  // atan(0.6 * 1.54 / 0.3) > max_steering: full lock
      break;
    case Drive::kFullRight:
      m.twist.vx_mps = 0.3;
      m.twist.omega_radps = -0.6;
      break;
    case Drive::kStrafeLeft:
      m.twist.vy_mps = 0.3;
      break;
    case Drive::kStrafeRight:
      m.twist.vy_mps = -0.3;
      break;
  }
  return m;
}

/// A script repeating `cycle` (each motion 3 s, a 1 s stop between) `repeats` times.
sim::DrivePlanOptions script(const std::vector<Drive>& cycle, int repeats, bool tricycle)
{
  sim::DrivePlanOptions plan;
  plan.type = "scripted";
  for (int r = 0; r < repeats; ++r) {
    for (Drive drive : cycle) {
      plan.script.push_back(motion(drive, tricycle));
      plan.script.push_back({1.0, sim::Twist2()});
    }
  }
  return plan;
}

double scriptDuration(const sim::DrivePlanOptions& plan)
{
  double total = 0.0;
  for (const auto& m : plan.script)
    total += m.duration_s;
  return total;
}

const std::map<std::string, double> kDiffDriveTruth = {{"left_wheel_radius", 0.0765},
                                                       {"right_wheel_radius", 0.0775},
                                                       {"wheel_separation", 0.32},
                                                       {"sensor_x", 0.2},
                                                       {"sensor_y", 0.05},
                                                       {"sensor_theta", 0.1}};

sim::PairGeneratorOptions diffDriveRun(const sim::DrivePlanOptions& plan)
{
  sim::PairGeneratorOptions options;
  options.robot = {"diff_drive",
                   {{"wheel_radius_left_m", 0.0765},
                    {"wheel_radius_right_m", 0.0775},
                    {"wheel_separation_m", 0.32}}};
  options.T_base_sensor = Pose2(0.2, 0.05, 0.1);
  options.motion = plan;
  options.duration_s = scriptDuration(plan);
  options.interval_s = 0.3;
  return options;
}

ModelFactoryOptions diffDriveNominal()
{
  ModelFactoryOptions factory;
  factory.diff_drive.initial_left_radius_m = 0.077;
  factory.diff_drive.initial_right_radius_m = 0.077;
  factory.diff_drive.initial_separation_m = 0.33;
  factory.diff_drive.initial_T_base_sensor = Pose2(0.15, 0.0, 0.0);
  factory.diff_drive.yaw_starts = 1;
  return factory;
}

const std::map<std::string, double> kTricycleTruth = {
    {"steering_scale", 0.56},   {"traction_scale", 0.0106}, {"axis_length", 1.54},
    {"steering_offset", -0.06}, {"sensor_x", 0.3},          {"sensor_y", -0.1},
    {"sensor_theta", 0.05}};

sim::PairGeneratorOptions tricycleRun(const sim::DrivePlanOptions& plan)
{
  sim::PairGeneratorOptions options;
  options.robot = {"tricycle", {}};  // the defaults are the truth above
  options.T_base_sensor = Pose2(0.3, -0.1, 0.05);
  options.motion = plan;
  options.duration_s = scriptDuration(plan);
  options.interval_s = 0.3;
  return options;
}

ModelFactoryOptions tricycleNominal()
{
  ModelFactoryOptions factory;
  factory.tricycle.initial.steering_scale = 0.55;
  factory.tricycle.initial.traction_scale_m_per_turn = 0.0105;
  factory.tricycle.initial.axis_length_m = 1.5;
  factory.tricycle.initial.steering_offset_rad = 0.0;
  factory.tricycle.initial.T_base_sensor = Pose2(0.25, 0.0, 0.0);
  return factory;
}

const ParameterGuidance& find(const ExcitationStatus& status, const std::string& name)
{
  for (const auto& p : status.parameters) {
    if (p.name == name)
      return p;
  }
  throw std::runtime_error("no parameter " + name);
}

bool mentions(const std::vector<std::string>& texts, const std::string& phrase)
{
  return std::any_of(texts.begin(), texts.end(), [&](const std::string& text) {
    return text.find(phrase) != std::string::npos;
  });
}

ExcitationStatus feed(const std::string& model, const ModelFactoryOptions& factory,
                      const std::vector<MotionPair>& pairs)
{
  auto guidance = makeExcitationGuidance(model, factory, ExcitationGuidanceOptions());
  for (const MotionPair& pair : pairs)
    guidance->addPair(pair);
  return guidance->status();
}

/// Feeds the pairs one by one; whenever a parameter turns "enough" for the first time, fits
/// the model on the pairs so far and checks that the fitted value's error is below three
/// target sigmas (no premature "enough"). Returns the final status.
ExcitationStatus feedAndCheckNotPremature(const std::string& model, ModelFactoryOptions factory,
                                          const sim::GeneratedPairs& data,
                                          const std::map<std::string, double>& truth)
{
  factory.joints = data.joints;
  const std::vector<MotionPair>& pairs = data.pairs;
  auto guidance = makeExcitationGuidance(model, factory, ExcitationGuidanceOptions());
  std::map<std::string, bool> was_enough;
  int fits = 0;
  for (std::size_t i = 0; i < pairs.size(); ++i) {
    guidance->addPair(pairs[i]);
    const ExcitationStatus status = guidance->status();
    std::vector<std::string> turned;
    for (const auto& p : status.parameters) {
      if (p.enough && !was_enough[p.name])
        turned.push_back(p.name);
      was_enough[p.name] = p.enough;
      EXPECT_FALSE(p.enough && !p.missing_motions.empty()) << p.name;
    }
    if (turned.empty())
      continue;
    const std::vector<MotionPair> so_far(pairs.begin(), pairs.begin() + i + 1);
    std::unique_ptr<MotionModel> fitted = makeModel(model, factory);
    const ModelReport report = fitted->fit(so_far);
    ++fits;
    for (const std::string& name : turned) {
      const auto estimate =
          std::find_if(report.parameters.begin(), report.parameters.end(),
                       [&](const ParameterEstimate& e) { return e.name == name; });
      if (estimate == report.parameters.end())
        throw std::runtime_error("the fit reports no " + name);
      const double target = find(status, name).target_sigma;
      EXPECT_LT(std::abs(estimate->value - truth.at(name)), 3.0 * target)
          << name << " turned enough after " << i + 1 << " pairs with the fitted value "
          << estimate->value << " (truth " << truth.at(name) << ", target sigma " << target << ")";
    }
  }
  EXPECT_GT(fits, 0);
  const ExcitationStatus status = guidance->status();
  std::printf("%s: %d fits checked; %s\n", model.c_str(), fits, status.summary().c_str());
  return status;
}

const std::vector<Drive> kAllDiffDrive = {Drive::kStraight, Drive::kSpotLeft,  Drive::kArcLeft,
                                          Drive::kReverse,  Drive::kSpotRight, Drive::kArcRight};

TEST(ExcitationGuidance, DiffDriveWithAllMotionsReachesEnoughAndNeverPrematurely)
{
  const auto data = sim::generatePairs(diffDriveRun(script(kAllDiffDrive, 12, false)));
  const ExcitationStatus status =
      feedAndCheckNotPremature("diff_drive", diffDriveNominal(), data, kDiffDriveTruth);
  EXPECT_TRUE(status.ready_to_fit) << status.summary();
  EXPECT_TRUE(status.missing_motions.empty());
  EXPECT_NE(status.summary().find("ready to fit"), std::string::npos);
}

TEST(ExcitationGuidance, DiffDriveWithoutLeftTurnsAsksForThem)
{
  const auto data = sim::generatePairs(diffDriveRun(
      script({Drive::kStraight, Drive::kSpotRight, Drive::kReverse, Drive::kArcRight}, 18, false)));
  const ExcitationStatus status = feed("diff_drive", diffDriveNominal(), data.pairs);
  std::printf("%s\n", status.summary().c_str());
  EXPECT_FALSE(status.ready_to_fit);
  EXPECT_TRUE(mentions(status.missing_motions, "turn on the spot to the left")) << status.summary();
  EXPECT_TRUE(mentions(status.missing_motions, "turn left"));
  EXPECT_FALSE(mentions(status.missing_motions, "right")) << status.summary();
  EXPECT_FALSE(mentions(status.missing_motions, "straight"));
  for (const char* name :
       {"left_wheel_radius", "right_wheel_radius", "wheel_separation", "sensor_x", "sensor_y"}) {
    EXPECT_FALSE(find(status, name).enough) << name;
    EXPECT_TRUE(mentions(find(status, name).missing_motions, "left")) << name;
  }
  EXPECT_TRUE(find(status, "sensor_theta").enough) << status.summary();
  EXPECT_NE(status.summary().find("turn on the spot to the left"), std::string::npos);
}

TEST(ExcitationGuidance, DiffDriveWithoutTurningOnTheSpotAsksForIt)
{
  const auto data = sim::generatePairs(diffDriveRun(
      script({Drive::kStraight, Drive::kArcLeft, Drive::kReverse, Drive::kArcRight}, 18, false)));
  const ExcitationStatus status = feed("diff_drive", diffDriveNominal(), data.pairs);
  std::printf("%s\n", status.summary().c_str());
  EXPECT_FALSE(status.ready_to_fit);
  EXPECT_TRUE(mentions(status.missing_motions, "turn on the spot to the left")) << status.summary();
  EXPECT_TRUE(mentions(status.missing_motions, "turn on the spot to the right"));
  EXPECT_EQ(status.missing_motions.size(), 2u) << status.summary();
  EXPECT_FALSE(find(status, "sensor_x").enough);
  EXPECT_FALSE(find(status, "sensor_y").enough);
  for (const char* name :
       {"left_wheel_radius", "right_wheel_radius", "wheel_separation", "sensor_theta"}) {
    EXPECT_TRUE(find(status, name).enough) << name << ": " << status.summary();
  }
}

const std::vector<Drive> kAllTricycle = {Drive::kStraight, Drive::kFullLeft,  Drive::kArcLeft,
                                         Drive::kReverse,  Drive::kFullRight, Drive::kArcRight};

TEST(ExcitationGuidance, TricycleWithAllMotionsReachesEnoughAndNeverPrematurely)
{
  const auto data = sim::generatePairs(tricycleRun(script(kAllTricycle, 15, true)));
  const ExcitationStatus status =
      feedAndCheckNotPremature("tricycle", tricycleNominal(), data, kTricycleTruth);
  EXPECT_TRUE(status.ready_to_fit) << status.summary();
}

TEST(ExcitationGuidance, TricycleWithoutFullLockAsksForIt)
{
  const auto data = sim::generatePairs(tricycleRun(
      script({Drive::kStraight, Drive::kArcLeft, Drive::kReverse, Drive::kArcRight}, 22, true)));
  const ExcitationStatus status = feed("tricycle", tricycleNominal(), data.pairs);
  std::printf("%s\n", status.summary().c_str());
  EXPECT_FALSE(status.ready_to_fit);
  EXPECT_TRUE(mentions(status.missing_motions, "steer full left while driving"))
      << status.summary();
  EXPECT_TRUE(mentions(status.missing_motions, "steer full right while driving"));
  for (const char* name : {"steering_scale", "sensor_x", "sensor_y"})
    EXPECT_FALSE(find(status, name).enough) << name;
  EXPECT_TRUE(find(status, "traction_scale").enough) << status.summary();
}

TEST(ExcitationGuidance, SigmasAtTheFittedValuesMatchTheFitsOwn)
{
  // The guidance's sigma is the Cramer-Rao bound of the fit: at the fitted values, on the same
  // pairs (noise as stated), it agrees with the fit's covariance.
  const auto data = sim::generatePairs(diffDriveRun(script(kAllDiffDrive, 6, false)));
  ModelFactoryOptions factory = diffDriveNominal();
  factory.joints = data.joints;
  std::unique_ptr<MotionModel> model = makeModel("diff_drive", factory);
  const ModelReport report = model->fit(data.pairs);
  ASSERT_TRUE(report.converged);
  auto guidance =
      makeExcitationGuidance("diff_drive", factory, ExcitationGuidanceOptions(), report.parameters);
  for (const MotionPair& pair : data.pairs)
    guidance->addPair(pair);
  const ExcitationStatus status = guidance->status();
  for (const ParameterEstimate& estimate : report.parameters) {
    const ParameterGuidance& p = find(status, estimate.name);
    EXPECT_DOUBLE_EQ(p.value, estimate.value) << estimate.name;
    std::printf("%s: guidance sigma / fit sigma = %.3f\n", estimate.name.c_str(),
                p.sigma / estimate.sigma);
    EXPECT_NEAR(p.sigma / estimate.sigma, 1.0, 0.25)
        << estimate.name << ": guidance " << p.sigma << ", fit " << estimate.sigma;
  }
  EXPECT_THROW(makeExcitationGuidance("diff_drive", factory, ExcitationGuidanceOptions(),
                                      {{"axis_length", "m", 1.0, 1.0, 0.1}}),
               std::invalid_argument);
}

const std::map<std::string, double> kMecanumTruth = {{"wheel_radius_front_left", 0.05},
                                                     {"wheel_radius_front_right", 0.05},
                                                     {"wheel_radius_rear_left", 0.05},
                                                     {"wheel_radius_rear_right", 0.05},
                                                     {"lx_plus_ly", 0.35},
                                                     {"sensor_x", 0.2},
                                                     {"sensor_y", 0.05},
                                                     {"sensor_theta", 0.1}};

sim::PairGeneratorOptions mecanumRun(const sim::DrivePlanOptions& plan)
{
  sim::PairGeneratorOptions options;
  options.robot = {"mecanum", {}};  // radii 0.05 m, lx + ly = 0.35 m
  options.T_base_sensor = Pose2(0.2, 0.05, 0.1);
  options.motion = plan;
  options.duration_s = scriptDuration(plan);
  options.interval_s = 0.3;
  return options;
}

ModelFactoryOptions mecanumNominal()
{
  ModelFactoryOptions factory;
  factory.mecanum.layout.ticks_per_turn = 1000.0;
  factory.mecanum.initial_radius_m = {0.051, 0.049, 0.05, 0.0505};
  factory.mecanum.initial_lx_plus_ly_m = 0.34;
  factory.mecanum.initial_T_base_sensor = Pose2(0.15, 0.0, 0.0);
  factory.mecanum.yaw_starts = 1;
  return factory;
}

TEST(ExcitationGuidance, MecanumWithAllMotionsReachesEnoughAndWithoutStrafingAsksForIt)
{
  const std::vector<Drive> all = {Drive::kStraight,  Drive::kStrafeLeft, Drive::kSpotLeft,
                                  Drive::kArcLeft,   Drive::kReverse,    Drive::kStrafeRight,
                                  Drive::kSpotRight, Drive::kArcRight};
  const auto data = sim::generatePairs(mecanumRun(script(all, 10, false)));
  const ExcitationStatus status =
      feedAndCheckNotPremature("mecanum", mecanumNominal(), data, kMecanumTruth);
  EXPECT_TRUE(status.ready_to_fit) << status.summary();

  const auto no_strafe =
      sim::generatePairs(mecanumRun(script({Drive::kStraight, Drive::kSpotLeft, Drive::kArcLeft,
                                            Drive::kReverse, Drive::kSpotRight, Drive::kArcRight},
                                           14, false)));
  const ExcitationStatus missing = feed("mecanum", mecanumNominal(), no_strafe.pairs);
  std::printf("%s\n", missing.summary().c_str());
  EXPECT_FALSE(missing.ready_to_fit);
  EXPECT_TRUE(mentions(missing.missing_motions, "strafe to the left")) << missing.summary();
  EXPECT_TRUE(mentions(missing.missing_motions, "strafe to the right"));
  // Without sideways motion one combination of the radii is not seen at all: their sigma stays
  // at the prior's scale, far above the target.
  for (const char* name : {"wheel_radius_front_left", "wheel_radius_front_right",
                           "wheel_radius_rear_left", "wheel_radius_rear_right"}) {
    EXPECT_FALSE(find(missing, name).enough) << name;
    EXPECT_GT(find(missing, name).sigma, 10.0 * find(missing, name).target_sigma) << name;
  }
}

TEST(ExcitationGuidance, NoPairsMeansEverythingCollecting)
{
  auto guidance =
      makeExcitationGuidance("diff_drive", diffDriveNominal(), ExcitationGuidanceOptions());
  const ExcitationStatus status = guidance->status();
  EXPECT_EQ(status.pairs, 0u);
  EXPECT_FALSE(status.ready_to_fit);
  EXPECT_EQ(status.missing_motions.size(), 5u);  // straight, 2 turns, 2 on the spot
  for (const auto& p : status.parameters)
    EXPECT_GT(p.sigma, 100.0 * p.target_sigma) << p.name;
}

TEST(ExcitationGuidance, TargetsFollowTheOptions)
{
  ExcitationGuidanceOptions options;
  options.target_sigma["wheel_separation"] = 0.001;
  auto guidance = makeExcitationGuidance("diff_drive", diffDriveNominal(), options);
  const ExcitationStatus status = guidance->status();
  EXPECT_DOUBLE_EQ(find(status, "wheel_separation").target_sigma, 0.001);
  EXPECT_DOUBLE_EQ(find(status, "left_wheel_radius").target_sigma, 0.002 * 0.077);
  EXPECT_DOUBLE_EQ(find(status, "sensor_x").target_sigma, 0.005);
  EXPECT_DOUBLE_EQ(find(status, "sensor_theta").target_sigma, 0.005);
}

TEST(ExcitationGuidance, RejectsUnsupportedModelsAndBadOptions)
{
  EXPECT_THROW(makeExcitationGuidance("gp", diffDriveNominal(), ExcitationGuidanceOptions()),
               std::invalid_argument);
  ExcitationGuidanceOptions options;
  options.target_sigma["sensor_x"] = -1.0;
  EXPECT_THROW(makeExcitationGuidance("diff_drive", diffDriveNominal(), options),
               std::invalid_argument);
  EXPECT_TRUE(hasExcitationGuidance("tricycle"));
  EXPECT_FALSE(hasExcitationGuidance("linear"));
}

TEST(ExcitationGuidance, SkipsPairsWithoutSamplesOrCovariance)
{
  auto guidance =
      makeExcitationGuidance("diff_drive", diffDriveNominal(), ExcitationGuidanceOptions());
  MotionPair pair;
  guidance->addPair(pair);
  EXPECT_EQ(guidance->skipped(), 1u);
  EXPECT_EQ(guidance->status().pairs, 0u);
}

}  // namespace
}  // namespace odometry_calibration
