#include <cmath>
#include <stdexcept>
#include <string>

#include <gtest/gtest.h>

#include "odometry_calibration/data/velocity_integrator.h"

namespace odometry_calibration {
namespace {

Eigen::VectorXd both(double left, double right)
{
  Eigen::VectorXd v(2);
  v << left, right;
  return v;
}

TEST(VelocityIntegrator, TheTrapezoidIsExactForVelocitiesLinearInTime)
{
  // v_left = 2 + 3 t, v_right = -1 + 0.5 t at uneven stamps: p = 2 t + 1.5 t^2, -t + 0.25 t^2.
  VelocityIntegrator integrator(2, 0.5, "wheels.max_gap_s");
  double t = 1.0;  // positions count from the first message
  integrator.add(t, both(2 + 3 * t, -1 + 0.5 * t));
  Eigen::VectorXd p;
  for (double dt : {0.02, 0.013, 0.031, 0.02, 0.009}) {
    t += dt;
    p = integrator.add(t, both(2 + 3 * t, -1 + 0.5 * t));
  }
  const double t0 = 1.0;
  EXPECT_NEAR(p(0), 2 * (t - t0) + 1.5 * (t * t - t0 * t0), 1e-12);
  EXPECT_NEAR(p(1), -(t - t0) + 0.25 * (t * t - t0 * t0), 1e-12);
}

TEST(VelocityIntegrator, AQuadraticPositionIsWithinTheTrapezoidsError)
{
  // v = cos(t): the trapezoid's error over [0, T] is at most T h^2 / 12 * max|v''|.
  VelocityIntegrator integrator(1, 0.5, "wheels.max_gap_s");
  const double h = 0.02;
  Eigen::VectorXd p;
  for (int k = 0; k <= 100; ++k)
    p = integrator.add(k * h, Eigen::VectorXd::Constant(1, std::cos(k * h)));
  EXPECT_NEAR(p(0), std::sin(2.0), 2.0 * h * h / 12.0);
  EXPECT_GT(std::abs(p(0) - std::sin(2.0)), 1e-6);  // a trapezoid, not the exact integral
}

TEST(VelocityIntegrator, AGapRestartsTheIntegrationNamingTheKey)
{
  VelocityIntegrator integrator(2, 0.5, "wheels.max_gap_s");
  std::string note;
  integrator.add(0.0, both(1, 1), &note);
  EXPECT_TRUE(note.empty());
  Eigen::VectorXd p = integrator.add(0.1, both(1, 1), &note);
  EXPECT_NEAR(p(0), 0.1, 1e-15);
  p = integrator.add(1.1, both(3, 3), &note);  // 1 s silent
  EXPECT_NEAR(p(0), 0.1, 1e-15);               // held, not integrated across
  EXPECT_NE(note.find("no joint velocity for 1.0"), std::string::npos) << note;
  EXPECT_NE(note.find("wheels.max_gap_s 0.5"), std::string::npos) << note;
  p = integrator.add(1.2, both(3, 3), &note);
  EXPECT_NEAR(p(0), 0.4, 1e-12);
  EXPECT_TRUE(note.empty());
  p = integrator.add(0.7, both(3, 3), &note);  // time going backwards
  EXPECT_NE(note.find("went back by 0.5"), std::string::npos) << note;
  EXPECT_NEAR(p(0), 0.4, 1e-12);
}

TEST(VelocityIntegrator, BadInputIsRefused)
{
  VelocityIntegrator integrator(2, 0.5, "wheels.max_gap_s");
  EXPECT_THROW(integrator.add(0.0, Eigen::VectorXd::Ones(3)), std::invalid_argument);
  EXPECT_THROW(integrator.add(0.0, both(std::nan(""), 1)), std::invalid_argument);
  EXPECT_THROW(integrator.add(0.0, both(1e308, 1e308 * 10)), std::invalid_argument);
  EXPECT_THROW(VelocityIntegrator(2, 0.0, "wheels.max_gap_s"), std::invalid_argument);
  // Finite velocities whose integral is not: refused, the positions kept.
  integrator.add(1.0, both(1e308, 1e308));
  EXPECT_THROW(integrator.add(1.1, both(1e308, 1e308)), std::invalid_argument);
  EXPECT_TRUE(integrator.add(1.2, both(1, 1)).allFinite());
}

}  // namespace
}  // namespace odometry_calibration
