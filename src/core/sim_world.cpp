#include "odometry_calibration/sim/world.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

namespace odometry_calibration {
namespace sim {

World::World(std::vector<Segment> segments) : segments_(std::move(segments))
{
  for (const Segment& s : segments_) {
    ax_.push_back(s.a.x());
    ay_.push_back(s.a.y());
    dx_.push_back(s.b.x() - s.a.x());
    dy_.push_back(s.b.y() - s.a.y());
  }
}

double World::castRay(const Eigen::Vector2d& origin, double angle_rad, double max_range_m) const
{
  // Ray o + t u (t >= 0) against segment a + s d (0 <= s <= 1): solve with 2D cross products,
  // t = ((a - o) x d) / (u x d), s = ((a - o) x u) / (u x d).
  const double ux = std::cos(angle_rad);
  const double uy = std::sin(angle_rad);
  double best = max_range_m;
  bool hit = false;
  const std::size_t n = ax_.size();
  for (std::size_t i = 0; i < n; ++i) {
    const double denominator = ux * dy_[i] - uy * dx_[i];
    if (std::abs(denominator) < 1e-15) {
      continue;  // parallel
    }
    const double wx = ax_[i] - origin.x();
    const double wy = ay_[i] - origin.y();
    const double t = (wx * dy_[i] - wy * dx_[i]) / denominator;
    const double s = (wx * uy - wy * ux) / denominator;
    if (t > 0.0 && t <= best && s >= 0.0 && s <= 1.0) {
      best = t;
      hit = true;
    }
  }
  return hit ? best : std::numeric_limits<double>::infinity();
}

double World::clearance(const Eigen::Vector2d& point) const
{
  double best = std::numeric_limits<double>::infinity();
  for (const Segment& s : segments_) {
    const Eigen::Vector2d d = s.b - s.a;
    const double length2 = d.squaredNorm();
    const double t = length2 > 0.0 ? std::clamp((point - s.a).dot(d) / length2, 0.0, 1.0) : 0.0;
    best = std::min(best, (s.a + t * d - point).norm());
  }
  return best;
}

namespace {

Eigen::Vector2d point2(const YAML::Node& node, const std::string& what)
{
  if (!node.IsSequence() || node.size() != 2) {
    throw std::runtime_error(what + ": expected a point [x, y]");
  }
  return Eigen::Vector2d(node[0].as<double>(), node[1].as<double>());
}

void addOutline(const std::vector<Eigen::Vector2d>& corners, std::vector<Segment>* segments)
{
  for (std::size_t i = 0; i < corners.size(); ++i) {
    segments->push_back({corners[i], corners[(i + 1) % corners.size()]});
  }
}

}  // namespace

World parseWorldYaml(const std::string& text, const std::string& source)
{
  std::vector<Segment> segments;
  std::string entry = source;
  try {
    const YAML::Node root = YAML::Load(text);
    if (!root.IsMap()) {
      throw std::runtime_error("expected a map with segments/polygons/boxes/circles");
    }
    for (const auto& key : root) {
      const std::string name = key.first.as<std::string>();
      if (name != "segments" && name != "polygons" && name != "boxes" && name != "circles" &&
          name != "description") {
        throw std::runtime_error("unknown key '" + name +
                                 "' (expected segments, polygons, boxes, circles, description)");
      }
    }
    std::size_t index = 0;
    for (const YAML::Node& node : root["segments"]) {
      entry = "segments[" + std::to_string(index++) + "]";
      if (!node.IsSequence() || node.size() != 4) {
        throw std::runtime_error("expected [x0, y0, x1, y1]");
      }
      segments.push_back({Eigen::Vector2d(node[0].as<double>(), node[1].as<double>()),
                          Eigen::Vector2d(node[2].as<double>(), node[3].as<double>())});
    }
    index = 0;
    for (const YAML::Node& node : root["polygons"]) {
      entry = "polygons[" + std::to_string(index++) + "]";
      std::vector<Eigen::Vector2d> corners;
      for (const YAML::Node& corner : node) {
        corners.push_back(point2(corner, "corner"));
      }
      if (corners.size() < 3) {
        throw std::runtime_error("a polygon needs at least 3 corners");
      }
      addOutline(corners, &segments);
    }
    index = 0;
    for (const YAML::Node& node : root["boxes"]) {
      entry = "boxes[" + std::to_string(index++) + "]";
      const Eigen::Vector2d center = point2(node["center"], "center");
      const Eigen::Vector2d size = point2(node["size"], "size");
      const double yaw = node["yaw"] ? node["yaw"].as<double>() : 0.0;
      if (!(size.x() > 0.0) || !(size.y() > 0.0)) {
        throw std::runtime_error("size must be positive");
      }
      const Eigen::Rotation2Dd rotation(yaw);
      std::vector<Eigen::Vector2d> corners;
      for (const auto& sign : {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1),
                               Eigen::Vector2d(1, 1), Eigen::Vector2d(-1, 1)}) {
        corners.push_back(center + rotation * (0.5 * size.cwiseProduct(sign)));
      }
      addOutline(corners, &segments);
    }
    index = 0;
    for (const YAML::Node& node : root["circles"]) {
      entry = "circles[" + std::to_string(index++) + "]";
      const Eigen::Vector2d center = point2(node["center"], "center");
      const double radius = node["radius"].as<double>();
      const int sides = node["sides"] ? node["sides"].as<int>() : 24;
      if (!(radius > 0.0) || sides < 3) {
        throw std::runtime_error("radius must be positive and sides >= 3");
      }
      std::vector<Eigen::Vector2d> corners;
      for (int k = 0; k < sides; ++k) {
        const double angle = 2.0 * M_PI * k / sides;
        corners.push_back(center + radius * Eigen::Vector2d(std::cos(angle), std::sin(angle)));
      }
      addOutline(corners, &segments);
    }
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(source + ": " + entry + ": " + error.what());
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(source + ": " + entry + ": " + error.what());
  }
  if (segments.empty()) {
    throw std::runtime_error(source + ": the world has no walls");
  }
  return World(std::move(segments));
}

World loadWorldYaml(const std::string& path)
{
  std::ifstream file(path);
  if (!file) {
    throw std::runtime_error("cannot open world file '" + path + "'");
  }
  std::stringstream text;
  text << file.rdbuf();
  return parseWorldYaml(text.str(), path);
}

}  // namespace sim
}  // namespace odometry_calibration
