// A soil site made simply: a flat layer of one soil over a flat hard base.
// Exercises bring their own height maps; tests, benchmarks and demos use this.
#pragma once

#include <Eigen/Core>

#include <cmath>
#include <memory>

#include "engine/world.h"
#include "terrain/granular_grid.h"

namespace skidsim::engine {

// A size_x_m x size_y_m grid at cells_per_m, its cell (0, 0) centred at
// `origin_m`, holding `depth_m` of soil over a base at z = 0.
inline std::unique_ptr<terrain::GranularGrid> flat_soil_grid(const terrain::SoilFlowParameters& flow, double cells_per_m,
                                                             const Eigen::Vector2d& origin_m, double size_x_m,
                                                             double size_y_m, double depth_m) {
  terrain::GridSpec spec;
  spec.cell_size_m = 1.0 / cells_per_m;
  spec.nx = static_cast<int>(std::lround(size_x_m * cells_per_m));
  spec.ny = static_cast<int>(std::lround(size_y_m * cells_per_m));
  spec.origin_m = origin_m;
  auto grid = std::make_unique<terrain::GranularGrid>(spec, flow, kStepSeconds);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) grid->set_material_m(i, j, depth_m);
  return grid;
}

}  // namespace skidsim::engine
