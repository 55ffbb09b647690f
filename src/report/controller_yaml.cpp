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

/// The fit a controller.yaml comes from, as its header gives it: "model diff_drive, 240 pairs".
struct FitOrigin
{
  std::string fit;
  bool warnings = false;
  const char* report_file = "report.txt";  ///< where the warnings are
};

FitOrigin oneSensorOrigin(const ModelReport& report)
{
  return {"model " + report.model + ", " + std::to_string(report.pairs_used) + " pairs",
          !report.warnings.empty()};
}

std::string header(const FitOrigin& origin, const std::string& source, const char* what)
{
  return "# " + std::string(what) + "\n# From the odometry_calibration fit of " + source + " (" +
         origin.fit +
         (origin.warnings ? std::string("; the fit has WARNINGS, see ") + origin.report_file
                          : std::string()) +
         ").\n";
}

/// diff_drive_controller: geometric values plus the multipliers that make them the fitted ones.
std::string diffDriveController(const FitOrigin& origin, const std::string& source,
                                const ParameterEstimate& left, const ParameterEstimate& right,
                                const ParameterEstimate& separation)
{
  const double radius = left.initial;
  std::string text = header(origin, source,
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

/// A tracked base (b(nu) = b0 + b1 nu, tracked_kinematics.h): diff_drive_controller takes one
/// separation; the multiplier above is b0's (straight, gentle curves), this comment gives the
/// one for turning on the spot. Empty without `growth`.
std::string separationGrowthAdvice(const ParameterEstimate* growth,
                                   const ParameterEstimate& separation)
{
  if (!growth)
    return "";
  const double spot = separation.value + growth->value;
  return "# tracked base: the separation grows with the turn's tightness nu (0 straight, 1 on the "
         "spot):\n#   b(nu) = " +
         number(separation.value) + " + " + number(growth->value) + " nu m (separation_growth " +
         sigma(growth->sigma) + " m); on the spot " + number(spot) +
         " m,\n#   wheel_separation_multiplier " + number(spot / separation.initial) +
         " for a base that mostly turns on the spot\n";
}

/// Mecanum: ros2_controllers' mecanum_drive_controller (ROS 2 Jazzy, ros2_controllers 4.x)
/// reads one radius and lx + ly under its nested `kinematics` keys; the fitted per-wheel radii,
/// which no controller reads, are comments.
std::string mecanumController(const FitOrigin& origin, const std::string& source,
                              const std::vector<const ParameterEstimate*>& radii,
                              const ParameterEstimate* lever)
{
  std::string text = header(origin, source,
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

/// controller.yaml's text for the values of `report`, `origin` its header's fit.
std::string controllerYamlFrom(const ModelReport& report, const FitOrigin& origin,
                               const std::string& source)
{
  const ParameterEstimate* left = find(report, "left_wheel_radius");
  const ParameterEstimate* right = find(report, "right_wheel_radius");
  const ParameterEstimate* separation = find(report, "wheel_separation");
  if (left && right && separation && left->initial > 0.0 && separation->initial > 0.0) {
    return diffDriveController(origin, source, *left, *right, *separation) +
           separationGrowthAdvice(find(report, "separation_growth"), *separation);
  }
  std::vector<const ParameterEstimate*> radii;
  for (const ParameterEstimate& p : report.parameters) {
    if (p.name.rfind("wheel_radius_", 0) == 0)
      radii.push_back(&p);
  }
  const ParameterEstimate* lever = find(report, "lx_plus_ly");
  if (lever || !radii.empty())
    return mecanumController(origin, source, radii, lever);
  return "";
}

}  // namespace

std::string controllerYaml(const ModelReport& report, const std::string& source)
{
  return controllerYamlFrom(report, oneSensorOrigin(report), source);
}

std::string jointControllerYaml(const JointFitReport& joint, const std::string& source)
{
  FitOrigin origin;
  origin.fit =
      "joint " + joint.model + " fit of " + std::to_string(joint.sensors.size()) + " sensors, ";
  std::size_t total = 0;
  for (std::size_t s = 0; s < joint.sensors.size(); ++s) {
    origin.fit += (s == 0 ? "" : " + ") + std::to_string(joint.sensors[s].pairs);
    total += joint.sensors[s].pairs;
    origin.warnings = origin.warnings || !joint.sensors[s].warnings.empty();
  }
  origin.fit += (joint.sensors.size() > 1 ? " = " + std::to_string(total) : "") + " pairs";
  origin.report_file = "joint_report.txt";
  return controllerYamlFrom(sensorModelReport(joint, 0), origin, source);
}

}  // namespace odometry_calibration
