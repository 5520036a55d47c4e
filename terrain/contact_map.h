// Contact maps (thesis 5.2): which cells a body presses into, how deep, and
// where its border cuts the cells. Built from vertical segment tests at the
// cell corners against the body's real shape (BodyGeometry); the part of a
// cell the body covers is taken as an axis-aligned rectangle through the
// points where the body's outline crosses the cell edges (5.2.2, fig. 5.6),
// found by bisection along those edges.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <array>
#include <cstdint>
#include <vector>

#include "terrain/body_geometry.h"
#include "terrain/granular_grid.h"

namespace skidsim::terrain {

// Directions of vertical interfaces, the side of the cell that is free:
// +x, -x, +y, -y (the neighbour order of the automaton).
inline constexpr int kFaceCount = 4;
// Each face's outward step in cells, in that order.
inline constexpr int kFaceStep[kFaceCount][2] = {{1, 0}, {-1, 0}, {0, 1}, {0, -1}};
// A face lies ahead of a motion when its outward direction is within about
// 73 deg of it (cosine over 0.3): the faces a cutting edge or a blade meets.
inline constexpr double kFaceAheadCosine = 0.3;
// `dir_norm` is |dir| (1 for a unit direction: the comparison stays exact).
inline bool face_ahead(int face, double dir_x, double dir_y, double dir_norm) {
  return kFaceStep[face][0] * dir_x + kFaceStep[face][1] * dir_y > kFaceAheadCosine * dir_norm;
}

struct CellContact {
  // The mapper sets every field; the empty constructor saves zeroing each
  // record first (measurably: a fifth of the map's cost).
  CellContact() noexcept {}
  std::uint32_t cell = 0;
  int i = 0, j = 0;               // the cell's column and row
  double covered_fraction = 0.0;  // of the cell's area, in (0, 1]
  double bottom_z_m = 0.0;        // the body's underside over the covered part
  double depth_m = 0.0;           // d0: the cell's surface minus bottom_z (> 0)
  // Level of the soil under the covered part (h1 of 5.2.2); the free part
  // holds the rest of the cell's material. Kept across steps by
  // SoilContactModel; the mapper sets it to the cell's surface.
  double covered_level_m = 0.0;
  Eigen::Vector3d point_m = Eigen::Vector3d::Zero();       // centroid of the covered part, at bottom_z
  Eigen::Vector3d normal = -Eigen::Vector3d::UnitZ();      // the body's outward face normal
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();  // the body's velocity at point_m
  // Vertical interfaces (5.2.3), per free side (+x, -x, +y, -y): s, the
  // covered length measured from the cell edge behind the interface, and w,
  // its width; w = 0 where the cell has no interface on that side.
  std::array<double, kFaceCount> interface_s_m{};
  std::array<double, kFaceCount> interface_w_m{};
};

struct ContactMap {
  std::vector<CellContact> cells;  // in increasing cell index
  Eigen::AlignedBox2d footprint;   // bounds of the covered area (world x, y)
  // Bekker's b (5.4.1), the footprint's smaller side: that of the rectangle
  // with the footprint's principal second moments (turning the body does not
  // change it).
  double footprint_b_m = 0.0;
  std::int64_t segment_tests = 0;  // BodyGeometry queries made
  void clear() {
    cells.clear();
    footprint.setEmpty();
    footprint_b_m = 0.0;
    segment_tests = 0;
  }
};

// Builds contact maps. Keeps its scratch (sized by the body's footprint on
// the grid, not by the grid) between calls, so a body that keeps touching
// the terrain costs no allocation.
class ContactMapper {
 public:
  void build(const GranularGrid& grid, const BodyGeometry& body, const BodyMotion& motion, ContactMap* map);
  // Sizes the scratch for footprints of up to `corners` cell corners, so
  // that building maps that large never allocates.
  void reserve(std::size_t corners) {
    corners_.reserve(corners);
    x_edge_t_.reserve(corners);
    y_edge_t_.reserve(corners);
  }

 private:
  struct Corner {
    bool inside = false;
    double top_m = 0.0, bottom_m = 0.0;
    VerticalHit hit;
  };
  // Fraction along the edge from corner a (inside) to corner b (outside)
  // where the body's outline crosses it.
  double crossing(const BodyGeometry& body, const Corner& a, const Corner& b, const Eigen::Vector2d& pa,
                  const Eigen::Vector2d& pb, std::int64_t* tests) const;

  std::vector<Corner> corners_;
  std::vector<double> x_edge_t_, y_edge_t_;  // crossing positions along +x / +y, in [0, 1]
  int bisection_steps_ = 6;
};

}  // namespace skidsim::terrain
