// The terrain tests' soil-contact helpers: a translating body (now in
// experiments/translating_body.h, shared with the performance report) and a flat site.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <cmath>

#include "terrain/granular_grid.h"
#include "terrain/soil_contact.h"
#include "experiments/translating_body.h"

namespace skidsim::terrain::testing {

using terrain::TranslatingBody;

// A flat site of `depth_m` of soil on a flat base at z = 0, `size_m` square,
// cell (0, 0) centred at the origin.
inline GranularGrid flat_site(double cells_per_m, double size_m, double depth_m, double dt_s = 0.002,
                              SoilFlowParameters flow = {}) {
  GridSpec spec;
  spec.cell_size_m = 1.0 / cells_per_m;
  spec.nx = spec.ny = static_cast<int>(std::lround(size_m * cells_per_m));
  GranularGrid g(spec, flow, dt_s);
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, j, depth_m);
  return g;
}

}  // namespace skidsim::terrain::testing
