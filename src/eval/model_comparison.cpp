#include "odometry_calibration/eval/model_comparison.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "odometry_calibration/eval/metrics.h"

namespace odometry_calibration {

ModelScore scoreModel(const MotionModel& model, const std::vector<MotionPair>& test)
{
  if (test.size() < 2) {
    throw std::invalid_argument("scoring needs at least two test pairs");
  }
  ModelScore score;
  score.model = model.name();
  score.test_pairs = test.size();
  std::vector<Pose2> predicted = {Pose2()}, measured = {Pose2()};
  score.stamps_s = {test.front().start_stamp_s};
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const MotionPair& pair : test) {
    score.stamps_s.push_back(pair.end_stamp_s);
    const Pose2 prediction = model.predict(pair.encoder_samples).mean;
    const Eigen::Vector3d error(prediction.x() - pair.sensor_motion.x(),
                                prediction.y() - pair.sensor_motion.y(),
                                normalizeAngle(prediction.theta() - pair.sensor_motion.theta()));
    sum += error.cwiseAbs2();
    predicted.push_back(predicted.back() * prediction);
    measured.push_back(measured.back() * pair.sensor_motion);
  }
  score.rmse_xytheta = (sum / static_cast<double>(test.size())).cwiseSqrt();
  score.ate_m = absoluteTrajectoryError(predicted, measured);
  score.rpe_m = relativePoseError(predicted, measured);
  score.predicted = std::move(predicted);
  score.measured = std::move(measured);
  return score;
}

ModelScore scoreNominal(const MotionModel& nominal, const std::vector<MotionPair>& test)
{
  ModelScore score = scoreModel(nominal, test);
  score.model = "nominal";
  score.fitted = false;
  score.nominal_model = nominal.name();
  return score;
}

ModelScore withFitReport(ModelScore score, const ModelReport& report)
{
  score.fit_time_s = report.fit_time_s;
  score.outliers = report.outliers;
  score.warnings = report.warnings;
  score.converged = report.converged;
  score.termination = report.termination;
  if (report.has_extrinsic)
    score.T_base_sensor = report.T_base_sensor;
  return score;
}

std::string formatComparisonTable(const std::vector<ModelScore>& scores)
{
  std::string table;
  char line[256];
  std::snprintf(line, sizeof(line), "%-12s %10s %10s %11s %11s %13s %9s %8s\n", "model", "ATE [m]",
                "RPE [m]", "RMSE x [m]", "RMSE y [m]", "RMSE th [rad]", "fit [s]", "outliers");
  table += line;
  for (const ModelScore& s : scores) {
    if (!s.skipped.empty()) {
      std::snprintf(line, sizeof(line), "%-12s %10s  skipped: it cannot be fitted here\n",
                    s.model.c_str(), "-");
      table += line;
      continue;
    }
    char fit[32] = "-", outliers[32] = "-";
    if (s.fitted) {
      std::snprintf(fit, sizeof(fit), "%.3f", s.fit_time_s);
      std::snprintf(outliers, sizeof(outliers), "%zu", s.outliers);
    }
    std::snprintf(line, sizeof(line), "%-12s %10.4f %10.5f %11.5f %11.5f %13.5f %9s %8s%s\n",
                  s.model.c_str(), s.ate_m, s.rpe_m, s.rmse_xytheta(0), s.rmse_xytheta(1),
                  s.rmse_xytheta(2), fit, outliers, s.converged ? "" : "  NOT converged");
    table += line;
  }
  for (const ModelScore& s : scores) {
    if (!s.fitted && s.model == "nominal") {
      table += "nominal: the configured nominal model, not fitted (" + s.nominal_model +
               " at its start values)\n";
      break;
    }
  }
  for (const ModelScore& s : scores) {
    if (!s.skipped.empty())
      table += "skipped: " + s.model + " (" + s.skipped + ")\n";
  }
  for (const ModelScore& s : scores) {
    if (!s.converged) {
      table += "NOT converged: " + s.model + " (" + s.termination +
               "); its scores are those of wherever the solver stopped, not a calibration\n";
    }
  }
  return table;
}

namespace {

/// The scored rows' names (not skipped, converged) from the lowest `score` to the highest.
std::vector<std::string> rankBy(const std::vector<ModelScore>& scores,
                                double (*score)(const ModelScore&))
{
  std::vector<const ModelScore*> scored;
  for (const ModelScore& s : scores) {
    if (s.skipped.empty() && s.converged)
      scored.push_back(&s);
  }
  std::stable_sort(scored.begin(), scored.end(),
                   [&](const ModelScore* a, const ModelScore* b) { return score(*a) < score(*b); });
  std::vector<std::string> names;
  for (const ModelScore* s : scored)
    names.push_back(s->model);
  return names;
}

std::string joinRanking(const std::vector<std::string>& ranking)
{
  std::string text;
  for (std::size_t k = 0; k < ranking.size(); ++k)
    text += (k == 0 ? " " : " < ") + ranking[k];
  return text;
}

}  // namespace

std::vector<std::string> rankByAte(const std::vector<ModelScore>& scores)
{
  return rankBy(scores, [](const ModelScore& s) { return s.ate_m; });
}

std::vector<std::string> rankByRpe(const std::vector<ModelScore>& scores)
{
  return rankBy(scores, [](const ModelScore& s) { return s.rpe_m; });
}

std::string formatBestModel(const std::vector<ModelScore>& scores, const std::string& where)
{
  const std::vector<std::string> ranking = rankByAte(scores);
  if (ranking.size() < 2)
    return "";
  auto row = [&](const std::string& name) -> const ModelScore& {
    return *std::find_if(scores.begin(), scores.end(),
                         [&](const ModelScore& s) { return s.model == name; });
  };
  const ModelScore& best = row(ranking[0]);
  char text[200];
  std::snprintf(text, sizeof(text), "best on %s: %s, ATE %.4f m", where.c_str(), best.model.c_str(),
                best.ate_m);
  std::string line = text;
  auto lower = [&](const ModelScore& other) {
    std::snprintf(text, sizeof(text), ", %.1fx lower than %s (%.4f m)",
                  best.ate_m > 0.0 ? other.ate_m / best.ate_m : INFINITY, other.model.c_str(),
                  other.ate_m);
    line += text;
  };
  lower(row(ranking[1]));
  if (std::find(ranking.begin() + 2, ranking.end(), "nominal") != ranking.end())
    lower(row("nominal"));
  return line + "; ranking by ATE:" + joinRanking(ranking) +
         ", by RPE:" + joinRanking(rankByRpe(scores)) + "\n";
}

std::vector<ModelScore> compareModels(const std::vector<std::string>& models,
                                      const ModelFactoryOptions& options,
                                      const std::vector<MotionPair>& training,
                                      const std::vector<MotionPair>& testing,
                                      const MotionModel* nominal)
{
  std::vector<ModelScore> scores;
  for (const std::string& name : models) {
    auto model = makeModel(name, options);
    if (training.empty())
      throw std::invalid_argument("the training files hold no pair");
    const ModelReport report = model->fit(training);
    scores.push_back(withFitReport(scoreModel(*model, testing), report));
  }
  if (nominal)
    scores.push_back(scoreNominal(*nominal, testing));
  return scores;
}

}  // namespace odometry_calibration
