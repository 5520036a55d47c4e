// Contact maps (thesis 5.2): covered areas, depths and vertical interfaces
// from vertical segment tests against real shapes, at several cell sizes.
#include <gtest/gtest.h>

#include <cmath>

#include "common/physical_constants.h"
#include "terrain/body_shapes.h"
#include "terrain/contact_map.h"
#include "tests/soil_contact_support.h"

namespace skidsim::terrain {
namespace {

double covered_area(const ContactMap& map, double cell_size_m) {
  double area = 0.0;
  for (const CellContact& c : map.cells) area += c.covered_fraction * cell_size_m * cell_size_m;
  return area;
}

TEST(ContactMap, BoxFootprintAreaDepthAndInterfacesAtEveryCellSize) {
  for (double cells_per_m : {5.0, 10.0, 20.0, 30.0, 50.0}) {
    SCOPED_TRACE(cells_per_m);
    const GranularGrid g = testing::flat_site(cells_per_m, 2.0, 0.4);
    OrientedBox box;
    box.half_extents_m = {0.5, 0.4, 0.2};
    box.centre_m = {0.9137, 1.0071, 0.4 - 0.03 + 0.2};  // 3 cm into the soil, edges off the cell edges
    ContactMapper mapper;
    ContactMap map;
    mapper.build(g, box, BodyMotion{}, &map);
    const double d = 1.0 / cells_per_m;
    EXPECT_NEAR(covered_area(map, d), 0.8, 0.8 * 0.005);
    EXPECT_NEAR(map.footprint_b_m, 0.8, 0.005);
    double width_px = 0.0, width_py = 0.0;
    for (const CellContact& c : map.cells) {
      EXPECT_NEAR(c.depth_m, 0.03, 1e-9);
      EXPECT_NEAR(c.normal.z(), -1.0, 1e-12);
      width_px += c.interface_w_m[0];
      width_py += c.interface_w_m[2];
    }
    // The +x border runs the box's whole width (0.8 m), the +y border its
    // length (1 m).
    EXPECT_NEAR(width_px, 0.8, 0.005);
    EXPECT_NEAR(width_py, 1.0, 0.005);
  }
}

TEST(ContactMap, RotatedBoxAndSphereFootprintsConvergeWithCellSize) {
  double previous_error = 1.0;
  for (double cells_per_m : {5.0, 10.0, 20.0, 50.0}) {
    const GranularGrid g = testing::flat_site(cells_per_m, 2.0, 0.4);
    const double d = 1.0 / cells_per_m;
    OrientedBox box;
    box.half_extents_m = {0.5, 0.5, 0.2};
    box.orientation = Eigen::AngleAxisd(kPi / 6.0, Eigen::Vector3d::UnitZ());
    box.centre_m = {1.0, 1.0, 0.4 - 0.05 + 0.2};
    Sphere ball;
    ball.radius_m = 0.5;
    ball.centre_m = {1.0, 1.0, 0.4 - 0.1 + 0.5};  // footprint radius 0.3 m
    ContactMapper mapper;
    ContactMap box_map, ball_map;
    mapper.build(g, box, BodyMotion{}, &box_map);
    mapper.build(g, ball, BodyMotion{}, &ball_map);
    const double box_error = std::abs(covered_area(box_map, d) - 1.0);
    const double ball_error = std::abs(covered_area(ball_map, d) - kPi * 0.09) / (kPi * 0.09);
    SCOPED_TRACE(::testing::Message() << cells_per_m << " cells/m: box area error " << box_error
                                      << ", ball area error " << ball_error);
    // Border cells are taken as axis-aligned rectangles (fig. 5.6): the
    // error is of the order of a cell's share of the border.
    EXPECT_LT(box_error, 0.5 * d);
    EXPECT_LT(ball_error, 1.0 * d);
    EXPECT_LT(box_error, previous_error);
    previous_error = box_error;
    // The sphere's deepest cell is 10 cm in, and its normals point down and out.
    double deepest = 0.0;
    for (const CellContact& c : ball_map.cells) {
      deepest = std::max(deepest, c.depth_m);
      EXPECT_LT(c.normal.z(), 0.0);
    }
    // Depths are the mean of a cell's corner hits (5.2.2): on a curved
    // underside that is shallower than the lowest point by about d^2 / 4r.
    EXPECT_NEAR(deepest, 0.1, 1.1 * d * d / (4.0 * ball.radius_m));
  }
}

// Bekker's b is the footprint's smaller side however the body is turned.
TEST(ContactMap, BekkerWidthDoesNotDependOnTheBodysYaw) {
  const GranularGrid g = testing::flat_site(20.0, 3.0, 0.4);
  for (double yaw_deg : {0.0, 30.0, 45.0, 90.0}) {
    OrientedBox plate;
    plate.half_extents_m = {1.0, 0.1, 0.1};
    plate.orientation = Eigen::AngleAxisd(yaw_deg * kPi / 180.0, Eigen::Vector3d::UnitZ());
    plate.centre_m = {1.5137, 1.4871, 0.4 - 0.03 + 0.1};
    ContactMapper mapper;
    ContactMap map;
    mapper.build(g, plate, BodyMotion{}, &map);
    EXPECT_NEAR(map.footprint_b_m, 0.2, 0.01) << "yaw " << yaw_deg << " deg";
  }
}

// A wheel pressed 4 cm into the soil, axle turned 30 degrees: the footprint
// is its width times the chord 2 sqrt(2 R d - d^2); the deepest cell is 4 cm.
TEST(ContactMap, WheelFootprintIsWidthTimesChord) {
  const GranularGrid g = testing::flat_site(40.0, 2.0, 0.4);
  Cylinder wheel;
  wheel.radius_m = 0.3;
  wheel.half_width_m = 0.15;
  wheel.orientation = Eigen::AngleAxisd(kPi / 6.0, Eigen::Vector3d::UnitZ());
  wheel.centre_m = {1.0137, 0.9871, 0.4 - 0.04 + 0.3};
  ContactMapper mapper;
  ContactMap map;
  mapper.build(g, wheel, BodyMotion{}, &map);
  const double chord = 2.0 * std::sqrt(2.0 * 0.3 * 0.04 - 0.04 * 0.04);
  EXPECT_NEAR(covered_area(map, 1.0 / 40.0), 0.3 * chord, 0.05 * 0.3 * chord);
  double deepest = 0.0;
  for (const CellContact& c : map.cells) deepest = std::max(deepest, c.depth_m);
  EXPECT_NEAR(deepest, 0.04, 0.002);
  EXPECT_NEAR(map.footprint_b_m, std::min(0.3, chord), 0.03);
}

TEST(ContactMap, TriangleMeshGivesTheSameMapAsTheAnalyticBox) {
  const GranularGrid g = testing::flat_site(20.0, 2.0, 0.4);
  OrientedBox box;
  box.half_extents_m = {0.45, 0.3, 0.2};
  box.orientation = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX());
  box.centre_m = {1.03, 0.97, 0.4 - 0.04 + 0.2};
  TriangleMesh mesh = TriangleMesh::box(box.half_extents_m);
  mesh.pose = Eigen::Translation3d(box.centre_m) * box.orientation;
  mesh.update();
  ContactMapper mapper;
  ContactMap a, b;
  BodyMotion spin;
  spin.reference_point_m = box.centre_m;
  spin.angular_velocity_rad_s = {0.0, 0.0, 1.0};
  mapper.build(g, box, spin, &a);
  mapper.build(g, mesh, spin, &b);
  ASSERT_EQ(a.cells.size(), b.cells.size());
  ASSERT_GT(a.cells.size(), 100u);
  for (std::size_t k = 0; k < a.cells.size(); ++k) {
    EXPECT_EQ(a.cells[k].cell, b.cells[k].cell);
    EXPECT_NEAR(a.cells[k].covered_fraction, b.cells[k].covered_fraction, 1e-9);
    EXPECT_NEAR(a.cells[k].bottom_z_m, b.cells[k].bottom_z_m, 1e-9);
    EXPECT_NEAR((a.cells[k].normal - b.cells[k].normal).norm(), 0.0, 1e-9);
    // The body's velocity at the contact point: omega x r.
    const Eigen::Vector3d expected = spin.angular_velocity_rad_s.cross(a.cells[k].point_m - box.centre_m);
    EXPECT_NEAR((a.cells[k].velocity_m_s - expected).norm(), 0.0, 1e-12);
  }
}

TEST(ContactMap, ABodyAboveTheSoilOrOffTheGridTouchesNothing) {
  const GranularGrid g = testing::flat_site(10.0, 2.0, 0.4);
  ContactMapper mapper;
  ContactMap map;
  Sphere ball;
  ball.radius_m = 0.3;
  ball.centre_m = {1.0, 1.0, 0.4 + 0.3 + 1e-6};
  mapper.build(g, ball, BodyMotion{}, &map);
  EXPECT_TRUE(map.cells.empty());
  ball.centre_m = {-5.0, 1.0, 0.0};
  mapper.build(g, ball, BodyMotion{}, &map);
  EXPECT_TRUE(map.cells.empty());
  EXPECT_EQ(map.segment_tests, 0);
}

}  // namespace
}  // namespace skidsim::terrain

namespace skidsim::terrain {
namespace {

// A wheel's bounds clipped at a height hold every point of the wheel below
// that height, and are much smaller than the whole wheel's when it is sunk
// only a little.
TEST(CylinderBounds, ClippedBoundsHoldThePartBelowTheClip) {
  for (double roll : {0.0, 0.2}) {
    for (double yaw : {0.0, 0.7}) {
      Cylinder wheel;
      wheel.centre_m = {1.0, 2.0, 0.45};
      wheel.radius_m = 0.41;
      wheel.half_width_m = 0.13;
      wheel.orientation = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(roll, Eigen::Vector3d::UnitX());
      const Eigen::AlignedBox3d full = wheel.world_bounds();
      wheel.clip_above_m = 0.10;
      const Eigen::AlignedBox3d clipped = wheel.world_bounds();
      EXPECT_LT(clipped.volume(), 0.5 * full.volume());
      const Eigen::Matrix3d r = wheel.orientation.toRotationMatrix();
      for (double a = 0.0; a < 6.2832; a += 0.01)
        for (double rr : {0.2, 0.41})
          for (double w : {-0.13, 0.0, 0.13}) {
            const Eigen::Vector3d p = wheel.centre_m + r * Eigen::Vector3d(rr * std::cos(a), w, rr * std::sin(a));
            if (p.z() <= wheel.clip_above_m) {
              EXPECT_TRUE(clipped.contains(p)) << p.transpose();
            }
          }
    }
  }
}

}  // namespace
}  // namespace skidsim::terrain
