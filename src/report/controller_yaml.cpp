#include "odometry_calibration/report/controller_yaml.h"

#include <cmath>
#include <cstdio>
#include <vector>

namespace odometry_calibration {
namespace {

const ParameterEstimate* find(const ModelReport& report, const std::string& name)
{
  for (const ParameterEstimate& p : report.parameters) {
    if (p.name == name)
      return &p;
  }
  return nullptr;
}

std::string number(double value)
{
  char text[64];
  std::snprintf(text, sizeof(text), "%.7g", value);
  return text;
}

std::string sigma(double value)
{
  return std::isfinite(value) ? "sigma " + number(value) : "sigma unavailable (not determined)";
}

std::string header(const ModelReport& report, const std::string& source, const char* what)
{
  return "# " + std::string(what) + "\n# From the odometry_calibration fit of " + source +
         " (model " + report.model + ", " + std::to_string(report.pairs_used) + " pairs" +
         (report.warnings.empty() ? "" : "; the fit has WARNINGS, see report.txt") + ").\n";
}

/// diff_drive_controller: geometric values plus the multipliers that make them the fitted ones.
std::string diffDriveController(const ModelReport& report, const std::string& source,
                                const ParameterEstimate& left, const ParameterEstimate& right,
                                const ParameterEstimate& separation)
{
  const double radius = left.initial;
  std::string text = header(report, source,
                            "ros_control diff_drive_controller parameters: paste under the "
                            "controller's namespace.\n# wheel_separation and wheel_radius are "
                            "the configured nominal values; the multipliers carry the fit.");
  text += "wheel_separation: " + number(separation.initial) + "  # configured nominal [m]\n";
  text += "wheel_radius: " + number(radius) + "  # configured nominal [m]\n";
  auto multiplier = [&](const char* key, const ParameterEstimate& p, double nominal,
                        const char* fitted) {
    text += std::string(key) + ": " + number(p.value / nominal) + "  # " +
            sigma(p.sigma / nominal) + "; fitted " + fitted + " " + number(p.value) + " m, " +
            sigma(p.sigma) + " m\n";
  };
  multiplier("wheel_separation_multiplier", separation, separation.initial, "effective separation");
  multiplier("left_wheel_radius_multiplier", left, radius, "left radius");
  multiplier("right_wheel_radius_multiplier", right, radius, "right radius");
  return text;
}

/// Mecanum: ros2_controllers' mecanum_drive_controller (ROS 2 Jazzy, ros2_controllers 4.x)
/// reads one radius and lx + ly under its nested `kinematics` keys; the fitted per-wheel radii,
/// which no controller reads, are comments.
std::string mecanumController(const ModelReport& report, const std::string& source,
                              const std::vector<const ParameterEstimate*>& radii,
                              const ParameterEstimate* lever)
{
  std::string text = header(report, source,
                            "ros2_controllers mecanum_drive_controller parameters (ROS 2 Jazzy, "
                            "ros2_controllers 4.x): paste under\n# the controller's "
                            "ros__parameters.");
  double sum = 0.0, variance = 0.0;
  if (!radii.empty())
    text += "# The fitted radius of each wheel (the controller takes one: their mean below):\n";
  for (const ParameterEstimate* r : radii) {
    text += "#   " + r->name + ": " + number(r->value) + "  (" + sigma(r->sigma) + " [" + r->unit +
            "]; configured " + number(r->initial) + ")\n";
    sum += r->value;
    variance += r->sigma * r->sigma;
  }
  text += "kinematics:\n";
  if (!radii.empty()) {
    const double n = static_cast<double>(radii.size());
    text += "  wheels_radius: " + number(sum / n) + "  # " + sigma(std::sqrt(variance) / n) +
            " [m]; the mean of the " + std::to_string(radii.size()) +
            " radii (taken as independent)\n";
  }
  if (lever) {
    text += "  sum_of_robot_center_projection_on_X_Y_axis: " + number(lever->value) + "  # " +
            sigma(lever->sigma) + " [" + lever->unit + "]; lx + ly (" + lever->name +
            "), configured " + number(lever->initial) + "\n";
  }
  return text;
}

}  // namespace

std::string controllerYaml(const ModelReport& report, const std::string& source)
{
  const ParameterEstimate* left = find(report, "left_wheel_radius");
  const ParameterEstimate* right = find(report, "right_wheel_radius");
  const ParameterEstimate* separation = find(report, "wheel_separation");
  if (left && right && separation && left->initial > 0.0 && separation->initial > 0.0)
    return diffDriveController(report, source, *left, *right, *separation);
  std::vector<const ParameterEstimate*> radii;
  for (const ParameterEstimate& p : report.parameters) {
    if (p.name.rfind("wheel_radius_", 0) == 0)
      radii.push_back(&p);
  }
  const ParameterEstimate* lever = find(report, "lx_plus_ly");
  if (lever || !radii.empty())
    return mecanumController(report, source, radii, lever);
  return "";
}

}  // namespace odometry_calibration
