// A 2D world of line segments for the simulator, ray-cast exactly.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace odometry_calibration {
namespace sim {

/// A wall: the segment from a to b, in the world frame [m], standing on the floor (z = 0) up
/// to `height_m` (seen by the multi-beam lidar; the planar laser sees every wall).
struct Segment
{
  Eigen::Vector2d a;
  Eigen::Vector2d b;
  double height_m = std::numeric_limits<double>::infinity();
};

/// What a ray hits: its distance, the wall and the angle it meets the wall at.
struct RayHit
{
  double range_m = std::numeric_limits<double>::infinity();  ///< +infinity: nothing in range
  int segment = -1;            ///< index into World::segments(), -1 when nothing is hit
  double cos_incidence = 0.0;  ///< |cos| of the angle between the ray and the wall's normal
};

/// Walls, furniture and pillars as segments (circles are polygons of many sides).
class World
{
public:
  World() = default;
  explicit World(std::vector<Segment> segments);

  /// A single wall.
  void addSegment(const Segment& segment);

  /// Closed shapes: `outlines` enclose free space (rooms: the robot belongs inside an odd
  /// number of them, if there are any), `solids` are obstacles (the robot never belongs inside).
  /// Their edges are added to the segments.
  void addOutline(const std::vector<Eigen::Vector2d>& corners,
                  double height_m = std::numeric_limits<double>::infinity());
  void addSolid(const std::vector<Eigen::Vector2d>& corners,
                double height_m = std::numeric_limits<double>::infinity());

  /// Whether a point is in free space: inside no solid, and inside the outlines (odd count)
  /// when there are outlines.
  bool isFree(const Eigen::Vector2d& point) const;

  /// Distance [m] from `origin` along the unit direction of `angle_rad` (world frame) to the
  /// nearest segment, or +infinity if no segment is hit within `max_range_m`.
  double castRay(const Eigen::Vector2d& origin, double angle_rad, double max_range_m) const;

  /// The 3D ray from `origin` at `origin_z_m` above the floor, heading `angle_rad` (world
  /// frame) and rising `elevation_rad` above the horizontal: its length [m] to the first
  /// surface it meets, a wall's face (between the floor and the wall's height: a ray passes
  /// over lower walls) or the floor (z = 0), or +infinity if none within `max_range_m`.
  double castRay3d(const Eigen::Vector2d& origin, double origin_z_m, double angle_rad,
                   double elevation_rad, double max_range_m) const;
  /// castRay with which wall was hit and how obliquely (the laser model's mixed pixels and
  /// dark-surface dropouts). Same range as castRay.
  RayHit castRayHit(const Eigen::Vector2d& origin, double angle_rad, double max_range_m) const;

  /// Distance [m] from a point to the nearest segment (+infinity in an empty world).
  double clearance(const Eigen::Vector2d& point) const;

  const std::vector<Segment>& segments() const { return segments_; }

private:
  /// The nearest segment the ray origin + t (ux, uy), 0 < t <= best, crosses and `accept(i, t)`
  /// admits; `best` becomes its t. Returns its index, or -1 (best unchanged). Defined and used
  /// in world.cpp only.
  template <class Accept>
  int nearestCrossing(const Eigen::Vector2d& origin, double ux, double uy, double& best,
                      Accept accept) const;

  std::vector<Segment> segments_;
  std::vector<std::vector<Eigen::Vector2d>> outlines_;
  std::vector<std::vector<Eigen::Vector2d>> solids_;
  // Per segment: a and (b - a), stored flat for a tight ray-casting loop.
  std::vector<double> ax_, ay_, dx_, dy_, height_;
};

/// Loads a world from YAML. Keys (all optional, all in metres):
///   segments: [[x0, y0, x1, y1], ...]
///   polygons: [[[x, y], [x, y], ...], ...]        closed outlines
///   boxes:    [{center: [x, y], size: [w, h], yaw: rad}, ...]
///   circles:  [{center: [x, y], radius: r, sides: 24}, ...]
///   wall_height_m: h                             height of segments and polygons (default inf)
/// Boxes and circles take an optional `height` [m] (default: wall_height_m).
/// Throws std::runtime_error naming the file and the malformed entry.
World loadWorldYaml(const std::string& path);

/// Same, from YAML text; `source` names it in error messages.
World parseWorldYaml(const std::string& text, const std::string& source);

}  // namespace sim
}  // namespace odometry_calibration
