// Choice of the inducing inputs of the sparse GP: deterministic k-means++ seeding (fixed-seed
// D^2 sampling, Arthur & Vassilvitskii 2007) followed by a few Lloyd iterations, in the model's
// scaled input space, so that the inducing inputs cover the inputs where they are dense.
#pragma once

#include <Eigen/Core>

namespace odometry_calibration {

/// At most `count` inducing inputs (m x M) for the columns of `inputs` (m x n, distinct): all of
/// them if n <= count, otherwise k-means++ seeds refined by `lloyd_iterations` Lloyd steps.
/// The same inputs, count and seed give the same result. Throws std::invalid_argument if
/// count < 1 or inputs is empty.
Eigen::MatrixXd selectInducingInputs(const Eigen::MatrixXd& inputs, Eigen::Index count,
                                     unsigned seed, int lloyd_iterations = 5);

}  // namespace odometry_calibration
