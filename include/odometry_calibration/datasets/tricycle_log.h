// Turns a parsed tricycle log into what the calibration consumes: the encoder layout and
// nominal parameters from its header, decoded encoder samples, and keyframe pairs whose
// measured displacement comes from the tracker (the ego-motion source).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "odometry_calibration/data/motion_pair.h"
#include "odometry_calibration/datasets/tricycle_dataset.h"
#include "odometry_calibration/models/tricycle_calibration.h"

namespace odometry_calibration {

/// Encoder layout from the header's joint names and ranges (steering absolute, traction
/// incremental). Throws std::invalid_argument naming the missing header line.
TricycleEncoderLayout tricycleLayoutFromHeader(const TricycleDatasetHeader& header);

/// Nominal parameters (Ksteer Ktraction axis_length steer_offset + laser pose) from the header.
/// Throws std::invalid_argument naming the missing header line.
TricycleParameters tricycleNominalFromHeader(const TricycleDatasetHeader& header);

/// Decodes every row: steering as a signed absolute reading, traction as a cumulative count from
/// signed differences of the uint32 counter (wrap-around and reversal handled). Values are
/// stored at layout.steering_index / layout.traction_index.
std::vector<EncoderSample> decodeTricycleEncoders(const TricycleDataset& dataset,
                                                  const TricycleEncoderLayout& layout);

/// One pair per keyframe window (keyframes every `interval_s` [s]): the decoded samples of the
/// window and the tracker's sensor displacement, with `covariance` [m^2, rad^2].
std::vector<MotionPair> tricyclePairs(const TricycleDataset& dataset,
                                      const std::vector<EncoderSample>& samples, double interval_s,
                                      const Eigen::Matrix3d& covariance);

/// The tracker's sensor pose of every row (the ego-motion reference), in file order.
std::vector<Pose2> tricycleTrackerPoses(const TricycleDataset& dataset);

}  // namespace odometry_calibration
