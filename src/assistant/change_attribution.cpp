#include "odometry_calibration/assistant/change_attribution.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>
#include <utility>

#include <Eigen/Cholesky>
#include <Eigen/QR>

namespace odometry_calibration {
namespace {

constexpr std::size_t kMinBaselinePairs = 50;  // pairs before the search for delta_0
constexpr std::size_t kMinChangePairs = 3;     // pairs after a change point

/// "+2.03 +- 0.11 %"
std::string valueWords(const ChangeCandidate& candidate)
{
  char text[80];
  std::snprintf(text, sizeof(text), "%+.2f +- %.2f %s", candidate.estimate, candidate.sigma,
                candidate.hypothesis.unit.c_str());
  return text;
}

std::string kindWords(ChangeKind kind)
{
  return kind == ChangeKind::kWheel ? "the wheels" : "the sensor's mounting";
}

/// The best candidate of `kind` (candidates sorted best first), or null.
const ChangeCandidate* bestOfKind(const std::vector<ChangeCandidate>& candidates, ChangeKind kind)
{
  for (const ChangeCandidate& candidate : candidates) {
    if (candidate.hypothesis.kind == kind)
      return &candidate;
  }
  return nullptr;
}

/// The verdict's sentence.
std::string verdictWords(const ChangeVerdict& verdict)
{
  const std::string pairs = std::to_string(verdict.pairs) + " pairs";
  if (!verdict.significant)
    return "cause: no single change explains the residuals yet (" + pairs + ")";
  const ChangeCandidate& best = verdict.candidates.front();
  if (verdict.quantity_told) {
    return "cause: " +
           std::string(best.hypothesis.kind == ChangeKind::kWheel ? "a wheel change, "
                                                                  : "a mounting "
                                                                    "change, ") +
           "the " + best.hypothesis.name + " (" + valueWords(best) + ", from " + pairs + ")";
  }
  if (verdict.kind_told) {
    const ChangeCandidate* second = nullptr;
    for (std::size_t i = 1; i < verdict.candidates.size() && !second; ++i) {
      if (verdict.candidates[i].hypothesis.kind == best.hypothesis.kind)
        second = &verdict.candidates[i];
    }
    return "cause: a change of " + kindWords(best.hypothesis.kind) + ": the " +
           best.hypothesis.name + " (" + valueWords(best) + ") or the " + second->hypothesis.name +
           " (" + valueWords(*second) + "); cannot tell which from " + pairs;
  }
  const ChangeCandidate* wheel = bestOfKind(verdict.candidates, ChangeKind::kWheel);
  const ChangeCandidate* mounting = bestOfKind(verdict.candidates, ChangeKind::kMounting);
  return "cause: cannot tell yet whether the wheels or the sensor's mounting changed: the " +
         wheel->hypothesis.name + " (" + valueWords(*wheel) + ") and the " +
         mounting->hypothesis.name + " (" + valueWords(*mounting) + ") explain " + pairs +
         " about as well";
}

/// The sensor of a told mounting change whose rivals within `margin` are all of that sensor;
/// -1 otherwise.
int toldSensor(const ChangeVerdict& verdict, double margin)
{
  if (!verdict.kind_told || verdict.kind != ChangeKind::kMounting)
    return -1;
  const ChangeCandidate& best = verdict.candidates.front();
  for (const ChangeCandidate& candidate : verdict.candidates) {
    if (candidate.hypothesis.kind == ChangeKind::kMounting && best.chi2 - candidate.chi2 < margin &&
        candidate.hypothesis.sensor != best.hypothesis.sensor)
      return -1;
  }
  return best.hypothesis.sensor;
}

}  // namespace

void validate(const ChangeAttributionOptions& options)
{
  if (!(options.decisive_likelihood_ratio > 1.0) ||
      !std::isfinite(options.decisive_likelihood_ratio))
    throw std::invalid_argument("change attribution: decisive_likelihood_ratio must be > 1");
  if (!(options.significance_chi2 >= 0.0) || !std::isfinite(options.significance_chi2))
    throw std::invalid_argument("change attribution: significance_chi2 must be >= 0");
  if (!(options.huber_sigma > 0.0))
    throw std::invalid_argument("change attribution: huber_sigma must be > 0");
  if (options.max_pairs < 10)
    throw std::invalid_argument("change attribution: max_pairs must be >= 10");
  if (options.slack_pairs > options.max_pairs)
    throw std::invalid_argument("change attribution: slack_pairs must be <= max_pairs");
}

ChangeAttribution::ChangeAttribution(std::unique_ptr<ChangeHypotheses> hypotheses,
                                     ChangeAttributionOptions options)
    : hypotheses_(std::move(hypotheses)), options_(options)
{
  if (!hypotheses_)
    throw std::invalid_argument("change attribution: no hypotheses");
  validate(options_);
}

bool ChangeAttribution::add(std::size_t index, const std::vector<EncoderSample>& samples,
                            const Eigen::Vector3d& residual, const Eigen::Matrix3d& covariance,
                            std::size_t sensor)
{
  Eigen::MatrixXd jacobian;
  try {
    jacobian = hypotheses_->sensorSensitivity(samples, sensor);
  } catch (const std::exception&) {
    return false;
  }
  const Eigen::LLT<Eigen::Matrix3d> llt(covariance);
  if (llt.info() != Eigen::Success || !residual.allFinite())
    return false;
  // Whitened: S^-1/2 r and S^-1/2 J (L^-1 with S = L L^T).
  const Eigen::Vector3d whitened_residual = llt.matrixL().solve(residual);
  const Eigen::MatrixXd whitened_jacobian = llt.matrixL().solve(jacobian);
  const double norm = whitened_residual.norm();
  const double weight = norm > options_.huber_sigma ? options_.huber_sigma / norm : 1.0;
  entries_.push_back({index, weight * whitened_jacobian.transpose() * whitened_residual,
                      weight * whitened_jacobian.transpose() * whitened_jacobian});
  while (entries_.size() > options_.max_pairs)
    entries_.pop_front();
  return true;
}

Eigen::VectorXd ChangeAttribution::baseline(std::size_t last_index) const
{
  const auto n = static_cast<Eigen::Index>(hypotheses_->hypotheses().size());
  Eigen::VectorXd gradient = Eigen::VectorXd::Zero(n);
  Eigen::MatrixXd information = Eigen::MatrixXd::Zero(n, n);
  std::size_t count = 0;
  for (const Entry& entry : entries_) {
    if (entry.index > last_index)
      break;
    gradient += entry.gradient;
    information += entry.information;
    ++count;
  }
  if (count < kMinBaselinePairs)
    return Eigen::VectorXd::Zero(n);
  // Least squares; a direction the drive did not excite gets no baseline.
  return information.completeOrthogonalDecomposition().solve(gradient);
}

ChangeCandidate ChangeAttribution::bestChange(Eigen::Index c, std::size_t start_index,
                                              const Eigen::VectorXd& delta_0) const
{
  ChangeCandidate best;
  best.hypothesis = hypotheses_->hypotheses()[static_cast<std::size_t>(c)];
  double gradient = 0.0, information = 0.0;
  std::size_t count = 0;
  // From the newest pair back: each prefix is "the change came before this pair".
  for (auto entry = entries_.rbegin(); entry != entries_.rend() && entry->index > start_index;
       ++entry) {
    gradient += entry->gradient(c) - entry->information.row(c).dot(delta_0);
    information += entry->information(c, c);
    ++count;
    if (count < kMinChangePairs || !(information > 0.0))
      continue;
    const double chi2 = gradient * gradient / information;
    if (chi2 > best.chi2 && std::abs(gradient / information) <= best.hypothesis.plausible) {
      best.chi2 = chi2;
      best.estimate = gradient / information;
      best.sigma = 1.0 / std::sqrt(information);
      best.pairs = count;
    }
  }
  return best;
}

ChangeVerdict ChangeAttribution::verdict(std::size_t change_index) const
{
  const auto n = static_cast<Eigen::Index>(hypotheses_->hypotheses().size());
  const std::size_t start_index =
      change_index > options_.slack_pairs ? change_index - options_.slack_pairs : 0;
  const Eigen::VectorXd delta_0 = baseline(start_index);
  ChangeVerdict verdict;
  for (Eigen::Index c = 0; c < n; ++c)
    verdict.candidates.push_back(bestChange(c, start_index, delta_0));
  std::stable_sort(
      verdict.candidates.begin(), verdict.candidates.end(),
      [](const ChangeCandidate& a, const ChangeCandidate& b) { return a.chi2 > b.chi2; });
  const double margin = 2.0 * std::log(options_.decisive_likelihood_ratio);
  const ChangeCandidate* wheel = bestOfKind(verdict.candidates, ChangeKind::kWheel);
  const ChangeCandidate* mounting = bestOfKind(verdict.candidates, ChangeKind::kMounting);
  verdict.pairs = verdict.candidates.empty() ? 0 : verdict.candidates.front().pairs;
  verdict.significant =
      !verdict.candidates.empty() && verdict.candidates.front().chi2 > options_.significance_chi2;
  if (verdict.significant) {
    const ChangeCandidate& best = verdict.candidates.front();
    verdict.kind = best.hypothesis.kind;
    const ChangeCandidate* other = verdict.kind == ChangeKind::kWheel ? mounting : wheel;
    verdict.kind_told = !other || best.chi2 - other->chi2 >= margin;
    verdict.quantity_told = verdict.kind_told;
    for (std::size_t i = 1; i < verdict.candidates.size(); ++i) {
      const ChangeCandidate& candidate = verdict.candidates[i];
      if (candidate.hypothesis.kind == best.hypothesis.kind && best.chi2 - candidate.chi2 < margin)
        verdict.quantity_told = false;
    }
    verdict.sensor = toldSensor(verdict, margin);
  }
  verdict.words = verdictWords(verdict);
  return verdict;
}

}  // namespace odometry_calibration
