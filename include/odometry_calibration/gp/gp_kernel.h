// Covariance functions of the GP motion model (paper eqs. 7-8), one scalar kernel per output
// (the paper's diagonal kernel), with derivatives with respect to their log-parameters for the
// marginal-likelihood gradient.
//
// Inputs are columns of an m x n matrix. Parameters are logarithms of positive quantities:
//   rbf:        [log sigma_f, log l_1 .. log l_m]   k = sigma_f^2 exp(-1/2 sum_p
//   (x_p-x'_p)^2/l_p^2) linear:     [log sigma_l]                       k = sigma_l^2 <x, x'>
//   rbf+linear: [log sigma_f, log l_1 .. log l_m, log sigma_l]   the sum
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/gp/gp_options.h"

namespace odometry_calibration {

/// A kernel of one output: its type and input dimension; parameters are passed to each call.
class GpKernel
{
public:
  GpKernel() = default;
  /// Throws std::invalid_argument if input_dimension < 1.
  GpKernel(GpKernelType type, int input_dimension);

  GpKernelType type() const { return type_; }
  int inputDimension() const { return dimension_; }
  /// Number of log-parameters (layout in the file comment).
  int parameterCount() const;
  /// Names of the parameters without the log, e.g. "signal_sigma", "length_scale_1",
  /// "linear_sigma"; length scales are numbered from 1 in input order.
  std::vector<std::string> parameterNames() const;

  /// k(a_i, b_j) for the columns of a (m x na) and b (m x nb): an na x nb matrix.
  Eigen::MatrixXd cross(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                        const Eigen::MatrixXd& b) const;
  /// k(a_i, a_j), symmetric na x na (both triangles filled).
  Eigen::MatrixXd gram(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a) const;
  /// k(a_i, a_i).
  Eigen::VectorXd diagonal(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a) const;
  /// k(a_i, x) for one input x (m).
  Eigen::VectorXd column(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                         const Eigen::VectorXd& x) const;

  /// gradient_p += sum_ij weights(i, j) d k(a_i, b_j) / d log_parameter_p.
  void addCrossGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                        const Eigen::MatrixXd& b, const Eigen::MatrixXd& weights,
                        Eigen::VectorXd* gradient) const;
  /// gradient_p += sum_ij weights(i, j) d k(a_i, a_j) / d log_parameter_p for a symmetric
  /// `weights`, of which only the lower triangle is read.
  void addGramGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                       const Eigen::MatrixXd& weights, Eigen::VectorXd* gradient) const;
  /// gradient_p += sum_i weights(i) d k(a_i, a_i) / d log_parameter_p.
  void addDiagonalGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                           const Eigen::VectorXd& weights, Eigen::VectorXd* gradient) const;

private:
  bool hasRbf() const { return type_ != GpKernelType::kLinear; }
  bool hasLinear() const { return type_ != GpKernelType::kRbf; }
  /// Index of log sigma_l in the parameter vector.
  int linearIndex() const { return hasRbf() ? dimension_ + 1 : 0; }
  /// Throws std::invalid_argument for a parameter vector or input of the wrong size.
  void check(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a) const;

  GpKernelType type_ = GpKernelType::kRbf;
  int dimension_ = 1;
};

}  // namespace odometry_calibration
