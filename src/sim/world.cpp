#include "odometry_calibration/sim/world.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include <yaml-cpp/yaml.h>
#include <Eigen/Geometry>

#include "odometry_calibration/common/yaml_reading.h"

namespace odometry_calibration {
namespace sim {

World::World(std::vector<Segment> segments)
{
  for (const Segment& segment : segments) {
    addSegment(segment);
  }
}

void World::addSegment(const Segment& segment)
{
  segments_.push_back(segment);
  ax_.push_back(segment.a.x());
  ay_.push_back(segment.a.y());
  dx_.push_back(segment.b.x() - segment.a.x());
  dy_.push_back(segment.b.y() - segment.a.y());
  height_.push_back(segment.height_m);
}

void World::addOutline(const std::vector<Eigen::Vector2d>& corners, double height_m)
{
  for (std::size_t i = 0; i < corners.size(); ++i) {
    addSegment({corners[i], corners[(i + 1) % corners.size()], height_m});
  }
  outlines_.push_back(corners);
}

void World::addSolid(const std::vector<Eigen::Vector2d>& corners, double height_m)
{
  for (std::size_t i = 0; i < corners.size(); ++i) {
    addSegment({corners[i], corners[(i + 1) % corners.size()], height_m});
  }
  solids_.push_back(corners);
}

namespace {

/// Even-odd rule: does a horizontal ray from the point cross the polygon an odd number of times?
bool insidePolygon(const std::vector<Eigen::Vector2d>& polygon, const Eigen::Vector2d& p)
{
  bool inside = false;
  for (std::size_t i = 0, j = polygon.size() - 1; i < polygon.size(); j = i++) {
    const Eigen::Vector2d& a = polygon[i];
    const Eigen::Vector2d& b = polygon[j];
    if ((a.y() > p.y()) != (b.y() > p.y()) &&
        p.x() < (b.x() - a.x()) * (p.y() - a.y()) / (b.y() - a.y()) + a.x()) {
      inside = !inside;
    }
  }
  return inside;
}

}  // namespace

bool World::isFree(const Eigen::Vector2d& point) const
{
  for (const auto& solid : solids_) {
    if (insidePolygon(solid, point))
      return false;
  }
  if (outlines_.empty())
    return true;
  int count = 0;
  for (const auto& outline : outlines_) {
    count += insidePolygon(outline, point) ? 1 : 0;
  }
  return count % 2 == 1;
}

double World::castRay(const Eigen::Vector2d& origin, double angle_rad, double max_range_m) const
{
  return castRayHit(origin, angle_rad, max_range_m).range_m;
}

template <class Accept>
int World::nearestCrossing(const Eigen::Vector2d& origin, double ux, double uy, double& best,
                           Accept accept) const
{
  // Ray o + t u (t >= 0) against segment a + s d (0 <= s <= 1): solve with 2D cross products,
  // t = ((a - o) x d) / (u x d), s = ((a - o) x u) / (u x d).
  int hit = -1;
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
    if (t > 0.0 && t <= best && s >= 0.0 && s <= 1.0 && accept(i, t)) {
      best = t;
      hit = static_cast<int>(i);
    }
  }
  return hit;
}

RayHit World::castRayHit(const Eigen::Vector2d& origin, double angle_rad, double max_range_m) const
{
  const double ux = std::cos(angle_rad);
  const double uy = std::sin(angle_rad);
  double best = max_range_m;
  const int hit = nearestCrossing(origin, ux, uy, best, [](std::size_t, double) { return true; });
  RayHit result;
  if (hit >= 0) {
    const std::size_t i = static_cast<std::size_t>(hit);
    result.range_m = best;
    result.segment = hit;
    // |u x d| / |d| = |sin| of the angle between ray and wall = |cos| of the incidence angle.
    result.cos_incidence = std::abs(ux * dy_[i] - uy * dx_[i]) / std::hypot(dx_[i], dy_[i]);
  }
  return result;
}

double World::castRay3d(const Eigen::Vector2d& origin, double origin_z_m, double angle_rad,
                        double elevation_rad, double max_range_m) const
{
  // The same 2D intersection as castRayHit, t being the horizontal distance; the ray is at
  // height z(t) = origin_z + t tan(elevation) there, and hits the wall only below its top.
  const double slope = std::tan(elevation_rad);
  double best = max_range_m * std::cos(elevation_rad);
  bool hit = false;
  if (slope < 0.0 && origin_z_m / -slope <= best) {  // the floor
    best = origin_z_m / -slope;
    hit = true;
  }
  const int wall = nearestCrossing(origin, std::cos(angle_rad), std::sin(angle_rad), best,
                                   [&](std::size_t i, double t) {
                                     const double z = origin_z_m + t * slope;
                                     return z >= 0.0 && z <= height_[i];
                                   });
  hit = hit || wall >= 0;
  return hit ? best / std::cos(elevation_rad) : std::numeric_limits<double>::infinity();
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

/// Refuses a root that is not a map or has a key no world has.
void checkWorldKeys(const YAML::Node& root)
{
  if (!root.IsMap()) {
    throw std::runtime_error("expected a map with segments/polygons/boxes/circles");
  }
  for (const auto& key : root) {
    const std::string name = key.first.as<std::string>();
    if (name != "segments" && name != "polygons" && name != "boxes" && name != "circles" &&
        name != "description" && name != "wall_height_m") {
      throw std::runtime_error(
          "unknown key '" + name +
          "' (expected segments, polygons, boxes, circles, wall_height_m, description)");
    }
  }
}

/// An entry's own height [m], default wall_height_m.
double heightOf(const YAML::Node& node, double wall_height_m)
{
  if (!node["height"])
    return wall_height_m;
  const double height = node["height"].as<double>();
  if (!(height > 0.0))
    throw std::runtime_error("height must be a positive number of metres");
  return height;
}

/// segments: [x0, y0, x1, y1] each; `entry` names the one being read.
void addSegments(const YAML::Node& segments, double wall_height_m, std::string& entry, World& world)
{
  std::size_t index = 0;
  for (const YAML::Node& node : segments) {
    entry = "segments[" + std::to_string(index++) + "]";
    if (!node.IsSequence() || node.size() != 4) {
      throw std::runtime_error("expected [x0, y0, x1, y1]");
    }
    world.addSegment({Eigen::Vector2d(node[0].as<double>(), node[1].as<double>()),
                      Eigen::Vector2d(node[2].as<double>(), node[3].as<double>()), wall_height_m});
  }
}

/// polygons: closed outlines of at least 3 corners; `entry` names the one being read.
void addPolygons(const YAML::Node& polygons, double wall_height_m, std::string& entry, World& world)
{
  std::size_t index = 0;
  for (const YAML::Node& node : polygons) {
    entry = "polygons[" + std::to_string(index++) + "]";
    std::vector<Eigen::Vector2d> corners;
    for (const YAML::Node& corner : node) {
      corners.push_back(point2(corner, "corner"));
    }
    if (corners.size() < 3) {
      throw std::runtime_error("a polygon needs at least 3 corners");
    }
    world.addOutline(corners, wall_height_m);
  }
}

/// boxes: solid rectangles (center, size, yaw); `entry` names the one being read.
void addBoxes(const YAML::Node& boxes, double wall_height_m, std::string& entry, World& world)
{
  std::size_t index = 0;
  for (const YAML::Node& node : boxes) {
    entry = "boxes[" + std::to_string(index++) + "]";
    const Eigen::Vector2d center = point2(node["center"], "center");
    const Eigen::Vector2d size = point2(node["size"], "size");
    const double yaw = node["yaw"] ? node["yaw"].as<double>() : 0.0;
    if (!(size.x() > 0.0) || !(size.y() > 0.0)) {
      throw std::runtime_error("size must be positive");
    }
    const Eigen::Rotation2Dd rotation(yaw);
    std::vector<Eigen::Vector2d> corners;
    for (const auto& sign : {Eigen::Vector2d(-1, -1), Eigen::Vector2d(1, -1), Eigen::Vector2d(1, 1),
                             Eigen::Vector2d(-1, 1)}) {
      corners.push_back(center + rotation * (0.5 * size.cwiseProduct(sign)));
    }
    world.addSolid(corners, heightOf(node, wall_height_m));
  }
}

/// circles: solid regular polygons (center, radius, sides); `entry` names the one being read.
void addCircles(const YAML::Node& circles, double wall_height_m, std::string& entry, World& world)
{
  std::size_t index = 0;
  for (const YAML::Node& node : circles) {
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
    world.addSolid(corners, heightOf(node, wall_height_m));
  }
}

}  // namespace

World parseWorldYaml(const std::string& text, const std::string& source)
{
  World world;
  std::string entry = source;
  const YAML::Node root = loadYamlDocument(text, source);  // its messages name the source
  try {
    checkWorldKeys(root);
    double wall_height_m = std::numeric_limits<double>::infinity();
    if (root["wall_height_m"]) {
      entry = "wall_height_m";
      wall_height_m = root["wall_height_m"].as<double>();
      if (!(wall_height_m > 0.0))
        throw std::runtime_error("must be a positive number of metres");
    }
    addSegments(root["segments"], wall_height_m, entry, world);
    addPolygons(root["polygons"], wall_height_m, entry, world);
    addBoxes(root["boxes"], wall_height_m, entry, world);
    addCircles(root["circles"], wall_height_m, entry, world);
  } catch (const YAML::Exception& error) {
    throw std::runtime_error(source + ": " + entry + ": " + error.what());
  } catch (const std::runtime_error& error) {
    throw std::runtime_error(source + ": " + entry + ": " + error.what());
  }
  if (world.segments().empty()) {
    throw std::runtime_error(source + ": the world has no walls");
  }
  return world;
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
