#include <algorithm>
#include <cmath>
#include <vector>

#include <pcl/kdtree/kdtree_flann.h>
#include <pcl/point_cloud.h>
#include <pcl/point_types.h>

#include "odometry_calibration/scan/nearest_point_search.h"

namespace odometry_calibration {
namespace {

class KdTreeSearch final : public NearestPointSearch
{
public:
  KdTreeSearch(const ScanPoints& points, const ScanLines& lines) : NearestPointSearch(points, lines)
  {
    auto cloud = std::make_shared<pcl::PointCloud<pcl::PointXY>>();
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (lines.valid[i] != 0) {
        normals_.push_back(lines.normals[i]);
        fitted_.push_back(lines.fitted[i]);
        pcl::PointXY point;
        point.x = static_cast<float>(points.points_m[i].x());
        point.y = static_cast<float>(points.points_m[i].y());
        cloud->push_back(point);
        indices_.push_back(static_cast<int>(i));
        points_m_.push_back(points.points_m[i]);
      }
    }
    if (!cloud->empty()) {
      tree_.setInputCloud(cloud);
    }
  }

  NearestPoint find(const Eigen::Vector2d& query_m, const Eigen::Vector2d& query_normal,
                    double min_cosine, double max_distance_m, int /*hint*/,
                    double margin_m) const override
  {
    NearestPoint answer;
    if (indices_.empty()) {
      return answer;
    }
    pcl::PointXY query;
    query.x = static_cast<float>(query_m.x());
    query.y = static_cast<float>(query_m.y());
    // Scratch buffers per thread: the search is const and PCL resizes them.
    thread_local std::vector<int> found;
    thread_local std::vector<float> found_distance2;
    // Sorted by distance: the first compatible one is the answer. The radius is widened by
    // 0.1 mm, more than the float rounding of coordinates within 100 m, and the distances
    // re-checked in double: a point it misses lies beyond reach_m, which bounds the isolation.
    const double reach_m = max_distance_m + margin_m;
    const double radius_m = reach_m + 1e-4;
    answer.isolation_m = reach_m;
    if (tree_.radiusSearch(query, radius_m, found, found_distance2) <= 0) {
      return answer;
    }
    const double min_dot = min_cosine * query_normal.norm();
    for (const int k : found) {
      const double distance = (points_m_[k] - query_m).norm();
      if (answer.index < 0 && distance <= max_distance_m &&
          (fitted_[k] == 0 || normals_[k].dot(query_normal) >= min_dot)) {
        answer.index = indices_[k];
        answer.distance_m = distance;
      } else {
        answer.isolation_m = std::min(answer.isolation_m, distance);
      }
    }
    return answer;
  }

private:
  pcl::KdTreeFLANN<pcl::PointXY> tree_;
  std::vector<int> indices_;
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> normals_;
  // A segment's normal (not fitted) is too noisy to test against: it passes every test.
  std::vector<std::uint8_t> fitted_;
  std::vector<Eigen::Vector2d, Eigen::aligned_allocator<Eigen::Vector2d>> points_m_;
};

}  // namespace

std::unique_ptr<NearestPointSearch> makeKdTreeSearch(const ScanPoints& points,
                                                     const ScanLines& lines)
{
  return std::make_unique<KdTreeSearch>(points, lines);
}

}  // namespace odometry_calibration
