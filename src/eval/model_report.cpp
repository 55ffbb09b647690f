#include "odometry_calibration/eval/model_report.h"

#include <cmath>
#include <cstdio>

#include <yaml-cpp/yaml.h>

namespace odometry_calibration {

namespace {

/// The parameter table: initial value, estimate, sigma and unit of each parameter.
std::string parameterTable(const std::vector<ParameterEstimate>& parameters)
{
  std::string text;
  char line[512];
  std::snprintf(line, sizeof(line), "\n%-29s %12s %14s %12s  %s\n", "parameter", "initial",
                "estimate", "sigma", "unit");
  text += line;
  for (const ParameterEstimate& p : parameters) {
    // Learned quantities without a start value or a sigma (GP hyperparameters) show "-".
    char initial[32] = "-", sigma[32] = "-";
    if (std::isfinite(p.initial))
      std::snprintf(initial, sizeof(initial), "%.6g", p.initial);
    if (std::isfinite(p.sigma))
      std::snprintf(sigma, sizeof(sigma), "%.3g", p.sigma);
    std::snprintf(line, sizeof(line), "%-29s %12s %14.7g %12s  %s\n", p.name.c_str(), initial,
                  p.value, sigma, p.unit.c_str());
    text += line;
  }
  return text;
}

/// The residual RMS per pair before and after the fit, per axis, and the sensor pose.
std::string residualLines(const ModelReport& r)
{
  std::string text;
  char line[512];
  // A "before" exists only for models with start values (the parametric ones); the model-free
  // fits have none, and the nominal model's numbers are in the comparison lines instead.
  if (r.before.count > 0) {
    std::snprintf(line, sizeof(line),
                  "\nresidual RMS per pair: translation %.4f m -> %.4f m, rotation %.5f rad -> "
                  "%.5f rad\n",
                  r.before.translation_m, r.after.translation_m, r.before.rotation_rad,
                  r.after.rotation_rad);
  } else {
    std::snprintf(line, sizeof(line),
                  "\nresidual RMS per pair: translation %.4f m, rotation %.5f rad (no start "
                  "values: nothing before the fit)\n",
                  r.after.translation_m, r.after.rotation_rad);
  }
  text += line;
  std::snprintf(line, sizeof(line),
                "(per axis on the kept pairs: x %.4f m, y %.4f m, theta %.5f rad)\n",
                r.residual_rms_xytheta(0), r.residual_rms_xytheta(1), r.residual_rms_xytheta(2));
  text += line;
  if (r.has_extrinsic) {
    std::snprintf(line, sizeof(line),
                  "sensor pose in base_link: x %.4f m, y %.4f m, theta %.5f rad\n",
                  r.T_base_sensor.x(), r.T_base_sensor.y(), r.T_base_sensor.theta());
    text += line;
  }
  return text;
}

}  // namespace

std::string formatModelReport(const ModelReport& r)
{
  std::string text;
  char line[512];
  std::snprintf(line, sizeof(line), "Model '%s': %zu pairs, %zu rejected, %zu down-weighted\n",
                r.model.c_str(), r.pairs_used, r.rejected, r.down_weighted);
  text += line;
  std::snprintf(line, sizeof(line), "fit: %s after %d iterations, %.3f s (%s)\n",
                r.converged ? "converged" : "NOT converged", r.iterations, r.fit_time_s,
                r.termination.c_str());
  text += line;
  if (r.starts > 1) {
    std::snprintf(line, sizeof(line), "starts: %d of %d sensor-yaw starts reached the best fit\n",
                  r.starts_agreed, r.starts);
    text += line;
  }
  if (!r.parameters.empty()) {
    text += parameterTable(r.parameters);
  }
  text += residualLines(r);
  text += r.warnings.empty() ? "observability: no warning\n" : "WARNINGS:\n";
  for (const std::string& warning : r.warnings)
    text += "  - " + warning + "\n";
  for (const std::string& note : r.notes)
    text += "  note: " + note + "\n";
  return text;
}

std::string modelResultYaml(const ModelReport& r, const std::string& model_yaml,
                            const std::string& source)
{
  YAML::Emitter out;
  out.SetDoublePrecision(10);
  out << YAML::BeginMap;
  out << YAML::Key << "source" << YAML::Value << source;
  out << YAML::Key << "model" << YAML::Value << YAML::Load(model_yaml);
  out << YAML::Key << "fit" << YAML::Value << YAML::BeginMap;
  out << YAML::Key << "model" << YAML::Value << r.model;
  out << YAML::Key << "converged" << YAML::Value << r.converged;
  out << YAML::Key << "iterations" << YAML::Value << r.iterations;
  out << YAML::Key << "termination" << YAML::Value << r.termination;
  out << YAML::Key << "pairs" << YAML::Value << r.pairs_used;
  out << YAML::Key << "outliers" << YAML::Value << r.outliers;
  out << YAML::Key << "rejected" << YAML::Value << r.rejected;
  out << YAML::Key << "down_weighted" << YAML::Value << r.down_weighted;
  out << YAML::Key << "starts" << YAML::Value << r.starts;
  out << YAML::Key << "starts_agreed" << YAML::Value << r.starts_agreed;
  out << YAML::Key << "residual_rms_translation_m" << YAML::Value << r.after.translation_m;
  out << YAML::Key << "residual_rms_rotation_rad" << YAML::Value << r.after.rotation_rad;
  out << YAML::EndMap;
  out << YAML::Key << "parameters" << YAML::Value << YAML::BeginMap;
  for (const ParameterEstimate& p : r.parameters) {
    out << YAML::Key << p.name << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "value" << YAML::Value << p.value << YAML::Key << "sigma" << YAML::Value << p.sigma
        << YAML::Key << "unit" << YAML::Value << p.unit << YAML::EndMap;
  }
  out << YAML::EndMap;
  if (r.has_extrinsic) {
    out << YAML::Key << "T_base_sensor" << YAML::Value << YAML::Flow << YAML::BeginMap << YAML::Key
        << "x_m" << YAML::Value << r.T_base_sensor.x() << YAML::Key << "y_m" << YAML::Value
        << r.T_base_sensor.y() << YAML::Key << "theta_rad" << YAML::Value << r.T_base_sensor.theta()
        << YAML::EndMap;
  }
  out << YAML::Key << "warnings" << YAML::Value << YAML::BeginSeq;
  for (const std::string& warning : r.warnings)
    out << warning;
  out << YAML::EndSeq;
  out << YAML::Key << "notes" << YAML::Value << YAML::BeginSeq;
  for (const std::string& note : r.notes)
    out << note;
  out << YAML::EndSeq << YAML::EndMap;
  return "# odometry_calibration result\n" + std::string(out.c_str()) + "\n";
}

}  // namespace odometry_calibration
