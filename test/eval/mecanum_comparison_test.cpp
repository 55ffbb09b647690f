// The paper's Table IV on the simulator: the deformed mecanum robot (T1: the front-left axis
// yawed by 3 and 6 deg, T2: the front-left wheel tilted by 20 deg; config/sim/scenarios, 300 s
// each) on generated pairs with a known noise (2 mm / 2 mrad), keyframe interval 0.5 s. Nominal
// (the undeformed robot's model, no fit), the fitted mecanum model, the linear model and the GP,
// trained on one run and scored on another (seed + 1000).
#include <cmath>
#include <iostream>

#include <gtest/gtest.h>

#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/sim/pair_generator.h"
#include "odometry_calibration/sim/scenario.h"

namespace odometry_calibration {
namespace {

const std::string kScenarios = std::string(ODOMETRY_CALIBRATION_CONFIG_DIR) + "/sim/scenarios";
constexpr double kNoiseM = 0.002;
constexpr double kNoiseRad = 0.002;

struct Table
{
  std::vector<ModelScore> scores;  ///< nominal, mecanum, linear, gp
  Eigen::Matrix<double, 8, 1> mecanum_parameters;
};

Table compare(const std::string& scenario_name)
{
  const sim::Scenario scenario = sim::loadScenarioYaml(kScenarios + "/" + scenario_name + ".yaml",
                                                       sim::shippedWorldsDirectory());
  sim::PairGeneratorOptions options;
  options.interval_s = 0.5;
  options.translation_noise_m = kNoiseM;
  options.rotation_noise_rad = kNoiseRad;
  options = sim::pairGeneratorOptions(scenario, options);
  const sim::GeneratedPairs training = sim::generatePairs(options);
  options.seed += 1000;
  const sim::GeneratedPairs testing = sim::generatePairs(options);

  ModelFactoryOptions factory;
  factory.joints = training.joints;
  factory.mecanum.layout = mecanumLayoutForJoints(training.joints, {"", "", "", ""}, 1000);
  factory.mecanum.initial_radius_m = {0.05, 0.05, 0.05, 0.05};
  factory.mecanum.initial_lx_plus_ly_m = 0.22;
  factory.mecanum.initial_T_base_sensor = Pose2(0.2, 0.0, 0.0);
  Table table;
  // The nominal robot: the mecanum model at its configured values, not fitted.
  const auto nominal = makeModel("mecanum", factory);
  ModelScore nominal_score = scoreModel(*nominal, testing.pairs);
  nominal_score.model = "nominal";
  table.scores.push_back(nominal_score);
  for (const ModelScore& score :
       compareModels({"mecanum", "linear", "gp"}, factory, training.pairs, testing.pairs)) {
    table.scores.push_back(score);
  }
  auto mecanum = makeModel("mecanum", factory);
  const ModelReport report = mecanum->fit(training.pairs);
  for (int i = 0; i < 8; ++i)
    table.mecanum_parameters(i) = report.parameters[static_cast<std::size_t>(i)].value;
  std::cout << "== " << scenario_name << " (" << training.pairs.size() << " training, "
            << testing.pairs.size() << " test pairs)\n"
            << formatComparisonTable(table.scores) << "mecanum fit:";
  for (const ParameterEstimate& p : report.parameters)
    std::cout << " " << p.name << " " << p.value << " +- " << p.sigma << ";";
  for (const std::string& note : report.notes)
    std::cout << "\nnote: " << note;
  std::cout << "\n\n";
  return table;
}

void expectAcceptance(const Table& table)
{
  const Eigen::Vector3d floor(kNoiseM, kNoiseM, kNoiseRad);
  const ModelScore& nominal = table.scores[0];
  const ModelScore& mecanum = table.scores[1];
  const Eigen::Vector3d& best_gp = table.scores[3].rmse_xytheta;
  for (int axis = 0; axis < 3; ++axis)
    EXPECT_LT(best_gp(axis), 1.5 * floor(axis)) << "axis " << axis;
  // The nominal model is at least 3x worse than both fits in y or theta.
  bool worse = false;
  for (int axis = 1; axis < 3; ++axis) {
    worse = worse || (nominal.rmse_xytheta(axis) > 3.0 * best_gp(axis) &&
                      nominal.rmse_xytheta(axis) > 3.0 * mecanum.rmse_xytheta(axis));
  }
  EXPECT_TRUE(worse) << "nominal y " << nominal.rmse_xytheta(1) << " theta "
                     << nominal.rmse_xytheta(2);
}

TEST(MecanumComparison, AxisYawedBy3Degrees)
{
  expectAcceptance(compare("mecanum_office_t1_3deg"));
}
TEST(MecanumComparison, AxisYawedBy6Degrees)
{
  expectAcceptance(compare("mecanum_office_t1_6deg"));
}
TEST(MecanumComparison, TiltedWheel)
{
  expectAcceptance(compare("mecanum_office_t2"));
}

}  // namespace
}  // namespace odometry_calibration
