#include <cmath>

#include <gtest/gtest.h>

#include "odometry_calibration/sim/world.h"

namespace odometry_calibration {
namespace sim {
namespace {

World squareRoom()
{
  return parseWorldYaml("polygons:\n  - [[-2, -1], [3, -1], [3, 4], [-2, 4]]\n", "room");
}

TEST(SimWorld, RayCastHitsTheRightWallAtTheRightDistance)
{
  const World room = squareRoom();
  const Eigen::Vector2d origin(0.5, 0.25);
  EXPECT_NEAR(room.castRay(origin, 0.0, 20.0), 2.5, 1e-12);         // east wall x = 3
  EXPECT_NEAR(room.castRay(origin, M_PI / 2, 20.0), 3.75, 1e-12);   // north wall y = 4
  EXPECT_NEAR(room.castRay(origin, M_PI, 20.0), 2.5, 1e-12);        // west wall x = -2
  EXPECT_NEAR(room.castRay(origin, -M_PI / 2, 20.0), 1.25, 1e-12);  // south wall y = -1
  // Towards the corner (3, 4): along the diagonal direction.
  const double angle = std::atan2(3.75, 2.5);
  EXPECT_NEAR(room.castRay(origin, angle, 20.0), std::hypot(2.5, 3.75), 1e-9);
  // 30 degrees up: hits x = 3 at height 0.25 + 2.5 tan 30.
  EXPECT_NEAR(room.castRay(origin, M_PI / 6, 20.0), 2.5 / std::cos(M_PI / 6), 1e-12);
}

TEST(SimWorld, ThreeDimensionalRaysPassOverLowWallsAndHitTheFloor)
{
  // A 2.5 m room (x = 3 is the east wall, 2.5 m from the origin) with a 0.75 m desk whose west
  // face is at x = 1.5 (1 m away); the lidar is 0.5 m above the floor.
  const World world = parseWorldYaml(
      "wall_height_m: 2.5\n"
      "polygons:\n  - [[-2, -1], [3, -1], [3, 4], [-2, 4]]\n"
      "boxes:\n  - {center: [2.0, 0.25], size: [1.0, 0.5], height: 0.75}\n",
      "room");
  const Eigen::Vector2d origin(0.5, 0.25);
  // Level: the desk's face at 1 m.
  EXPECT_NEAR(world.castRay3d(origin, 0.5, 0.0, 0.0, 20.0), 1.0, 1e-12);
  // Rising 20 deg: at 1 m the ray is 0.86 m high, over the desk, and meets the wall at 2.5 m.
  const double up = 20.0 * M_PI / 180.0;
  EXPECT_NEAR(world.castRay3d(origin, 0.5, 0.0, up, 20.0), 2.5 / std::cos(up), 1e-12);
  // Falling 15 deg towards the north wall (3.75 m away): the floor comes first, 1.87 m out.
  const double down = -15.0 * M_PI / 180.0;
  EXPECT_NEAR(world.castRay3d(origin, 0.5, M_PI / 2, down, 20.0), 0.5 / std::sin(-down), 1e-12);
  // Rising 45 deg: 2.5 m high 2 m out, before any wall: nothing.
  EXPECT_TRUE(std::isinf(world.castRay3d(origin, 0.5, M_PI / 2, M_PI / 4, 20.0)));
  // The planar cast ignores heights: the desk.
  EXPECT_NEAR(world.castRay(origin, 0.0, 20.0), 1.0, 1e-12);
}

TEST(SimWorld, NothingWithinRangeIsInfinity)
{
  const World room = squareRoom();
  EXPECT_TRUE(std::isinf(room.castRay(Eigen::Vector2d(0.5, 0.25), 0.0, 2.0)));
  const World wall = parseWorldYaml("segments: [[5, -1, 5, 1]]\n", "wall");
  EXPECT_TRUE(std::isinf(wall.castRay(Eigen::Vector2d(0, 0), M_PI, 100.0)));  // looking away
  EXPECT_TRUE(std::isinf(wall.castRay(Eigen::Vector2d(0, 0), 0.5, 100.0)));   // passes above
  EXPECT_NEAR(wall.castRay(Eigen::Vector2d(0, 0), 0.0, 100.0), 5.0, 1e-12);
}

TEST(SimWorld, ShapesBecomeSegments)
{
  const World world = parseWorldYaml(
      "boxes: [{center: [1, 2], size: [2, 1], yaw: 0.5}]\n"
      "circles: [{center: [-3, 0], radius: 0.5, sides: 12}]\n",
      "shapes");
  EXPECT_EQ(world.segments().size(), 4u + 12u);
  // A ray from the circle's centre hits the inscribed polygon: between r cos(pi/12) and r.
  const double range = world.castRay(Eigen::Vector2d(-3, 0), 0.1, 10.0);
  EXPECT_GE(range, 0.5 * std::cos(M_PI / 12) - 1e-12);
  EXPECT_LE(range, 0.5 + 1e-12);
  // The box's centre is 0.5 from its long sides (height 1).
  EXPECT_NEAR(world.clearance(Eigen::Vector2d(1, 2)), 0.5, 1e-12);
}

TEST(SimWorld, ClearanceIsTheDistanceToTheNearestWall)
{
  EXPECT_NEAR(squareRoom().clearance(Eigen::Vector2d(0.5, 0.25)), 1.25, 1e-12);
  EXPECT_NEAR(squareRoom().clearance(Eigen::Vector2d(4.0, 5.0)), std::hypot(1.0, 1.0), 1e-12);
}

TEST(SimWorld, FreeSpaceIsInsideTheRoomAndOutsideTheFurniture)
{
  const World world = parseWorldYaml(
      "polygons: [[[-5, -4], [5, -4], [5, 4], [-5, 4]]]\n"
      "boxes: [{center: [2, 2], size: [1, 1]}]\n"
      "circles: [{center: [-2, -2], radius: 0.5}]\n",
      "room");
  EXPECT_TRUE(world.isFree(Eigen::Vector2d(0, 0)));
  EXPECT_FALSE(world.isFree(Eigen::Vector2d(2.1, 1.9)));    // in the box
  EXPECT_FALSE(world.isFree(Eigen::Vector2d(-2.1, -1.9)));  // in the round table
  EXPECT_FALSE(world.isFree(Eigen::Vector2d(20, 0)));       // outside the building
  // Worlds of loose segments only (the corridor) have no inside or outside.
  EXPECT_TRUE(parseWorldYaml("segments: [[0, 0, 1, 0]]\n", "w").isFree(Eigen::Vector2d(5, 5)));
}

TEST(SimWorld, BadYamlNamesTheEntry)
{
  auto message = [](const std::string& text) -> std::string {
    try {
      parseWorldYaml(text, "w.yaml");
    } catch (const std::runtime_error& error) {
      return error.what();
    }
    return "";
  };
  EXPECT_NE(message("segments: [[0, 0, 1]]\n").find("segments[0]"), std::string::npos);
  EXPECT_NE(message("boxes: [{center: [0, 0], size: [0, 1]}]\n").find("boxes[0]"),
            std::string::npos);
  EXPECT_NE(message("walls: []\n").find("unknown key 'walls'"), std::string::npos);
  EXPECT_NE(message("description: empty\n").find("no walls"), std::string::npos);
  EXPECT_THROW(loadWorldYaml("/nonexistent/world.yaml"), std::runtime_error);
}

}  // namespace
}  // namespace sim
}  // namespace odometry_calibration
