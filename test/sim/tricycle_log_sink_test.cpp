#include <cmath>
#include <sstream>

#include <gtest/gtest.h>

#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/datasets/tricycle_log.h"
#include "odometry_calibration/sim/robot.h"
#include "odometry_calibration/sim/simulator.h"
#include "odometry_calibration/sim/tricycle_log_sink.h"

namespace odometry_calibration {
namespace sim {
namespace {

TEST(SimTricycleLog, CalibratingTheSimulatedLogRecoversTheTruth)
{
  Scenario s;
  s.seed = 21;
  s.duration_s = 90.0;
  s.start_pose = Pose2(0.0, -2.0, 0.0);
  s.robot = {"tricycle",
             {{"steering_scale", 0.52},
              {"traction_scale_m_per_turn", 0.0112},
              {"axis_length_m", 1.6},
              {"steering_offset_rad", 0.05}}};
  s.encoders.rate_hz = 25.0;
  s.encoders.initial_ticks = 4294967296.0 - 20000.0;  // the counter wraps after ~4 cm
  s.laser.T_base_laser = Pose2(1.7, 0.03, 0.02);
  s.laser.rays = 10;
  s.tracker.enabled = true;
  s.motion.max_speed_mps = 0.8;
  s.motion.max_turn_rate_radps = 0.5;
  s.motion.clearance_m = 0.5;
  const World world =
      parseWorldYaml("polygons:\n  - [[-15, -10], [15, -10], [15, 10], [-15, 10]]\n", "hall");
  const auto robot = makeRobot(s.robot);
  const TricycleParameters nominal = TricycleParameters::fromVectors(
      Eigen::Vector4d(0.1, 0.0106141, 1.4, 0.0), Eigen::Vector3d(1.5, 0.0, 0.0));
  TricycleLogSink sink(s, nominal, 8192, 5000);
  const SimulationSummary summary = simulate(s, world, *robot, sink);
  EXPECT_EQ(sink.rows(), summary.joint_states);
  EXPECT_GE(summary.counter_wraps, 1u);

  std::istringstream text(sink.text());
  const TricycleDataset dataset = parseTricycleDataset(text, "simulated");
  ASSERT_EQ(dataset.rows.size(), sink.rows());
  EXPECT_NEAR(dataset.rows[25].stamp_s, 1.0, 1e-9);
  EXPECT_NEAR(dataset.first_stamp_unix_s, s.start_time_s, 1e-6);
  const TricycleEncoderLayout layout = tricycleLayoutFromHeader(dataset.header);
  const TricycleParameters initial = tricycleNominalFromHeader(dataset.header);
  EXPECT_DOUBLE_EQ(initial.axis_length_m, 1.4);
  const auto samples = decodeTricycleEncoders(dataset, layout);
  const Eigen::Matrix3d covariance = Eigen::Vector3d(1e-4, 1e-4, 1e-4).asDiagonal();
  const auto result =
      calibrateTricycle(tricyclePairs(dataset, samples, 0.5, covariance), layout, initial, {});
  ASSERT_TRUE(result.converged);
  EXPECT_NEAR(result.calibrated.steering_scale, 0.52, 0.01);
  EXPECT_NEAR(result.calibrated.traction_scale_m_per_turn, 0.0112, 0.0001);
  EXPECT_NEAR(result.calibrated.axis_length_m, 1.6, 0.03);
  EXPECT_NEAR(result.calibrated.steering_offset_rad, 0.05, 0.005);
  EXPECT_NEAR(result.calibrated.T_base_sensor.x(), 1.7, 0.02);
  EXPECT_NEAR(result.calibrated.T_base_sensor.y(), 0.03, 0.02);
  EXPECT_NEAR(result.calibrated.T_base_sensor.theta(), 0.02, 0.01);

  // The log's model_pose is the nominal odometry: integrating the nominal model over the
  // decoded encoders must give it back (to the printed precision).
  const Eigen::Vector4d kinematic = initial.kinematicVector();
  const Pose2 end = integrateTricycleMotion(kinematic.data(), layout, samples);
  const Pose2 logged = dataset.rows.back().T_odom_base_model;
  EXPECT_NEAR(end.x(), logged.x(), 1e-3 * std::max(1.0, std::abs(logged.x())));
  EXPECT_NEAR(end.y(), logged.y(), 1e-3 * std::max(1.0, std::abs(logged.y())));
}

TEST(SimTricycleLog, NeedsTicksAndA32BitCounter)
{
  Scenario s;
  s.robot.type = "tricycle";
  s.encoders.output_ticks = false;
  EXPECT_THROW(TricycleLogSink(s, TricycleParameters(), 8192, 5000), std::invalid_argument);
  s.encoders.output_ticks = true;
  s.encoders.counter_bits = 16;
  EXPECT_THROW(TricycleLogSink(s, TricycleParameters(), 8192, 5000), std::invalid_argument);
}

TEST(SimTricycleLog, MadeForATrackedTricycleWithTheRealLogsNominalValues)
{
  Scenario s;
  s.robot = {"tricycle", {}};
  EXPECT_FALSE(canWriteTricycleLog(s));  // no tracker
  EXPECT_THROW(makeTricycleLogSink(s), std::invalid_argument);
  s.tracker.enabled = true;
  EXPECT_TRUE(canWriteTricycleLog(s));
  s.robot.type = "diff_drive";
  EXPECT_FALSE(canWriteTricycleLog(s));
  s.robot.type = "tricycle";
  s.duration_s = 2.0;
  s.motion.max_speed_mps = 0.5;
  const World world =
      parseWorldYaml("polygons:\n  - [[-15, -10], [15, -10], [15, 10], [-15, 10]]\n", "hall");
  const auto sink = makeTricycleLogSink(s);
  simulate(s, world, *makeRobot(s.robot), *sink);
  std::istringstream text(sink->text());
  const TricycleDataset dataset = parseTricycleDataset(text, "simulated");
  const TricycleParameters nominal = tricycleNominalFromHeader(dataset.header);
  EXPECT_DOUBLE_EQ(nominal.steering_scale, 0.1);
  EXPECT_DOUBLE_EQ(nominal.traction_scale_m_per_turn, 0.0106141);
  EXPECT_DOUBLE_EQ(nominal.axis_length_m, 1.4);
  EXPECT_DOUBLE_EQ(nominal.steering_offset_rad, 0.0);
  EXPECT_DOUBLE_EQ(nominal.T_base_sensor.x(), 1.5);
  EXPECT_GT(sink->rows(), 0u);
}
}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
