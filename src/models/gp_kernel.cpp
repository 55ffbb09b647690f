#include "odometry_calibration/models/gp_kernel.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// The kernel's positive parameters, unpacked from the log-parameters.
struct Unpacked
{
  double signal_variance = 0.0;    ///< sigma_f^2 (0 without rbf)
  Eigen::VectorXd inverse_length;  ///< 1 / l_p (rbf)
  double linear_variance = 0.0;    ///< sigma_l^2 (0 without linear)
};

/// Squared scaled distance sum_p ((a_p - b_p) / l_p)^2.
inline double scaledDistance2(const double* a, const double* b, const double* inverse_length, int m)
{
  double q = 0.0;
  for (int p = 0; p < m; ++p) {
    const double d = (a[p] - b[p]) * inverse_length[p];
    q += d * d;
  }
  return q;
}

inline double dot(const double* a, const double* b, int m)
{
  double s = 0.0;
  for (int p = 0; p < m; ++p) {
    s += a[p] * b[p];
  }
  return s;
}

}  // namespace

GpKernel::GpKernel(GpKernelType type, int input_dimension)
    : type_(type), dimension_(input_dimension)
{
  if (input_dimension < 1) {
    throw std::invalid_argument("gp kernel needs at least one input dimension");
  }
}

int GpKernel::parameterCount() const
{
  return (hasRbf() ? dimension_ + 1 : 0) + (hasLinear() ? 1 : 0);
}

std::vector<std::string> GpKernel::parameterNames() const
{
  std::vector<std::string> names;
  if (hasRbf()) {
    names.push_back("signal_sigma");
    for (int p = 0; p < dimension_; ++p) {
      names.push_back("length_scale_" + std::to_string(p + 1));
    }
  }
  if (hasLinear()) {
    names.push_back("linear_sigma");
  }
  return names;
}

void GpKernel::check(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a) const
{
  if (log_parameters.size() != parameterCount()) {
    throw std::invalid_argument("gp kernel expects " + std::to_string(parameterCount()) +
                                " parameters, got " + std::to_string(log_parameters.size()));
  }
  if (a.rows() != dimension_) {
    throw std::invalid_argument("gp kernel expects inputs of dimension " +
                                std::to_string(dimension_) + ", got " + std::to_string(a.rows()));
  }
}

namespace {

Unpacked unpack(const GpKernel& kernel, const Eigen::VectorXd& theta)
{
  Unpacked u;
  const int m = kernel.inputDimension();
  if (kernel.type() != GpKernelType::kLinear) {
    u.signal_variance = std::exp(2.0 * theta(0));
    u.inverse_length = (-theta.segment(1, m)).array().exp();
  } else {
    u.inverse_length = Eigen::VectorXd::Ones(m);
  }
  if (kernel.type() != GpKernelType::kRbf) {
    u.linear_variance = std::exp(2.0 * theta(theta.size() - 1));
  }
  return u;
}

}  // namespace

Eigen::MatrixXd GpKernel::cross(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                                const Eigen::MatrixXd& b) const
{
  check(log_parameters, a);
  check(log_parameters, b);
  const Unpacked u = unpack(*this, log_parameters);
  Eigen::MatrixXd k(a.cols(), b.cols());
  const int m = dimension_;
  for (Eigen::Index j = 0; j < b.cols(); ++j) {
    const double* bj = b.col(j).data();
    for (Eigen::Index i = 0; i < a.cols(); ++i) {
      const double* ai = a.col(i).data();
      double value = 0.0;
      if (hasRbf()) {
        value = u.signal_variance *
                std::exp(-0.5 * scaledDistance2(ai, bj, u.inverse_length.data(), m));
      }
      if (hasLinear()) {
        value += u.linear_variance * dot(ai, bj, m);
      }
      k(i, j) = value;
    }
  }
  return k;
}

Eigen::MatrixXd GpKernel::gram(const Eigen::VectorXd& log_parameters,
                               const Eigen::MatrixXd& a) const
{
  check(log_parameters, a);
  const Unpacked u = unpack(*this, log_parameters);
  const Eigen::Index n = a.cols();
  Eigen::MatrixXd k(n, n);
  const int m = dimension_;
  for (Eigen::Index j = 0; j < n; ++j) {
    const double* aj = a.col(j).data();
    for (Eigen::Index i = j; i < n; ++i) {
      const double* ai = a.col(i).data();
      double value = 0.0;
      if (hasRbf()) {
        value = u.signal_variance *
                std::exp(-0.5 * scaledDistance2(ai, aj, u.inverse_length.data(), m));
      }
      if (hasLinear()) {
        value += u.linear_variance * dot(ai, aj, m);
      }
      k(i, j) = value;
      k(j, i) = value;
    }
  }
  return k;
}

Eigen::VectorXd GpKernel::diagonal(const Eigen::VectorXd& log_parameters,
                                   const Eigen::MatrixXd& a) const
{
  check(log_parameters, a);
  const Unpacked u = unpack(*this, log_parameters);
  Eigen::VectorXd d = Eigen::VectorXd::Constant(a.cols(), u.signal_variance);
  if (hasLinear()) {
    d += u.linear_variance * a.colwise().squaredNorm().transpose();
  }
  return d;
}

Eigen::VectorXd GpKernel::column(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                                 const Eigen::VectorXd& x) const
{
  return cross(log_parameters, a, x);
}

void GpKernel::addCrossGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                                const Eigen::MatrixXd& b, const Eigen::MatrixXd& weights,
                                Eigen::VectorXd* gradient) const
{
  check(log_parameters, a);
  check(log_parameters, b);
  const Unpacked u = unpack(*this, log_parameters);
  const int m = dimension_;
  // d k / d log sigma_f = 2 k_rbf; d k / d log l_p = k_rbf (d_p / l_p)^2;
  // d k / d log sigma_l = 2 k_lin.
  double g_signal = 0.0;
  double g_linear = 0.0;
  Eigen::VectorXd g_length = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd d2(m);
  for (Eigen::Index j = 0; j < b.cols(); ++j) {
    const double* bj = b.col(j).data();
    for (Eigen::Index i = 0; i < a.cols(); ++i) {
      const double w = weights(i, j);
      const double* ai = a.col(i).data();
      if (hasRbf()) {
        double q = 0.0;
        for (int p = 0; p < m; ++p) {
          const double d = (ai[p] - bj[p]) * u.inverse_length(p);
          d2(p) = d * d;
          q += d2(p);
        }
        const double wk = w * u.signal_variance * std::exp(-0.5 * q);
        g_signal += wk;
        g_length += wk * d2;
      }
      if (hasLinear()) {
        g_linear += w * dot(ai, bj, m);
      }
    }
  }
  if (hasRbf()) {
    (*gradient)(0) += 2.0 * g_signal;
    gradient->segment(1, m) += g_length;
  }
  if (hasLinear()) {
    (*gradient)(linearIndex()) += 2.0 * u.linear_variance * g_linear;
  }
}

void GpKernel::addGramGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                               const Eigen::MatrixXd& weights, Eigen::VectorXd* gradient) const
{
  check(log_parameters, a);
  const Unpacked u = unpack(*this, log_parameters);
  const int m = dimension_;
  double g_signal = 0.0;
  double g_linear = 0.0;
  Eigen::VectorXd g_length = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd d2(m);
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    const double* aj = a.col(j).data();
    for (Eigen::Index i = j; i < a.cols(); ++i) {
      // Off-diagonal entries stand for both triangles.
      const double w = (i == j ? 1.0 : 2.0) * weights(i, j);
      const double* ai = a.col(i).data();
      if (hasRbf()) {
        double q = 0.0;
        for (int p = 0; p < m; ++p) {
          const double d = (ai[p] - aj[p]) * u.inverse_length(p);
          d2(p) = d * d;
          q += d2(p);
        }
        const double wk = w * u.signal_variance * std::exp(-0.5 * q);
        g_signal += wk;
        g_length += wk * d2;
      }
      if (hasLinear()) {
        g_linear += w * dot(ai, aj, m);
      }
    }
  }
  if (hasRbf()) {
    (*gradient)(0) += 2.0 * g_signal;
    gradient->segment(1, m) += g_length;
  }
  if (hasLinear()) {
    (*gradient)(linearIndex()) += 2.0 * u.linear_variance * g_linear;
  }
}

void GpKernel::addDiagonalGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                                   const Eigen::VectorXd& weights, Eigen::VectorXd* gradient) const
{
  check(log_parameters, a);
  const Unpacked u = unpack(*this, log_parameters);
  if (hasRbf()) {
    (*gradient)(0) += 2.0 * u.signal_variance * weights.sum();
  }
  if (hasLinear()) {
    (*gradient)(linearIndex()) +=
        2.0 * u.linear_variance * weights.dot(a.colwise().squaredNorm().transpose());
  }
}

}  // namespace odometry_calibration
