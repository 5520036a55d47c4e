#include "render/terrain_mesh.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace skidsim::render {
namespace {

float height(const HeightField& f, int i, int j) {
  i = std::clamp(i, 0, f.nx - 1);
  j = std::clamp(j, 0, f.ny - 1);
  return f.height_m[static_cast<std::size_t>(j) * f.nx + i];
}

bool shows(const HeightField& f, int i, int j) {
  return f.shows.empty() || f.shows[static_cast<std::size_t>(j) * f.nx + i] != 0;
}

void set_vertex(const HeightField& f, int i, int j, Mesh& m) {
  const std::size_t v = static_cast<std::size_t>(j) * f.nx + i;
  const auto d = static_cast<float>(f.cell_m);
  m.positions_m[v] = Eigen::Vector3f(d * i, d * j, height(f, i, j));
  // Central differences (one-sided at the edges).
  const float dx = (height(f, i + 1, j) - height(f, i - 1, j)) / (d * static_cast<float>(std::min(i + 1, f.nx - 1) - std::max(i - 1, 0)));
  const float dy = (height(f, i, j + 1) - height(f, i, j - 1)) / (d * static_cast<float>(std::min(j + 1, f.ny - 1) - std::max(j - 1, 0)));
  m.normals[v] = Eigen::Vector3f(-dx, -dy, 1.0f).normalized();
}

// The quads, in a fixed order (so a rebuilt index buffer is the same).
void write_indices(const HeightField& f, Mesh& m) {
  m.indices.clear();
  for (int j = 0; j + 1 < f.ny; ++j)
    for (int i = 0; i + 1 < f.nx; ++i) {
      if (!(shows(f, i, j) || shows(f, i + 1, j) || shows(f, i, j + 1) || shows(f, i + 1, j + 1))) continue;
      const auto v00 = static_cast<std::uint32_t>(j * f.nx + i), v10 = v00 + 1;
      const auto v01 = v00 + static_cast<std::uint32_t>(f.nx), v11 = v01 + 1;
      if (split_along_main_diagonal(height(f, i, j), height(f, i + 1, j), height(f, i, j + 1), height(f, i + 1, j + 1))) {
        m.indices.insert(m.indices.end(), {v00, v10, v11, v00, v11, v01});
      } else {
        m.indices.insert(m.indices.end(), {v00, v10, v01, v10, v11, v01});
      }
    }
}

bool has_skirt(const HeightField& f) { return !std::isnan(f.skirt_bottom_m) && f.shows.empty(); }

// The skirt's four sides: the edge cells of each, in order, and the way out.
struct SkirtSide {
  int i0, j0, di, dj, count;
  Eigen::Vector3f outward;
};
std::array<SkirtSide, 4> skirt_sides(const HeightField& f) {
  return {{{0, 0, 1, 0, f.nx, -Eigen::Vector3f::UnitY()},
           {f.nx - 1, 0, 0, 1, f.ny, Eigen::Vector3f::UnitX()},
           {0, f.ny - 1, 1, 0, f.nx, Eigen::Vector3f::UnitY()},
           {0, 0, 0, 1, f.ny, -Eigen::Vector3f::UnitX()}}};
}

// The skirt's vertices of the edge cells in [i0, i1) x [j0, j1).
void set_skirt_vertices(const HeightField& f, int i0, int j0, int i1, int j1, Mesh& m) {
  std::size_t v = static_cast<std::size_t>(f.nx) * f.ny;
  const auto d = static_cast<float>(f.cell_m);
  for (const SkirtSide& s : skirt_sides(f))
    for (int k = 0; k < s.count; ++k, v += 2) {
      const int i = s.i0 + k * s.di, j = s.j0 + k * s.dj;
      if (i < i0 || i >= i1 || j < j0 || j >= j1) continue;
      m.positions_m[v] = Eigen::Vector3f(d * i, d * j, height(f, i, j));
      m.positions_m[v + 1] = Eigen::Vector3f(d * i, d * j, std::min(f.skirt_bottom_m, height(f, i, j)));
      m.normals[v] = m.normals[v + 1] = s.outward;
    }
}

void write_skirt_indices(const HeightField& f, Mesh& m) {
  auto v = static_cast<std::uint32_t>(f.nx * f.ny);
  for (const SkirtSide& s : skirt_sides(f)) {
    for (int k = 0; k + 1 < s.count; ++k, v += 2) m.indices.insert(m.indices.end(), {v, v + 1, v + 3, v, v + 3, v + 2});
    v += 2;
  }
}

}  // namespace

std::size_t skirt_vertex_count(const HeightField& f) {
  return has_skirt(f) ? 4 * static_cast<std::size_t>(f.nx + f.ny) : 0;
}

bool split_along_main_diagonal(float h00, float h10, float h01, float h11) {
  return std::abs(h00 - h11) <= std::abs(h10 - h01);
}

void build_terrain_mesh(const HeightField& f, Mesh& m) {
  const auto n = static_cast<std::size_t>(f.nx) * static_cast<std::size_t>(f.ny) + skirt_vertex_count(f);
  m.positions_m.resize(n);
  m.normals.resize(n);
  for (int j = 0; j < f.ny; ++j)
    for (int i = 0; i < f.nx; ++i) set_vertex(f, i, j, m);
  write_indices(f, m);
  if (has_skirt(f)) {
    set_skirt_vertices(f, 0, 0, f.nx, f.ny, m);
    write_skirt_indices(f, m);
  }
}

bool update_terrain_mesh(const HeightField& f, int i0, int j0, int i1, int j1, Mesh& m) {
  i0 = std::max(0, i0 - 1);
  j0 = std::max(0, j0 - 1);
  i1 = std::min(f.nx, i1 + 1);
  j1 = std::min(f.ny, j1 + 1);
  for (int j = j0; j < j1; ++j)
    for (int i = i0; i < i1; ++i) set_vertex(f, i, j, m);
  if (has_skirt(f)) set_skirt_vertices(f, i0, j0, i1, j1, m);
  // The quads touching the region keep their place in the index buffer
  // (write_indices' order); one whose diagonal no longer follows the
  // surface is rewritten there.
  bool flipped = false;
  const auto rewrite = [&](int i, int j, std::size_t q) {
    const bool main = split_along_main_diagonal(height(f, i, j), height(f, i + 1, j), height(f, i, j + 1), height(f, i + 1, j + 1));
    if ((m.indices[q + 2] == static_cast<std::uint32_t>((j + 1) * f.nx + i + 1)) == main) return;
    const auto v00 = static_cast<std::uint32_t>(j * f.nx + i), v10 = v00 + 1;
    const auto v01 = v00 + static_cast<std::uint32_t>(f.nx), v11 = v01 + 1;
    const std::uint32_t quad[2][6] = {{v00, v10, v01, v10, v11, v01}, {v00, v10, v11, v00, v11, v01}};
    std::copy(quad[main], quad[main] + 6, m.indices.begin() + static_cast<std::ptrdiff_t>(q));
    flipped = true;
  };
  const int qi0 = std::max(0, i0 - 1), qj0 = std::max(0, j0 - 1);
  if (f.shows.empty()) {
    for (int j = qj0; j < j1 && j + 1 < f.ny; ++j)
      for (int i = qi0; i < i1 && i + 1 < f.nx; ++i) rewrite(i, j, 6 * (static_cast<std::size_t>(j) * (f.nx - 1) + i));
    return flipped;
  }
  // With a mask, a quad's place is the count of shown quads before it.
  std::size_t q = 0;
  for (int j = 0; j + 1 < f.ny && j < j1; ++j)
    for (int i = 0; i + 1 < f.nx; ++i) {
      if (!(shows(f, i, j) || shows(f, i + 1, j) || shows(f, i, j + 1) || shows(f, i + 1, j + 1))) continue;
      if (j >= qj0 && i >= qi0 && i < i1) rewrite(i, j, q);
      q += 6;
    }
  return flipped;
}

}  // namespace skidsim::render
