// Which change explains a stale calibration's residuals: a weighted least-squares
// regression of the pairs' residuals on each candidate change's sensitivity
// (change_hypotheses.h), and a likelihood comparison of the candidates.
//
// Pairs before the change carry the calibration's own small error: the parameters' error
// delta_0 = (sum_i w_i J_i^T S_i^-1 J_i)^-1 sum_i w_i J_i^T S_i^-1 r_i, all candidates together,
// from the pairs before the search (at least 50), is taken out of every later residual first
// (r_i - J_i delta_0: the change is what differs from then). Over the pairs i after a change
// point k, with residual r_i, covariance S_i and sensitivity column J_ic of candidate c
// (r_i = J_ic delta_c + noise if c alone changed by delta_c):
//   g_c = sum_i w_i J_ic^T S_i^-1 r_i,   H_c = sum_i w_i J_ic^T S_i^-1 J_ic,
//   delta_c = g_c / H_c,  sigma_c = 1 / sqrt(H_c),  X_c = g_c^2 / H_c,
// X_c being how much the candidate lowers the residuals' chi-square (twice the log-likelihood
// ratio of "c changed by delta_c after k" against "nothing changed"). Each candidate takes the
// change point k that maximises its X_c (the generalised likelihood ratio of Willsky and Jones,
// "A generalized likelihood ratio approach to the detection and estimation of jumps in linear
// systems", IEEE TAC 1976), searched from `slack_pairs` before the caller's estimate on, with at
// least 3 pairs after it and an estimate within the hypothesis' plausible range (20 %, 20 cm,
// 20 deg: a few pairs that barely sense a quantity would otherwise "explain" them by a huge
// change). Every candidate then has the same two unknowns (delta_c, k), so the candidates
// compare by X alone: c beats c' by the likelihood ratio exp((X_c - X_c') / 2). w_i is a Huber
// weight (min(1, k_H / |S_i^-1/2 r_i|)), so a failed scan match cannot decide. The verdict names
//   the kind (wheel or mounting) when the best of one kind beats the best of the other by the
//     decisive likelihood ratio (default 100: X apart by 2 ln 100 = 9.2),
//   the quantity when the best candidate beats every other one of its kind by that ratio,
// and says "cannot tell" otherwise; nothing is named unless the best X exceeds the chi-square
// significance threshold (default 10.8: p = 0.001 with no change).
//
// With several sensors each pair carries its sensor's index: a wheel candidate is
// regressed on every sensor's pairs, a sensor's mounting candidate on that sensor's pairs alone
// (its column is zero in the others'), so the pairs of a laser that did not move count against
// a wheel change that would have shown in them too. The verdict names the sensor when the kind
// is a mounting and every mounting candidate the best does not beat decisively is of one
// sensor (its x and its yaw may compete while the other laser is out of the question).
//
// What the data cannot carry, the verdict cannot either: left against right radius is told by
// the along-track residual (a radius moves the travel, the separation does not), so a scan
// matcher whose along-track motion is biased (a corridor) can tell the wrong side
// (docs/live_assistant.md).
#pragma once

#include <cstddef>
#include <deque>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/assistant/change_hypotheses.h"

namespace odometry_calibration {

struct ChangeAttributionOptions
{
  double decisive_likelihood_ratio = 100.0;  ///< a candidate is told apart beyond this
  double significance_chi2 = 10.83;          ///< best X needed to name anything (p = 0.001)
  double huber_sigma = 6.0;                  ///< whitened residual norm where weights fall
  std::size_t max_pairs = 2400;              ///< pairs kept (baseline and search)
  std::size_t slack_pairs = 60;  ///< the change point is searched from this far before the estimate
};

/// Throws std::invalid_argument naming the first invalid option.
void validate(const ChangeAttributionOptions& options);

/// One candidate's fit to the residuals.
struct ChangeCandidate
{
  ChangeHypothesis hypothesis;
  double estimate = 0.0;  ///< delta_c in the hypothesis' unit
  double sigma = 0.0;     ///< its standard deviation [unit]
  double chi2 = 0.0;      ///< X_c
  std::size_t pairs = 0;  ///< pairs after its change point
};

/// What the residuals say changed.
struct ChangeVerdict
{
  std::size_t pairs = 0;                    ///< pairs after the best candidate's change point
  std::vector<ChangeCandidate> candidates;  ///< best first (largest X)
  bool significant = false;                 ///< the best X beyond the significance threshold
  bool kind_told = false;                   ///< wheel vs mounting decided
  ChangeKind kind = ChangeKind::kWheel;     ///< valid when kind_told
  bool quantity_told = false;               ///< the best candidate decided within its kind
  /// A mounting change told to be of this sensor (ChangeHypothesis::sensor); -1: a wheel
  /// change, or not told which sensor.
  int sensor = -1;
  /// In words, e.g. "cause: the right wheel radius has changed (+2.0 +- 0.1 %)".
  std::string words;
};

/// Accumulates pairs and regresses them. Not thread-safe.
class ChangeAttribution
{
public:
  /// Throws std::invalid_argument for null hypotheses or invalid options.
  ChangeAttribution(std::unique_ptr<ChangeHypotheses> hypotheses,
                    ChangeAttributionOptions options = {});

  /// Adds pair number `index` (increasing) of sensor `sensor` (0 with one) with its residual
  /// and covariance; false when its sensitivity cannot be computed (the pair is left out).
  bool add(std::size_t index, const std::vector<EncoderSample>& samples,
           const Eigen::Vector3d& residual, const Eigen::Matrix3d& covariance,
           std::size_t sensor = 0);
  /// The verdict, the change point searched from slack_pairs before pair `change_index` on.
  ChangeVerdict verdict(std::size_t change_index) const;
  const ChangeHypotheses& hypotheses() const { return *hypotheses_; }

private:
  struct Entry
  {
    std::size_t index;
    Eigen::VectorXd gradient;     ///< w J^T S^-1 r
    Eigen::MatrixXd information;  ///< w J^T S^-1 J
  };
  /// delta_0 from the entries with index <= `last_index` (zero with fewer than 50).
  Eigen::VectorXd baseline(std::size_t last_index) const;
  /// Candidate c's best change point after `start_index`, residuals corrected by delta_0.
  ChangeCandidate bestChange(Eigen::Index c, std::size_t start_index,
                             const Eigen::VectorXd& delta_0) const;
  std::unique_ptr<ChangeHypotheses> hypotheses_;
  ChangeAttributionOptions options_;
  std::deque<Entry> entries_;
};

}  // namespace odometry_calibration
