// VFE bound and gradient. Notation: L_m L_m^T = K_mm (+ jitter), Lambda = diag(noise),
// A = L_m^-1 K_mn Lambda^-1/2 (M x n), B = I + A A^T = L_B L_B^T, r = y - H^T C,
// rt = Lambda^-1/2 r. Then log|Q + Lambda| = log|Lambda| + log|B| and
// r^T (Q + Lambda)^-1 r = rt^T rt - |L_B^-1 A rt|^2 (Woodbury). The gradient follows from
// dF = sum dK_nm .* G_nm + sum dK_mm .* G_mm + sum dk_ii g_diag_i + sum dlambda_i g_noise_i with
//   G_mn = w beta^T + L_m^-T (I - B^-1) A Lambda^-1/2,
//   G_mm = -1/2 w w^T + 1/2 L_m^-T (2 I - B^-1 - B) L_m^-1,
//   g_diag = -1/2 / lambda,
//   g_noise = 1/2 beta^2 - 1/2 diag((Q + Lambda)^-1) + 1/2 (k_ii - q_ii) / lambda^2,
// where beta = (Q + Lambda)^-1 r and w = L_m^-T B^-1 A rt.
#include <cmath>

#include <Eigen/Cholesky>
#include <Eigen/Dense>

#include "odometry_calibration/gp/gp_likelihood.h"

namespace odometry_calibration {

bool factorInducingCovariance(const Eigen::MatrixXd& k_mm, Eigen::MatrixXd* lower_factor)
{
  const double scale = std::max(k_mm.diagonal().mean(), 1e-300);
  for (double jitter = kGpInducingJitterStart; jitter <= 1.01e-4; jitter *= 10.0) {
    Eigen::MatrixXd jittered = k_mm;
    jittered.diagonal().array() += jitter * scale;
    Eigen::LLT<Eigen::MatrixXd> llt(jittered);
    if (llt.info() == Eigen::Success) {
      *lower_factor = llt.matrixL();
      return true;
    }
  }
  return false;
}

namespace {

/// The factors of the bound (file comment): L_m, Lambda^-1/2, A, B and B's Cholesky factor.
struct VfeFactors
{
  Eigen::MatrixXd l_m;
  Eigen::VectorXd inv_sqrt_noise;
  Eigen::MatrixXd a;
  Eigen::MatrixXd b;
  Eigen::LLT<Eigen::MatrixXd> llt_b;
};

/// The factors at the kernel's log-parameters; false if a factorisation fails.
bool factorVfe(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
               const GpRegressionData& data, const Eigen::MatrixXd& inducing_inputs,
               VfeFactors* factors)
{
  const Eigen::Index m = inducing_inputs.cols();
  if (!factorInducingCovariance(kernel.gram(log_parameters, inducing_inputs), &factors->l_m)) {
    return false;
  }
  const auto lower_m = factors->l_m.triangularView<Eigen::Lower>();
  factors->inv_sqrt_noise = data.noise_variance.array().rsqrt();
  // A = L_m^-1 K_mn Lambda^-1/2.
  Eigen::MatrixXd& a = factors->a;
  a = kernel.cross(log_parameters, inducing_inputs, data.inputs);
  lower_m.solveInPlace(a);
  a = a * factors->inv_sqrt_noise.asDiagonal();
  Eigen::MatrixXd b_lower = Eigen::MatrixXd::Identity(m, m);
  b_lower.selfadjointView<Eigen::Lower>().rankUpdate(a);
  factors->b = b_lower.selfadjointView<Eigen::Lower>();
  factors->llt_b.compute(factors->b);
  return factors->llt_b.info() == Eigen::Success;
}

/// (Q + Lambda)^-1 v = Lambda^-1 v - Lambda^-1/2 A^T B^-1 A Lambda^-1/2 v.
Eigen::MatrixXd applyVfeInverse(const VfeFactors& factors, const Eigen::MatrixXd& v)
{
  const Eigen::MatrixXd scaled = factors.inv_sqrt_noise.asDiagonal() * v;
  Eigen::MatrixXd out = scaled - factors.a.transpose() * factors.llt_b.solve(factors.a * scaled);
  return Eigen::MatrixXd(factors.inv_sqrt_noise.asDiagonal() * out);
}

/// The whitened residual rt = Lambda^-1/2 (y - H^T C), with the profiled mean coefficients C
/// into `result` (empty for the zero mean).
Eigen::VectorXd vfeWhitenedResidual(const VfeFactors& factors, const GpRegressionData& data,
                                    GpLikelihood* result)
{
  result->mean_coefficients.resize(0);
  Eigen::VectorXd residual = data.targets;
  if (data.mean_basis.rows() > 0) {
    result->mean_coefficients = profiledMeanCoefficients(
        data.mean_basis, applyVfeInverse(factors, data.mean_basis.transpose()),
        applyVfeInverse(factors, data.targets).col(0));
    residual.noalias() -= data.mean_basis.transpose() * result->mean_coefficients;
  }
  return factors.inv_sqrt_noise.cwiseProduct(residual);
}

/// The bound's derivatives (file comment) into `result`, from the factors, rt, c = L_B^-1 A rt
/// and the trace terms (k_ii - q_ii) / lambda_i.
void vfeGradient(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                 const GpRegressionData& data, const Eigen::MatrixXd& inducing_inputs,
                 const VfeFactors& factors, const Eigen::VectorXd& rt, const Eigen::VectorXd& c,
                 const Eigen::VectorXd& trace_terms, GpLikelihood* result)
{
  const Eigen::Index m = inducing_inputs.cols();
  const Eigen::MatrixXd& l_m = factors.l_m;
  const Eigen::MatrixXd& a = factors.a;
  const Eigen::LLT<Eigen::MatrixXd>& llt_b = factors.llt_b;
  const Eigen::VectorXd& inv_sqrt_noise = factors.inv_sqrt_noise;
  const Eigen::VectorXd e = llt_b.matrixU().solve(c);  // B^-1 A rt
  const Eigen::VectorXd beta = inv_sqrt_noise.cwiseProduct(rt - a.transpose() * e);
  const Eigen::VectorXd w = l_m.transpose().triangularView<Eigen::Upper>().solve(e);
  const Eigen::MatrixXd b_inverse = llt_b.solve(Eigen::MatrixXd::Identity(m, m));

  // G_mn (M x n), the coefficient of dK_mn.
  Eigen::MatrixXd g_mn = a - b_inverse * a;  // (I - B^-1) A
  l_m.transpose().triangularView<Eigen::Upper>().solveInPlace(g_mn);
  g_mn = g_mn * inv_sqrt_noise.asDiagonal();
  g_mn.noalias() += w * beta.transpose();

  // G_mm (M x M), the coefficient of dK_mm.
  Eigen::MatrixXd middle = 2.0 * Eigen::MatrixXd::Identity(m, m) - b_inverse - factors.b;
  l_m.transpose().triangularView<Eigen::Upper>().solveInPlace(middle);  // L_m^-T X
  Eigen::MatrixXd g_mm = middle.transpose();
  l_m.transpose().triangularView<Eigen::Upper>().solveInPlace(g_mm);  // L_m^-T X^T L_m^-1
  g_mm = 0.5 * g_mm.transpose().eval();
  g_mm.noalias() -= 0.5 * w * w.transpose();

  result->d_kernel = Eigen::VectorXd::Zero(kernel.parameterCount());
  kernel.addCrossGradient(log_parameters, inducing_inputs, data.inputs, g_mn, &result->d_kernel);
  kernel.addGramGradient(log_parameters, inducing_inputs, g_mm, &result->d_kernel);
  const Eigen::VectorXd g_diag = -0.5 * data.noise_variance.cwiseInverse();
  kernel.addDiagonalGradient(log_parameters, data.inputs, g_diag, &result->d_kernel);

  // diag((Q + Lambda)^-1)_i = (1 - |L_B^-1 A_i|^2) / lambda_i.
  Eigen::MatrixXd whitened = a;
  llt_b.matrixL().solveInPlace(whitened);
  const Eigen::VectorXd inverse_diag = (1.0 - whitened.colwise().squaredNorm().transpose().array())
                                           .matrix()
                                           .cwiseQuotient(data.noise_variance);
  result->d_noise = 0.5 * beta.cwiseAbs2() - 0.5 * inverse_diag +
                    0.5 * trace_terms.cwiseQuotient(data.noise_variance);
  result->d_targets = -beta;
}

}  // namespace

bool vfeLogLikelihoodBound(const GpKernel& kernel, const Eigen::VectorXd& log_parameters,
                           const GpRegressionData& data, const Eigen::MatrixXd& inducing_inputs,
                           bool with_gradient, GpLikelihood* result)
{
  const Eigen::Index n = data.inputs.cols();
  VfeFactors factors;
  if (!factorVfe(kernel, log_parameters, data, inducing_inputs, &factors)) {
    return false;
  }
  const Eigen::VectorXd rt = vfeWhitenedResidual(factors, data, result);
  const Eigen::VectorXd c = factors.llt_b.matrixL().solve(factors.a * rt);
  const Eigen::VectorXd k_diag = kernel.diagonal(log_parameters, data.inputs);
  // q_ii = lambda_i |A_i|^2.
  const Eigen::VectorXd q_diag =
      factors.a.colwise().squaredNorm().transpose().cwiseProduct(data.noise_variance);
  const Eigen::VectorXd trace_terms = (k_diag - q_diag).cwiseQuotient(data.noise_variance);
  constexpr double kLog2Pi = 1.8378770664093453;
  const double log_det_b = 2.0 * factors.llt_b.matrixLLT().diagonal().array().log().sum();
  result->value = -0.5 * static_cast<double>(n) * kLog2Pi -
                  0.5 * data.noise_variance.array().log().sum() - 0.5 * log_det_b -
                  0.5 * (rt.squaredNorm() - c.squaredNorm()) - 0.5 * trace_terms.sum();
  if (!std::isfinite(result->value)) {
    return false;
  }
  if (with_gradient) {
    vfeGradient(kernel, log_parameters, data, inducing_inputs, factors, rt, c, trace_terms, result);
  }
  return true;
}

}  // namespace odometry_calibration
