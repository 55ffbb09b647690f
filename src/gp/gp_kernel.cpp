#include "odometry_calibration/gp/gp_kernel.h"

#include <cmath>
#include <stdexcept>

namespace odometry_calibration {
namespace {

/// The kernel's positive parameters, unpacked from the log-parameters.
struct Unpacked
{
  bool rbf = false;                ///< the kernel has the rbf term
  bool linear = false;             ///< the kernel has the linear term
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
  u.rbf = kernel.type() != GpKernelType::kLinear;
  u.linear = kernel.type() != GpKernelType::kRbf;
  if (u.rbf) {
    u.signal_variance = std::exp(2.0 * theta(0));
    u.inverse_length = (-theta.segment(1, m)).array().exp();
  } else {
    u.inverse_length = Eigen::VectorXd::Ones(m);
  }
  if (u.linear) {
    u.linear_variance = std::exp(2.0 * theta(theta.size() - 1));
  }
  return u;
}

/// k(a, b) for inputs of dimension m (paper eqs. 7-8, gp_kernel.h): sigma_f^2 exp(-1/2 sum_p
/// ((a_p - b_p) / l_p)^2) with rbf, plus sigma_l^2 <a, b> with linear.
double kernelValue(const Unpacked& u, const double* a, const double* b, int m)
{
  double value = 0.0;
  if (u.rbf) {
    value = u.signal_variance * std::exp(-0.5 * scaledDistance2(a, b, u.inverse_length.data(), m));
  }
  if (u.linear) {
    value += u.linear_variance * dot(a, b, m);
  }
  return value;
}

/// Weighted sums over pairs of inputs of the kernel's derivatives with respect to its
/// log-parameters: d k / d log sigma_f = 2 k_rbf; d k / d log l_p = k_rbf (d_p / l_p)^2;
/// d k / d log sigma_l = 2 k_lin (the factors 2 and sigma_l^2 are applied once, in addTo).
class GradientSums
{
public:
  GradientSums(const Unpacked& u, int m) : u_(u), m_(m), g_length_(Eigen::VectorXd::Zero(m)), d2_(m)
  {
  }

  /// Adds w times the derivatives of k(a, b).
  void add(double w, const double* a, const double* b)
  {
    if (u_.rbf) {
      double q = 0.0;
      for (int p = 0; p < m_; ++p) {
        const double d = (a[p] - b[p]) * u_.inverse_length(p);
        d2_(p) = d * d;
        q += d2_(p);
      }
      const double wk = w * u_.signal_variance * std::exp(-0.5 * q);
      g_signal_ += wk;
      g_length_ += wk * d2_;
    }
    if (u_.linear) {
      g_linear_ += w * dot(a, b, m_);
    }
  }

  /// gradient += the sums, in the parameter layout of the file comment (log sigma_l at
  /// linear_index).
  void addTo(int linear_index, Eigen::VectorXd* gradient) const
  {
    if (u_.rbf) {
      (*gradient)(0) += 2.0 * g_signal_;
      gradient->segment(1, m_) += g_length_;
    }
    if (u_.linear) {
      (*gradient)(linear_index) += 2.0 * u_.linear_variance * g_linear_;
    }
  }

private:
  const Unpacked& u_;
  int m_;
  double g_signal_ = 0.0;
  double g_linear_ = 0.0;
  Eigen::VectorXd g_length_;  ///< per input dimension
  Eigen::VectorXd d2_;        ///< scratch: ((a_p - b_p) / l_p)^2
};

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
      k(i, j) = kernelValue(u, a.col(i).data(), bj, m);
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
      const double value = kernelValue(u, a.col(i).data(), aj, m);
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
  // The same values as cross(a, x), computed a row of inputs at a time so that the distances
  // and the exponential vectorise: this is the O(n) part of every prediction.
  check(log_parameters, a);
  if (x.size() != dimension_) {
    throw std::invalid_argument("gp kernel expects inputs of dimension " +
                                std::to_string(dimension_) + ", got " + std::to_string(x.size()));
  }
  const Unpacked u = unpack(*this, log_parameters);
  Eigen::VectorXd k = Eigen::VectorXd::Zero(a.cols());
  if (u.rbf) {
    Eigen::ArrayXd q = Eigen::ArrayXd::Zero(a.cols());
    for (int p = 0; p < dimension_; ++p)
      q += ((a.row(p).transpose().array() - x(p)) * u.inverse_length(p)).square();
    k.array() = u.signal_variance * (-0.5 * q).exp();
  }
  if (u.linear)
    k.noalias() += u.linear_variance * (a.transpose() * x);
  return k;
}

void GpKernel::addCrossGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                                const Eigen::MatrixXd& b, const Eigen::MatrixXd& weights,
                                Eigen::VectorXd* gradient) const
{
  check(log_parameters, a);
  check(log_parameters, b);
  const Unpacked u = unpack(*this, log_parameters);
  GradientSums sums(u, dimension_);
  for (Eigen::Index j = 0; j < b.cols(); ++j) {
    const double* bj = b.col(j).data();
    for (Eigen::Index i = 0; i < a.cols(); ++i) {
      sums.add(weights(i, j), a.col(i).data(), bj);
    }
  }
  sums.addTo(linearIndex(), gradient);
}

void GpKernel::addGramGradient(const Eigen::VectorXd& log_parameters, const Eigen::MatrixXd& a,
                               const Eigen::MatrixXd& weights, Eigen::VectorXd* gradient) const
{
  check(log_parameters, a);
  const Unpacked u = unpack(*this, log_parameters);
  GradientSums sums(u, dimension_);
  for (Eigen::Index j = 0; j < a.cols(); ++j) {
    const double* aj = a.col(j).data();
    for (Eigen::Index i = j; i < a.cols(); ++i) {
      // Off-diagonal entries stand for both triangles.
      sums.add((i == j ? 1.0 : 2.0) * weights(i, j), a.col(i).data(), aj);
    }
  }
  sums.addTo(linearIndex(), gradient);
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
