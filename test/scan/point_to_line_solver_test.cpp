// The closed-form point-to-line step (Censi ICRA 2008): exact recovery on noise-free data,
// constrained variants, singular inputs.
#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "odometry_calibration/scan/point_to_line_solver.h"

namespace odometry_calibration {
namespace {

/// Noise-free correspondences: new-frame points p, and for each the reference line through
/// T_ref_new * p with a random normal, its anchor slid along the line.
PointToLineSystem exactSystem(const Pose2& T_ref_new, int count, std::mt19937& rng,
                              bool one_direction_only = false)
{
  std::uniform_real_distribution<double> coordinate(-8.0, 8.0);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::uniform_real_distribution<double> slide(-0.5, 0.5);
  PointToLineSystem system;
  for (int i = 0; i < count; ++i) {
    const Eigen::Vector2d p(coordinate(rng), coordinate(rng));
    const double a = one_direction_only ? 0.3 : angle(rng);
    const Eigen::Vector2d normal(std::cos(a), std::sin(a));
    const Eigen::Vector2d tangent(-normal.y(), normal.x());
    system.add(p, T_ref_new.transformPoint(p) + slide(rng) * tangent, normal);
  }
  return system;
}

void expectPoseNear(const Pose2& actual, const Pose2& expected, double tolerance)
{
  EXPECT_NEAR(actual.x(), expected.x(), tolerance);
  EXPECT_NEAR(actual.y(), expected.y(), tolerance);
  EXPECT_NEAR(normalizeAngle(actual.theta() - expected.theta()), 0.0, tolerance);
}

TEST(PointToLineSolver, RecoversTheExactMotionFromNoiseFreeData)
{
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> translation(-2.0, 2.0);
  std::uniform_real_distribution<double> rotation(-M_PI, M_PI);
  for (int trial = 0; trial < 200; ++trial) {
    const Pose2 truth(translation(rng), translation(rng), rotation(rng));
    // Six or more lines: fewer may be met exactly by more than one pose.
    const PointToLineSystem system = exactSystem(truth, 6 + trial % 50, rng);
    const std::optional<Pose2> solution = system.solve();
    ASSERT_TRUE(solution.has_value());
    expectPoseNear(*solution, truth, 1e-9);
  }
}

TEST(PointToLineSolver, InformationIsTheSumOfTheResidualGradientsOuterProducts)
{
  // information(theta) must equal sum_i J_i J_i^T, J_i = (n_i, (R p_i) x n_i), computed here
  // point by point.
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> coordinate(-6.0, 6.0);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  PointToLineSystem system;
  Eigen::Matrix3d expected = Eigen::Matrix3d::Zero();
  const double theta = 0.7;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector2d p(coordinate(rng), coordinate(rng));
    const Eigen::Vector2d c(coordinate(rng), coordinate(rng));
    const double a = angle(rng);
    const Eigen::Vector2d n(std::cos(a), std::sin(a));
    system.add(p, c, n);
    const Eigen::Vector2d Rp(std::cos(theta) * p.x() - std::sin(theta) * p.y(),
                             std::sin(theta) * p.x() + std::cos(theta) * p.y());
    const Eigen::Vector3d J(n.x(), n.y(), Rp.x() * n.y() - Rp.y() * n.x());
    expected += J * J.transpose();
  }
  EXPECT_LT((system.information(theta) - expected).cwiseAbs().maxCoeff(), 1e-9);
}

TEST(PointToLineSolver, IsTheMinimumOfTheCostWithNoisyLines)
{
  // With inconsistent lines the solution must beat every nearby pose.
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> coordinate(-5.0, 5.0);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<std::array<Eigen::Vector2d, 3>> lines;
  PointToLineSystem system;
  for (int i = 0; i < 40; ++i) {
    const Eigen::Vector2d p(coordinate(rng), coordinate(rng));
    const double a = angle(rng);
    const Eigen::Vector2d n(std::cos(a), std::sin(a));
    const Eigen::Vector2d c = Pose2(0.3, -0.2, 0.7).transformPoint(p) + noise(rng) * n;
    system.add(p, c, n);
    lines.push_back({p, c, n});
  }
  auto cost = [&](const Pose2& T) {
    double sum = 0.0;
    for (const auto& line : lines) {
      sum += std::pow(line[2].dot(T.transformPoint(line[0]) - line[1]), 2);
    }
    return sum;
  };
  const Pose2 solution = *system.solve();
  const double best = cost(solution);
  for (int k = 0; k < 500; ++k) {
    const Pose2 nearby(solution.x() + 0.01 * std::cos(k), solution.y() + 0.01 * std::sin(3.0 * k),
                       solution.theta() + 0.01 * std::sin(7.0 * k));
    EXPECT_LE(best, cost(nearby) + 1e-12);
  }
}

TEST(PointToLineSolver, HoldsAFixedTranslationAxis)
{
  std::mt19937 rng(2);
  const Pose2 truth(0.4, -0.3, 0.2);
  const PointToLineSystem system = exactSystem(truth, 30, rng);
  StepConstraint constraint;
  constraint.fix_translation_along_axis = true;
  constraint.fixed_axis_ref = Eigen::Vector2d(1.0, 1.0).normalized();
  constraint.fixed_along_m = 0.5;  // not the truth's 0.07: the step must obey it anyway
  const Pose2 solution = *system.solve(constraint);
  EXPECT_NEAR(constraint.fixed_axis_ref.dot(Eigen::Vector2d(solution.x(), solution.y())), 0.5,
              1e-12);
  // With the truth's own value the exact motion comes back.
  constraint.fixed_along_m = constraint.fixed_axis_ref.dot(Eigen::Vector2d(truth.x(), truth.y()));
  expectPoseNear(*system.solve(constraint), truth, 1e-9);
}

TEST(PointToLineSolver, HoldsAFixedRotation)
{
  std::mt19937 rng(4);
  const Pose2 truth(-1.0, 0.5, -2.0);
  const PointToLineSystem system = exactSystem(truth, 30, rng);
  StepConstraint constraint;
  constraint.fix_rotation = true;
  constraint.fixed_theta_rad = truth.theta();
  expectPoseNear(*system.solve(constraint), truth, 1e-9);
}

TEST(PointToLineSolver, ParallelLinesDoNotDetermineTheMotion)
{
  std::mt19937 rng(6);
  // All normals equal: translation along the lines is free.
  EXPECT_FALSE(exactSystem(Pose2(0.1, 0.2, 0.3), 20, rng, true).solve().has_value());
  EXPECT_FALSE(PointToLineSystem().solve().has_value());
}

TEST(MinimizeQuadraticOnUnitCircle, MatchesABruteForceSearch)
{
  std::mt19937 rng(9);
  std::uniform_real_distribution<double> value(-3.0, 3.0);
  for (int trial = 0; trial < 300; ++trial) {
    Eigen::Matrix2d S;
    S << value(rng), value(rng), 0.0, value(rng);
    S(1, 0) = S(0, 1);
    const Eigen::Vector2d h(value(rng), value(rng));
    const Eigen::Vector2d r = *minimizeQuadraticOnUnitCircle(S, h);
    EXPECT_NEAR(r.norm(), 1.0, 1e-12);
    auto cost = [&](const Eigen::Vector2d& v) { return v.dot(S * v) - 2.0 * h.dot(v); };
    double best = std::numeric_limits<double>::infinity();
    for (int k = 0; k < 20000; ++k) {
      const double a = 2.0 * M_PI * k / 20000.0;
      best = std::min(best, cost(Eigen::Vector2d(std::cos(a), std::sin(a))));
    }
    EXPECT_LE(cost(r), best + 1e-9);
  }
  // Hard case: h orthogonal to the weakest eigenvector.
  const Eigen::Vector2d r =
      *minimizeQuadraticOnUnitCircle(Eigen::Vector2d(1.0, 3.0).asDiagonal(), Eigen::Vector2d(0, 1));
  EXPECT_NEAR(std::abs(r.x()), std::sqrt(0.75), 1e-12);
  EXPECT_NEAR(r.y(), 0.5, 1e-12);
  EXPECT_FALSE(minimizeQuadraticOnUnitCircle(Eigen::Matrix2d::Identity(), Eigen::Vector2d::Zero())
                   .has_value());
}

}  // namespace
}  // namespace odometry_calibration
