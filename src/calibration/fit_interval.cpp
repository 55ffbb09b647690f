#include "odometry_calibration/calibration/fit_interval.h"

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>

#include "odometry_calibration/data/holdout.h"
#include "odometry_calibration/eval/model_comparison.h"
#include "odometry_calibration/factory/model_factory.h"

namespace odometry_calibration {

namespace {

/// One validation block: its evaluation pairs and the time span they cover.
struct Block
{
  std::vector<MotionPair> evaluation;
  double start_s = 0.0;
  double end_s = 0.0;
};

std::vector<Block> cutBlocks(const std::vector<MotionPair>& evaluation, std::size_t block_count)
{
  std::vector<double> stamps;
  stamps.reserve(evaluation.size());
  for (const MotionPair& pair : evaluation)
    stamps.push_back(pair.start_stamp_s);
  std::vector<Block> blocks;
  for (const SampleBlock& range : timeBlocks(stamps, block_count)) {
    Block block;
    block.evaluation.assign(evaluation.begin() + static_cast<std::ptrdiff_t>(range.first),
                            evaluation.begin() + static_cast<std::ptrdiff_t>(range.last) + 1);
    block.start_s = block.evaluation.front().start_stamp_s;
    block.end_s = block.evaluation.back().end_stamp_s;
    blocks.push_back(std::move(block));
  }
  return blocks;
}

/// The RPE or ATE (paper eq. 10 or 11) of the chained predictions of a model fitted to the
/// candidate's pairs outside `block`, on the block's pairs; infinity when the fit is impossible.
double blockError(const CalibrationConfig& config, const ModelFactoryOptions& models,
                  const std::vector<MotionPair>& candidate, const Block& block,
                  FitIntervalCriterion criterion)
{
  std::vector<MotionPair> training;
  for (const MotionPair& pair : candidate) {
    if (pair.end_stamp_s <= block.start_s || pair.start_stamp_s >= block.end_s)
      training.push_back(pair);
  }
  try {
    const std::unique_ptr<MotionModel> model = makeModel(config.model, models);
    model->fit(training);
    const ModelScore score = scoreModel(*model, block.evaluation);
    const double error = criterion == FitIntervalCriterion::kAte ? score.ate_m : score.rpe_m;
    return std::isfinite(error) ? error : std::numeric_limits<double>::infinity();
  } catch (const std::exception&) {
    return std::numeric_limits<double>::infinity();
  }
}

/// Throws std::invalid_argument for no candidate or fold counts that cannot cut the drive.
void checkCandidatesAndFolds(const std::vector<IntervalPairs>& candidates,
                             const FitIntervalOptions& options)
{
  if (candidates.empty())
    throw std::invalid_argument("fit interval: no candidate interval");
  if (options.fold_counts.empty())
    throw std::invalid_argument("fit interval: fold_counts is empty");
  for (const std::size_t folds : options.fold_counts) {
    if (folds < 2)
      throw std::invalid_argument("fit interval: each fold count must be >= 2");
  }
}

}  // namespace

FitIntervalCriterion fitIntervalCriterion(EgoMotionSource source)
{
  return source == EgoMotionSource::kPose ? FitIntervalCriterion::kAte : FitIntervalCriterion::kRpe;
}

const char* criterionName(FitIntervalCriterion criterion)
{
  return criterion == FitIntervalCriterion::kAte ? "ATE" : "RPE";
}

FitIntervalChoice chooseFitInterval(const CalibrationConfig& config,
                                    const std::vector<IntervalPairs>& candidates,
                                    const std::vector<MotionPair>& evaluation,
                                    FitIntervalCriterion criterion,
                                    const FitIntervalOptions& options)
{
  checkCandidatesAndFolds(candidates, options);
  // The search's fits start from the configured sensor yaw only, as the time-offset search's.
  ModelFactoryOptions models = config.models;
  models.diff_drive.yaw_starts = 1;
  models.tricycle.calibration.yaw_starts = 1;

  std::vector<std::vector<Block>> cuts;
  for (const std::size_t folds : options.fold_counts) {
    try {
      cuts.push_back(cutBlocks(evaluation, folds));
    } catch (const std::invalid_argument&) {
      throw std::invalid_argument("fit interval: " + std::to_string(evaluation.size()) +
                                  " evaluation pairs are too few for " + std::to_string(folds) +
                                  " cross-validation blocks");
    }
  }

  FitIntervalChoice choice;
  choice.criterion = criterion;
  choice.fold_counts = options.fold_counts;
  double best = std::numeric_limits<double>::infinity();
  for (const IntervalPairs& candidate : candidates) {
    FitIntervalScore score;
    score.interval_s = candidate.interval_s;
    score.pairs = candidate.pairs.size();
    double sum = 0.0;
    for (const std::vector<Block>& blocks : cuts) {
      for (const Block& block : blocks) {
        if (block.evaluation.size() < std::max<std::size_t>(options.min_block_pairs, 2))
          continue;
        sum += blockError(config, models, candidate.pairs, block, criterion);
        ++score.blocks;
      }
    }
    score.validation_error_m = score.blocks > 0 ? sum / static_cast<double>(score.blocks)
                                                : std::numeric_limits<double>::infinity();
    if (score.validation_error_m < best) {
      best = score.validation_error_m;
      choice.interval_s = candidate.interval_s;
    }
    choice.curve.push_back(score);
  }
  if (!std::isfinite(best)) {
    throw std::invalid_argument(
        "fit interval: no candidate interval could be cross-validated (too few pairs outside "
        "the blocks, or every fit failed)");
  }
  return choice;
}

std::vector<MotionPair> pairsEndingBy(const std::vector<MotionPair>& pairs, double border_stamp_s)
{
  std::vector<MotionPair> before;
  for (const MotionPair& pair : pairs) {
    if (pair.end_stamp_s <= border_stamp_s)
      before.push_back(pair);
  }
  return before;
}

std::vector<MotionPair> pairsStartingFrom(const std::vector<MotionPair>& pairs,
                                          double border_stamp_s)
{
  std::vector<MotionPair> after;
  for (const MotionPair& pair : pairs) {
    if (pair.start_stamp_s >= border_stamp_s)
      after.push_back(pair);
  }
  return after;
}

std::string formatFitIntervalChoice(const FitIntervalChoice& choice, double evaluation_interval_s)
{
  char head[200];
  std::snprintf(head, sizeof(head),
                "fit interval T = %.2f s, chosen by time-blocked cross-validation (validation "
                "%s of %.2f s pairs):",
                choice.interval_s, criterionName(choice.criterion), evaluation_interval_s);
  std::string text = head;
  for (const FitIntervalScore& score : choice.curve) {
    char point[120];
    if (std::isfinite(score.validation_error_m)) {
      std::snprintf(point, sizeof(point), " %.2f s %.5f m%s,", score.interval_s,
                    score.validation_error_m,
                    score.interval_s == choice.interval_s ? " (chosen)" : "");
    } else {
      std::snprintf(point, sizeof(point), " %.2f s not scored,", score.interval_s);
    }
    text += point;
  }
  text.back() = '\n';
  return text;
}

}  // namespace odometry_calibration
