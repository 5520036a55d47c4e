#include "terrain/contact_map.h"

#include <algorithm>
#include <cmath>

namespace skidsim::terrain {
namespace {

// The covered part of a unit cell in "canonical" position (mirrored so that
// the covered corner, row, column or the free corner sits where the formulas
// below expect it), with its interfaces.
struct CoveredPart {
  double area = 0.0;
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  std::array<double, kFaceCount> s{}, w{};
};

// Crossing positions on the edges of a unit cell, each measured along +x
// (bottom, top edges) or +y (left, right edges) from the cell's lower-left
// corner.
struct EdgeCrossings {
  double bottom = 0.0, top = 0.0, left = 0.0, right = 0.0;
};

EdgeCrossings mirrored(EdgeCrossings e, bool mx, bool my) {
  if (mx) {
    std::swap(e.left, e.right);
    e.bottom = 1.0 - e.bottom;
    e.top = 1.0 - e.top;
  }
  if (my) {
    std::swap(e.bottom, e.top);
    e.left = 1.0 - e.left;
    e.right = 1.0 - e.right;
  }
  return e;
}

CoveredPart unmirrored(CoveredPart p, bool mx, bool my) {
  if (mx) {
    p.centroid.x() = 1.0 - p.centroid.x();
    std::swap(p.s[0], p.s[1]);
    std::swap(p.w[0], p.w[1]);
  }
  if (my) {
    p.centroid.y() = 1.0 - p.centroid.y();
    std::swap(p.s[2], p.s[3]);
    std::swap(p.w[2], p.w[3]);
  }
  return p;
}

// Only the lower-left corner inside: a rectangle with interfaces facing +x
// and +y.
CoveredPart one_corner(const EdgeCrossings& e) {
  CoveredPart p;
  const double x = e.bottom, y = e.left;
  p.area = x * y;
  p.centroid = {0.5 * x, 0.5 * y};
  p.s[0] = x;
  p.w[0] = y;
  p.s[2] = y;
  p.w[2] = x;
  return p;
}

// The bottom row inside: a strip with one interface facing +y.
CoveredPart bottom_row(const EdgeCrossings& e) {
  CoveredPart p;
  p.area = 0.5 * (e.left + e.right);
  p.centroid = {0.5, 0.5 * p.area};
  p.s[2] = p.area;
  p.w[2] = 1.0;
  return p;
}

// The left column inside: a strip with one interface facing +x.
CoveredPart left_column(const EdgeCrossings& e) {
  CoveredPart p;
  p.area = 0.5 * (e.bottom + e.top);
  p.centroid = {0.5 * p.area, 0.5};
  p.s[0] = p.area;
  p.w[0] = 1.0;
  return p;
}

// All but the upper-right corner inside: the cell minus a free rectangle,
// two interfaces around the free corner.
CoveredPart all_but_one(const EdgeCrossings& e) {
  CoveredPart p;
  const double fx = 1.0 - e.top, fy = 1.0 - e.right;
  const double free_area = fx * fy;
  p.area = 1.0 - free_area;
  p.centroid = (Eigen::Vector2d(0.5, 0.5) - free_area * Eigen::Vector2d(1.0 - 0.5 * fx, 1.0 - 0.5 * fy)) /
               std::max(p.area, 1e-12);
  p.s[0] = 1.0 - fx;
  p.w[0] = fy;
  p.s[2] = 1.0 - fy;
  p.w[2] = fx;
  return p;
}

// Corner bits: 1 lower-left, 2 lower-right, 4 upper-left, 8 upper-right.
CoveredPart covered_part(int mask, const EdgeCrossings& e) {
  switch (mask) {
    case 15: return {1.0, {0.5, 0.5}, {}, {}};
    case 1: case 2: case 4: case 8: {
      const int k = mask == 1 ? 0 : mask == 2 ? 1 : mask == 4 ? 2 : 3;
      const bool mx = k & 1, my = k & 2;
      return unmirrored(one_corner(mirrored(e, mx, my)), mx, my);
    }
    case 3: return bottom_row(e);
    case 12: return unmirrored(bottom_row(mirrored(e, false, true)), false, true);
    case 5: return left_column(e);
    case 10: return unmirrored(left_column(mirrored(e, true, false)), true, false);
    case 7: case 11: case 13: case 14: {
      const int free_bits = 15 & ~mask;
      const int k = free_bits == 1 ? 0 : free_bits == 2 ? 1 : free_bits == 4 ? 2 : 3;
      const bool mx = !(k & 1), my = !(k & 2);
      return unmirrored(all_but_one(mirrored(e, mx, my)), mx, my);
    }
    default: {
      // Two opposite corners (a saddle the axis-aligned picture cannot
      // hold): the two corner rectangles, without interfaces.
      const CoveredPart a = covered_part(mask == 9 ? 1 : 2, e), b = covered_part(mask == 9 ? 8 : 4, e);
      CoveredPart p;
      p.area = std::min(1.0, a.area + b.area);
      p.centroid = (a.area * a.centroid + b.area * b.centroid) / std::max(a.area + b.area, 1e-12);
      return p;
    }
  }
}

}  // namespace

double ContactMapper::crossing(const BodyGeometry& body, const Corner& a, const Corner& b, const Eigen::Vector2d& pa,
                               const Eigen::Vector2d& pb, std::int64_t* tests) const {
  const double top = std::max(a.top_m, b.top_m), bottom = std::min(a.bottom_m, b.bottom_m);
  double inside = 0.0, outside = 1.0;
  VerticalHit hit;
  for (int it = 0; it < bisection_steps_; ++it) {
    const double mid = 0.5 * (inside + outside);
    const Eigen::Vector2d p = pa + mid * (pb - pa);
    ++*tests;
    (body.lowest_hit(p.x(), p.y(), bottom, top, &hit) ? inside : outside) = mid;
  }
  return 0.5 * (inside + outside);
}

void ContactMapper::build(const GranularGrid& grid, const BodyGeometry& body, const BodyMotion& motion,
                          ContactMap* map) {
  map->clear();
  const double d = grid.cell_size_m();
  const Eigen::Vector2d origin = grid.spec().origin_m;
  // Bisect each border edge to about a millimetre or 1/32 of a cell.
  bisection_steps_ = std::clamp(static_cast<int>(std::ceil(std::log2(d / std::min(1e-3, d / 32.0)))), 5, 12);

  // Cells under the body's bounds (5.1): cell (i, j) spans
  // origin + d (i - 1/2 .. i + 1/2).
  const Eigen::AlignedBox3d bounds = body.world_bounds();
  if (bounds.isEmpty() || !bounds.min().allFinite() || !bounds.max().allFinite()) return;
  // Clamped in double before the conversion: a body far off the grid must
  // not overflow an int.
  const auto cell_index = [&](double coordinate, double grid_origin, int n) {
    return static_cast<int>(std::clamp(std::floor((coordinate - grid_origin) / d + 0.5), -1.0, static_cast<double>(n)));
  };
  const int i0 = std::max(0, cell_index(bounds.min().x(), origin.x(), grid.nx()));
  const int j0 = std::max(0, cell_index(bounds.min().y(), origin.y(), grid.ny()));
  const int i1 = std::min(grid.nx() - 1, cell_index(bounds.max().x(), origin.x(), grid.nx()));
  const int j1 = std::min(grid.ny() - 1, cell_index(bounds.max().y(), origin.y(), grid.ny()));
  if (i0 > i1 || j0 > j1) return;
  const int ci_n = i1 - i0 + 2, cj_n = j1 - j0 + 2;  // corners
  corners_.resize(static_cast<std::size_t>(ci_n) * cj_n);
  const auto corner_at = [&](int ci, int cj) -> Corner& { return corners_[static_cast<std::size_t>(cj) * ci_n + ci]; };
  const auto corner_xy = [&](int ci, int cj) {
    return Eigen::Vector2d(origin.x() + d * (i0 + ci - 0.5), origin.y() + d * (j0 + cj - 0.5));
  };

  // Vertical segments at the corners, from below the hard base (so that a
  // body pushed into the base is still seen) up to the highest of the four
  // cells around the corner (fig. 5.3).
  constexpr double kBelowBaseM = 1.0;
  for (int cj = 0; cj < cj_n; ++cj) {
    for (int ci = 0; ci < ci_n; ++ci) {
      Corner& c = corner_at(ci, cj);
      double top = -1e300, bottom = 1e300;
      const int ia = std::max(i0 + ci - 1, 0), ib = std::min(i0 + ci, grid.nx() - 1);
      const int ja = std::max(j0 + cj - 1, 0), jb = std::min(j0 + cj, grid.ny() - 1);
      for (int j = ja; j <= jb; ++j) {
        for (int i = ia; i <= ib; ++i) {
          const int cell = grid.index(i, j);
          top = std::max(top, grid.surface_at(cell));
          bottom = std::min(bottom, static_cast<double>(grid.base_at(cell)));
        }
      }
      c.top_m = top;
      c.bottom_m = bottom - kBelowBaseM;
      c.inside = false;
      if (bounds.min().z() > top) continue;  // the body is above this corner's cells
      const Eigen::Vector2d p = corner_xy(ci, cj);
      ++map->segment_tests;
      c.inside = body.lowest_hit(p.x(), p.y(), c.bottom_m, c.top_m, &c.hit);
    }
  }

  // Where the outline crosses the cell edges: only edges with one corner in.
  x_edge_t_.assign(static_cast<std::size_t>(ci_n - 1) * cj_n, 0.0);
  y_edge_t_.assign(static_cast<std::size_t>(ci_n) * (cj_n - 1), 0.0);
  for (int cj = 0; cj < cj_n; ++cj) {
    for (int ci = 0; ci < ci_n; ++ci) {
      const Corner& c = corner_at(ci, cj);
      const auto edge = [&](int ci2, int cj2, double* t) {
        const Corner& o = corner_at(ci2, cj2);
        if (c.inside == o.inside) {
          *t = c.inside ? 1.0 : 0.0;
          return;
        }
        const Eigen::Vector2d pa = corner_xy(ci, cj), pb = corner_xy(ci2, cj2);
        *t = c.inside ? crossing(body, c, o, pa, pb, &map->segment_tests)
                      : 1.0 - crossing(body, o, c, pb, pa, &map->segment_tests);
        const Eigen::Vector2d p = pa + *t * (pb - pa);
        map->footprint.extend(p);
      };
      if (ci + 1 < ci_n) edge(ci + 1, cj, &x_edge_t_[static_cast<std::size_t>(cj) * (ci_n - 1) + ci]);
      if (cj + 1 < cj_n) edge(ci, cj + 1, &y_edge_t_[static_cast<std::size_t>(cj) * ci_n + ci]);
      if (c.inside) map->footprint.extend(corner_xy(ci, cj));
    }
  }

  // Moments of the covered area, for Bekker's b (below).
  double area = 0.0, sx = 0.0, sy = 0.0, sxx = 0.0, syy = 0.0, sxy = 0.0, own = 0.0;
  for (int j = j0; j <= j1; ++j) {
    for (int i = i0; i <= i1; ++i) {
      const int ci = i - i0, cj = j - j0;
      const Corner* k[4] = {&corner_at(ci, cj), &corner_at(ci + 1, cj), &corner_at(ci, cj + 1),
                            &corner_at(ci + 1, cj + 1)};
      const int mask = (k[0]->inside ? 1 : 0) | (k[1]->inside ? 2 : 0) | (k[2]->inside ? 4 : 0) |
                       (k[3]->inside ? 8 : 0);
      if (mask == 0) continue;
      // The body's underside over the cell: the mean of the corner hits
      // (5.2.2: faces taken as flat over a cell).
      double bottom = 0.0;
      Eigen::Vector3d normal = Eigen::Vector3d::Zero();
      int count = 0;
      for (const Corner* c : k) {
        if (!c->inside) continue;
        bottom += c->hit.z_m;
        normal += c->hit.normal;
        ++count;
      }
      bottom /= count;
      const int cell = grid.index(i, j);
      const double depth = grid.surface_at(cell) - bottom;
      if (!(depth > 0.0)) continue;
      EdgeCrossings e;
      e.bottom = x_edge_t_[static_cast<std::size_t>(cj) * (ci_n - 1) + ci];
      e.top = x_edge_t_[static_cast<std::size_t>(cj + 1) * (ci_n - 1) + ci];
      e.left = y_edge_t_[static_cast<std::size_t>(cj) * ci_n + ci];
      e.right = y_edge_t_[static_cast<std::size_t>(cj) * ci_n + ci + 1];
      const CoveredPart part = covered_part(mask, e);
      if (!(part.area > 0.0)) continue;
      CellContact& out = map->cells.emplace_back();
      out.cell = static_cast<std::uint32_t>(cell);
      out.i = i;
      out.j = j;
      out.covered_fraction = std::min(part.area, 1.0);
      out.bottom_z_m = bottom;
      out.depth_m = depth;
      out.covered_level_m = grid.surface_at(cell);
      const Eigen::Vector2d corner00 = corner_xy(ci, cj);
      out.point_m = {corner00.x() + d * part.centroid.x(), corner00.y() + d * part.centroid.y(), bottom};
      out.normal = normal.norm() > 0.0 ? Eigen::Vector3d(normal.normalized()) : Eigen::Vector3d(-Eigen::Vector3d::UnitZ());
      out.velocity_m_s = motion.velocity_at(out.point_m);
      for (int f = 0; f < kFaceCount; ++f) {
        out.interface_s_m[f] = d * part.s[f];
        out.interface_w_m[f] = d * part.w[f];
      }
      const double a = out.covered_fraction * d * d;
      area += a;
      sx += a * out.point_m.x();
      sy += a * out.point_m.y();
      sxx += a * out.point_m.x() * out.point_m.x();
      syy += a * out.point_m.y() * out.point_m.y();
      sxy += a * out.point_m.x() * out.point_m.y();
      own += a * out.covered_fraction * d * d / 12.0;  // the cell's own spread about its centroid
    }
  }
  if (area > 0.0) {
    // Bekker's b, the smaller side of the footprint, whatever way the body
    // is turned: a rectangle b wide has the smaller principal second moment
    // A b^2 / 12 (the thesis's bounding box along the grid's axes would
    // make b, and the pressure, change with the body's yaw).
    const double mx = sx / area, my = sy / area;
    const double cxx = sxx / area - mx * mx + own / area, cyy = syy / area - my * my + own / area;
    const double cxy = sxy / area - mx * my;
    const double smaller = 0.5 * (cxx + cyy - std::sqrt((cxx - cyy) * (cxx - cyy) + 4.0 * cxy * cxy));
    map->footprint_b_m = std::sqrt(12.0 * std::max(smaller, 0.0));
  }
}

}  // namespace skidsim::terrain
