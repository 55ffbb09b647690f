#include "odometry_calibration/assistant/change_hypotheses.h"

#include <algorithm>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <utility>

#include "odometry_calibration/models/diff_drive_kinematics.h"
#include "odometry_calibration/models/diff_drive_model.h"
#include "odometry_calibration/models/skid_steer_model.h"

namespace odometry_calibration {
namespace {

constexpr double kPercent = 0.01;         // one unit of a relative change
constexpr double kCentimetre = 0.01;      // [m]
constexpr double kDegree = M_PI / 180.0;  // [rad]
constexpr double kRelativeStep = 1e-4;    // central-difference step of a relative change
constexpr double kAbsoluteStep = 1e-5;    // of a mounting change [m, rad]

/// Central differences of `predict` (perturbation vector -> sensor motion) at zero, column i
/// scaled by unit[i] / step[i].
Eigen::MatrixXd centralDifferences(const std::function<Pose2(const Eigen::VectorXd&)>& predict,
                                   const Eigen::VectorXd& step, const Eigen::VectorXd& unit)
{
  const Eigen::Index n = step.size();
  Eigen::MatrixXd jacobian(3, n);
  for (Eigen::Index i = 0; i < n; ++i) {
    Eigen::VectorXd delta = Eigen::VectorXd::Zero(n);
    delta(i) = step(i);
    const Pose2 plus = predict(delta);
    const Pose2 minus = predict(-delta);
    const Eigen::Vector3d difference(plus.x() - minus.x(), plus.y() - minus.y(),
                                     normalizeAngle(plus.theta() - minus.theta()));
    jacobian.col(i) = difference * (unit(i) / (2.0 * step(i)));
  }
  if (!jacobian.allFinite())
    throw std::invalid_argument("change hypotheses: the prediction is not finite");
  return jacobian;
}

std::vector<ChangeHypothesis> mountingHypotheses(const std::string& sensor,
                                                 const std::string& frame)
{
  return {{sensor + " mounting x" + frame, ChangeKind::kMounting, "cm", 20.0, 0},
          {sensor + " mounting y" + frame, ChangeKind::kMounting, "cm", 20.0, 0},
          {sensor + " mounting yaw", ChangeKind::kMounting, "deg", 20.0, 0}};
}

/// A differential drive (or a skid-steer's two averaged sides): r_L, r_R, b relative, the
/// sensor's pose in base_link absolute.
class DiffDriveHypotheses : public ChangeHypotheses
{
public:
  /// `prepare` turns a pair's samples into the two wheels' (identity for a diff drive).
  DiffDriveHypotheses(
      const Eigen::Vector3d& intrinsics, const Pose2& T_base_sensor, DiffDriveEncoderLayout layout,
      const std::string& sensor, const std::string& wheel_words,
      std::function<std::vector<EncoderSample>(const std::vector<EncoderSample>&)> prepare)
      : intrinsics_(intrinsics),
        T_base_sensor_(T_base_sensor),
        layout_(layout),
        prepare_(std::move(prepare))
  {
    hypotheses_ = {{"left " + wheel_words + " radius", ChangeKind::kWheel, "%", 20.0},
                   {"right " + wheel_words + " radius", ChangeKind::kWheel, "%", 20.0},
                   {"wheel separation", ChangeKind::kWheel, "%", 20.0}};
    for (ChangeHypothesis& h : mountingHypotheses(sensor, ""))
      hypotheses_.push_back(std::move(h));
  }

  Eigen::MatrixXd sensitivity(const std::vector<EncoderSample>& raw) const override
  {
    const std::vector<EncoderSample> samples = prepare_(raw);
    for (const EncoderSample& sample : samples) {
      if (sample.values.size() <= std::max<Eigen::Index>(layout_.left_index, layout_.right_index))
        throw std::invalid_argument("change hypotheses: a sample lacks a wheel joint");
    }
    if (samples.size() < 2)
      throw std::invalid_argument("change hypotheses: a pair needs two encoder samples");
    auto predict = [&](const Eigen::VectorXd& delta) {
      const Eigen::Vector3d intrinsics =
          intrinsics_.cwiseProduct(Eigen::Vector3d::Ones() + delta.head<3>());
      const Pose2 T(T_base_sensor_.x() + delta(3), T_base_sensor_.y() + delta(4),
                    T_base_sensor_.theta() + delta(5));
      return sensorMotionFromBodyMotion(
          T, integrateDiffDriveMotion(intrinsics.data(), layout_, samples));
    };
    Eigen::VectorXd step(6), unit(6);
    step << kRelativeStep, kRelativeStep, kRelativeStep, kAbsoluteStep, kAbsoluteStep,
        kAbsoluteStep;
    unit << kPercent, kPercent, kPercent, kCentimetre, kCentimetre, kDegree;
    return centralDifferences(predict, step, unit);
  }

private:
  Eigen::Vector3d intrinsics_;
  Pose2 T_base_sensor_;
  DiffDriveEncoderLayout layout_;
  std::function<std::vector<EncoderSample>(const std::vector<EncoderSample>&)> prepare_;
};

/// Any model: each joint's increments scaled, through the model's prediction; the sensor's
/// mounting moved in its own frame (Delta^-1 s Delta: no knowledge of base_link needed).
class JointScaleHypotheses : public ChangeHypotheses
{
public:
  JointScaleHypotheses(std::shared_ptr<const MotionModel> model, const std::string& sensor,
                       const std::vector<std::string>& joint_names)
      : model_(std::move(model))
  {
    for (const std::string& joint : joint_names)
      hypotheses_.push_back({"joint " + joint + " travel", ChangeKind::kWheel, "%", 20.0});
    joints_ = static_cast<Eigen::Index>(joint_names.size());
    for (ChangeHypothesis& h : mountingHypotheses(sensor, " (in its own frame)"))
      hypotheses_.push_back(std::move(h));
  }

  Eigen::MatrixXd sensitivity(const std::vector<EncoderSample>& samples) const override
  {
    if (samples.size() < 2 || samples.front().values.size() < joints_)
      throw std::invalid_argument("change hypotheses: a pair lacks samples or joints");
    const Eigen::VectorXd start = samples.front().values;
    // The model's prediction (a GP's may be costly) only with a joint scaled: the mounting
    // columns move the unchanged prediction (2 joints + 1 predictions per pair, not 2 (n + 3)).
    const Pose2 unchanged = model_->predict(samples).mean;
    auto predict = [&](const Eigen::VectorXd& delta) {
      Pose2 s = unchanged;
      if (!delta.head(joints_).isZero(0.0)) {
        std::vector<EncoderSample> scaled = samples;
        for (EncoderSample& sample : scaled) {
          for (Eigen::Index j = 0; j < joints_; ++j)
            sample.values(j) = start(j) + (1.0 + delta(j)) * (sample.values(j) - start(j));
        }
        s = model_->predict(scaled).mean;
      }
      const Pose2 moved(delta(joints_), delta(joints_ + 1), delta(joints_ + 2));
      return moved.inverse() * s * moved;
    };
    Eigen::VectorXd step(joints_ + 3), unit(joints_ + 3);
    step.head(joints_).setConstant(kRelativeStep);
    unit.head(joints_).setConstant(kPercent);
    step.tail<3>().setConstant(kAbsoluteStep);
    unit.tail<3>() << kCentimetre, kCentimetre, kDegree;
    return centralDifferences(predict, step, unit);
  }

private:
  std::shared_ptr<const MotionModel> model_;
  Eigen::Index joints_ = 0;
};

/// Several sensors on one robot: the wheel columns of each sensor's own hypotheses in shared
/// columns, its three mounting columns in a block of its own.
class SensorsChangeHypotheses : public ChangeHypotheses
{
public:
  explicit SensorsChangeHypotheses(std::vector<std::unique_ptr<ChangeHypotheses>> per_sensor)
      : per_sensor_(std::move(per_sensor))
  {
    const std::vector<ChangeHypothesis>& first = per_sensor_.front()->hypotheses();
    wheels_ = static_cast<Eigen::Index>(first.size()) - kMountingColumns;
    hypotheses_.assign(first.begin(), first.begin() + wheels_);
    for (std::size_t s = 0; s < per_sensor_.size(); ++s) {
      const std::vector<ChangeHypothesis>& own = per_sensor_[s]->hypotheses();
      if (static_cast<Eigen::Index>(own.size()) != wheels_ + kMountingColumns)
        throw std::invalid_argument("change hypotheses: the sensors' models differ in kind");
      for (Eigen::Index i = 0; i < wheels_; ++i) {
        if (own[static_cast<std::size_t>(i)].name != first[static_cast<std::size_t>(i)].name)
          throw std::invalid_argument("change hypotheses: the sensors' models differ in kind");
      }
      for (auto h = own.end() - kMountingColumns; h != own.end(); ++h) {
        hypotheses_.push_back(*h);
        hypotheses_.back().sensor = static_cast<int>(s);
      }
    }
  }

  Eigen::MatrixXd sensitivity(const std::vector<EncoderSample>& samples) const override
  {
    return sensorSensitivity(samples, 0);
  }
  std::size_t sensors() const override { return per_sensor_.size(); }
  Eigen::MatrixXd sensorSensitivity(const std::vector<EncoderSample>& samples,
                                    std::size_t sensor) const override
  {
    if (sensor >= per_sensor_.size())
      throw std::invalid_argument("change hypotheses: no sensor " + std::to_string(sensor));
    const Eigen::MatrixXd own = per_sensor_[sensor]->sensitivity(samples);
    Eigen::MatrixXd jacobian =
        Eigen::MatrixXd::Zero(3, static_cast<Eigen::Index>(hypotheses_.size()));
    jacobian.leftCols(wheels_) = own.leftCols(wheels_);
    jacobian.middleCols(wheels_ + kMountingColumns * static_cast<Eigen::Index>(sensor),
                        kMountingColumns) = own.rightCols(kMountingColumns);
    return jacobian;
  }

private:
  static constexpr Eigen::Index kMountingColumns = 3;  // x, y, yaw: the last of each sensor's
  std::vector<std::unique_ptr<ChangeHypotheses>> per_sensor_;
  Eigen::Index wheels_ = 0;
};

}  // namespace

Eigen::MatrixXd ChangeHypotheses::sensorSensitivity(const std::vector<EncoderSample>& samples,
                                                    std::size_t sensor) const
{
  if (sensor != 0)
    throw std::invalid_argument("change hypotheses: no sensor " + std::to_string(sensor) +
                                " (one sensor described)");
  return sensitivity(samples);
}

std::unique_ptr<ChangeHypotheses> makeChangeHypotheses(std::shared_ptr<const MotionModel> model,
                                                       const std::string& sensor_name,
                                                       const std::vector<std::string>& joint_names)
{
  if (!model)
    throw std::invalid_argument("change hypotheses: no model");
  if (const auto* diff = dynamic_cast<const DiffDriveModel*>(model.get())) {
    return std::make_unique<DiffDriveHypotheses>(
        diff->intrinsics(), diff->T_base_sensor(), diff->options().layout, sensor_name, "wheel",
        [](const std::vector<EncoderSample>& samples) { return samples; });
  }
  if (const auto* skid = dynamic_cast<const SkidSteerModel*>(model.get())) {
    const SkidSteerOptions options = skid->options();
    DiffDriveEncoderLayout layout;  // the averaged sides: left 0, right 1
    layout.ticks_per_turn = options.ticks_per_turn;
    return std::make_unique<DiffDriveHypotheses>(
        skid->intrinsics(), skid->T_base_sensor(), layout, sensor_name, "side's effective",
        [options](const std::vector<EncoderSample>& samples) {
          return averageSides(samples, options.left_indices, options.right_indices);
        });
  }
  return std::make_unique<JointScaleHypotheses>(std::move(model), sensor_name, joint_names);
}

std::unique_ptr<ChangeHypotheses> makeSensorsChangeHypotheses(
    const std::vector<std::shared_ptr<const MotionModel>>& models,
    const std::vector<std::string>& sensor_names, const std::vector<std::string>& joint_names)
{
  if (models.empty() || models.size() != sensor_names.size())
    throw std::invalid_argument("change hypotheses: one name per sensor needed (" +
                                std::to_string(models.size()) + " models, " +
                                std::to_string(sensor_names.size()) + " names)");
  std::vector<std::unique_ptr<ChangeHypotheses>> per_sensor;
  for (std::size_t s = 0; s < models.size(); ++s) {
    if (sensor_names[s].empty() ||
        std::count(sensor_names.begin(), sensor_names.end(), sensor_names[s]) > 1)
      throw std::invalid_argument("change hypotheses: sensor " + std::to_string(s) +
                                  "'s name is empty or repeated ('" + sensor_names[s] + "')");
    per_sensor.push_back(makeChangeHypotheses(models[s], sensor_names[s], joint_names));
  }
  return std::make_unique<SensorsChangeHypotheses>(std::move(per_sensor));
}

}  // namespace odometry_calibration
