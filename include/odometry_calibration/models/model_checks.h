// The checks of pairs and joints every model makes before it fits or predicts, and the factory
// before it makes one: written once, so that every model refuses the same input with the same
// words.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "odometry_calibration/data/motion_pair.h"

namespace odometry_calibration {

/// Throws std::invalid_argument "<what> needs at least <minimum> keyframe pairs, got <n>:
/// <advice>" when `pairs` holds fewer than `minimum`.
void requireEnoughPairs(const std::vector<MotionPair>& pairs, std::size_t minimum,
                        const std::string& what,
                        const std::string& advice = "record a longer drive");

/// Throws std::invalid_argument "<model>: every pair needs two or more encoder samples with
/// <joints>" unless every pair has two or more samples and its first one carries the joints at
/// `indices`.
void requirePairsWithJoints(const std::vector<MotionPair>& pairs, const std::vector<int>& indices,
                            const std::string& model, const std::string& joints);

/// Throws std::invalid_argument "<model> prediction needs at least two encoder samples" for
/// fewer, and requireJointIndices' error (data/pair_features.h: "<model>: the model's <joints>
/// (indices ...) are not among the samples' N joints") when a sample lacks one of `indices`.
void requirePredictionSamples(const std::vector<EncoderSample>& samples,
                              const std::vector<int>& indices, const std::string& model,
                              const std::string& joints);

/// Throws std::invalid_argument "<what> are not among the pairs' <joint_count> joints" when an
/// index of `indices` is not below `joint_count`; `what` names model and joints, e.g.
/// "diff_drive: the wheel joints".
void requireJointsAmong(const std::vector<int>& indices, std::size_t joint_count,
                        const std::string& what);

/// Throws std::invalid_argument "<model> option '<name>' must be > 0" unless `value` is a
/// positive finite number.
void requirePositiveOption(double value, const std::string& model, const std::string& name);

/// Throws std::invalid_argument "<model> option 'max_iterations' must be >= 1" or "<model>
/// option 'yaw_starts' must be in [1, 360]" for the shared solver's limits
/// (SensorMotionFitOptions).
void requireSolverLimits(int max_iterations, int yaw_starts, const std::string& model);

/// Whether the joint indices are all valid (not negative) and different from each other.
/// Why a fitted parameter is no physical value (empty when all are): every value finite, wheel
/// radii in (0, 5] m, separations and axis lengths in (0, 50] m (the configuration's ranges of
/// the start values), the sensor within 100 m of the base. `names`, `units` and `values` of the
/// report's parameters (model.h), in any model's layout; parameters of other names (a GP's
/// hyperparameters) are only checked to be finite.
std::string physicalBoundsProblem(const std::vector<std::string>& names,
                                  const std::vector<double>& values);

bool distinctJointIndices(const std::vector<int>& indices);

}  // namespace odometry_calibration
