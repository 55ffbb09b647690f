// The change attribution (issue 34) on synthetic sensitivities: the candidate that made the
// residuals is named with its size, two candidates the pairs cannot tell apart are said to be
// so, noise names nothing, and the calibration's own error before the change is taken out.
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "odometry_calibration/assistant/change_attribution.h"

namespace odometry_calibration {
namespace {

/// Per pair, values(0) = forward motion q, values(1) = rotation w. Candidates: "radius" (q, 0,
/// w / 2), "separation" (0, 0, w) or, `twin`, a second "radius" of the same column, and "yaw"
/// (0, q, 0), a mounting change.
class FakeHypotheses : public ChangeHypotheses
{
public:
  explicit FakeHypotheses(bool twin) : twin_(twin)
  {
    hypotheses_ = {{"radius", ChangeKind::kWheel, "%", 20.0},
                   {twin ? "other radius" : "separation", ChangeKind::kWheel, "%", 20.0},
                   {"yaw", ChangeKind::kMounting, "deg", 20.0}};
  }
  Eigen::MatrixXd sensitivity(const std::vector<EncoderSample>& samples) const override
  {
    const double q = samples.front().values(0), w = samples.front().values(1);
    Eigen::MatrixXd jacobian(3, 3);
    const Eigen::Vector3d radius(q, 0.0, 0.5 * w);
    jacobian.col(0) = radius;
    jacobian.col(1) = twin_ ? radius : Eigen::Vector3d(0.0, 0.0, w);
    jacobian.col(2) = Eigen::Vector3d(0.0, q, 0.0);
    return jacobian;
  }

private:
  bool twin_;
};

/// Feeds `count` pairs from index `first`: residual = J * delta + unit noise.
void feed(ChangeAttribution& attribution, std::size_t first, int count,
          const Eigen::Vector3d& delta, std::mt19937& rng)
{
  std::normal_distribution<double> noise(0.0, 1.0);
  std::uniform_real_distribution<double> motion(-1.0, 1.0);
  for (int i = 0; i < count; ++i) {
    EncoderSample sample;
    sample.values = Eigen::Vector2d(motion(rng), motion(rng));
    const std::vector<EncoderSample> samples = {sample, sample};
    const Eigen::Vector3d residual = attribution.hypotheses().sensitivity(samples) * delta +
                                     Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    ASSERT_TRUE(attribution.add(first + static_cast<std::size_t>(i), samples, residual,
                                Eigen::Matrix3d::Identity()));
  }
}

TEST(ChangeAttribution, NamesTheCandidateThatMadeTheResidualsWithItsSize)
{
  std::mt19937 rng(3);
  ChangeAttribution attribution(std::make_unique<FakeHypotheses>(false));
  feed(attribution, 1, 100, Eigen::Vector3d::Zero(), rng);
  feed(attribution, 101, 40, Eigen::Vector3d(0.0, 2.0, 0.0), rng);  // separation +2
  const ChangeVerdict verdict = attribution.verdict(100);
  ASSERT_TRUE(verdict.significant);
  EXPECT_TRUE(verdict.kind_told);
  EXPECT_EQ(verdict.kind, ChangeKind::kWheel);
  ASSERT_TRUE(verdict.quantity_told) << verdict.words;
  const ChangeCandidate& best = verdict.candidates.front();
  EXPECT_EQ(best.hypothesis.name, "separation");
  EXPECT_NEAR(best.estimate, 2.0, 4.0 * best.sigma);
  EXPECT_LT(best.sigma, 0.5);
  EXPECT_NE(verdict.words.find("a wheel change, the separation (+"), std::string::npos)
      << verdict.words;
}

TEST(ChangeAttribution, SaysWhenTwoCandidatesCannotBeToldApart)
{
  std::mt19937 rng(4);
  ChangeAttribution attribution(std::make_unique<FakeHypotheses>(true));
  feed(attribution, 1, 100, Eigen::Vector3d::Zero(), rng);
  feed(attribution, 101, 40, Eigen::Vector3d(1.0, 0.0, 0.0), rng);
  const ChangeVerdict verdict = attribution.verdict(100);
  ASSERT_TRUE(verdict.significant);
  EXPECT_TRUE(verdict.kind_told);  // both are wheels, the yaw is far behind
  EXPECT_EQ(verdict.kind, ChangeKind::kWheel);
  EXPECT_FALSE(verdict.quantity_told);
  EXPECT_NE(verdict.words.find("cannot tell which"), std::string::npos) << verdict.words;
}

TEST(ChangeAttribution, NoiseNamesNothingAndTheCalibrationsOwnErrorIsTakenOut)
{
  std::mt19937 rng(5);
  ChangeAttribution quiet(std::make_unique<FakeHypotheses>(false));
  feed(quiet, 1, 200, Eigen::Vector3d::Zero(), rng);
  const ChangeVerdict nothing = quiet.verdict(150);
  EXPECT_FALSE(nothing.significant) << nothing.words;
  EXPECT_FALSE(nothing.kind_told);
  EXPECT_NE(nothing.words.find("no single change"), std::string::npos) << nothing.words;

  // A yaw error of 0.5 from the fit on, then the radius +1: the radius is named, its size not
  // bent by the yaw, and the yaw does not compete.
  ChangeAttribution offset(std::make_unique<FakeHypotheses>(false));
  feed(offset, 1, 200, Eigen::Vector3d(0.0, 0.0, 0.5), rng);
  feed(offset, 201, 60, Eigen::Vector3d(1.0, 0.0, 0.5), rng);
  const ChangeVerdict verdict = offset.verdict(200);
  ASSERT_TRUE(verdict.quantity_told) << verdict.words;
  EXPECT_EQ(verdict.candidates.front().hypothesis.name, "radius");
  EXPECT_NEAR(verdict.candidates.front().estimate, 1.0, 4.0 * verdict.candidates.front().sigma);
  for (const ChangeCandidate& candidate : verdict.candidates) {
    if (candidate.hypothesis.name == "yaw") {
      EXPECT_LT(candidate.chi2, 10.83) << verdict.words;
    }
  }
}

TEST(ChangeAttribution, RefusesBadOptionsAndNoHypotheses)
{
  ChangeAttributionOptions options;
  options.decisive_likelihood_ratio = 1.0;
  EXPECT_THROW(ChangeAttribution(std::make_unique<FakeHypotheses>(false), options),
               std::invalid_argument);
  EXPECT_THROW(ChangeAttribution(nullptr), std::invalid_argument);
}

}  // namespace
}  // namespace odometry_calibration
