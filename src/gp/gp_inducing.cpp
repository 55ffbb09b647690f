#include "odometry_calibration/gp/gp_inducing.h"

#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>

namespace odometry_calibration {

Eigen::MatrixXd selectInducingInputs(const Eigen::MatrixXd& inputs, Eigen::Index count,
                                     unsigned seed, int lloyd_iterations)
{
  const Eigen::Index n = inputs.cols();
  if (count < 1 || n == 0) {
    throw std::invalid_argument("gp: inducing inputs need count >= 1 and at least one input");
  }
  if (n <= count) {
    return inputs;
  }

  // k-means++ seeding: the first centre uniformly, the next ones with probability proportional
  // to the squared distance to the nearest centre so far. Draws from our own generator with a
  // fixed mapping to indices (the standard distributions' algorithms vary between libraries).
  std::mt19937_64 rng(seed);
  const auto uniform01 = [&rng]() { return static_cast<double>(rng() >> 11) * 0x1.0p-53; };
  Eigen::MatrixXd centres(inputs.rows(), count);
  Eigen::VectorXd nearest2 = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  Eigen::Index chosen = static_cast<Eigen::Index>(rng() % static_cast<std::uint64_t>(n));
  for (Eigen::Index c = 0; c < count; ++c) {
    centres.col(c) = inputs.col(chosen);
    nearest2 =
        nearest2.cwiseMin((inputs.colwise() - centres.col(c)).colwise().squaredNorm().transpose());
    const double total = nearest2.sum();
    if (!(total > 0.0)) {
      centres.conservativeResize(Eigen::NoChange, c + 1);
      break;
    }
    const double target = uniform01() * total;
    double cumulative = 0.0;
    chosen = n - 1;
    for (Eigen::Index i = 0; i < n; ++i) {
      cumulative += nearest2(i);
      if (cumulative > target && nearest2(i) > 0.0) {
        chosen = i;
        break;
      }
    }
  }

  // Lloyd: move each centre to the mean of its inputs; an empty cluster keeps its centre.
  const Eigen::Index k = centres.cols();
  for (int iteration = 0; iteration < lloyd_iterations; ++iteration) {
    Eigen::MatrixXd sums = Eigen::MatrixXd::Zero(inputs.rows(), k);
    Eigen::VectorXd counts = Eigen::VectorXd::Zero(k);
    for (Eigen::Index i = 0; i < n; ++i) {
      Eigen::Index best = 0;
      (centres.colwise() - inputs.col(i)).colwise().squaredNorm().minCoeff(&best);
      sums.col(best) += inputs.col(i);
      counts(best) += 1.0;
    }
    for (Eigen::Index c = 0; c < k; ++c) {
      if (counts(c) > 0.0) {
        centres.col(c) = sums.col(c) / counts(c);
      }
    }
  }
  return centres;
}

}  // namespace odometry_calibration
