// Measurements of a pile on the grid: apex, run-out radius along the axes and
// the diagonals (isotropy), and the flank slope (angle of repose).
#pragma once

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

struct PileMetrics {
  double apex_material_m = 0.0;
  // Distance from the centre cell at which the material height falls to
  // `edge_material_m`, interpolated between cells, mean of the 4 directions.
  double radius_axes_m = 0.0;
  double radius_diagonals_m = 0.0;
  // Least-squares slope of material height against distance from the centre
  // over the flank (cells between 15 % and 85 % of the apex height).
  double flank_slope_deg = 0.0;
  int flank_cells = 0;
};

PileMetrics measure_pile(const GranularGrid& grid, int centre_i, int centre_j, double edge_material_m);

}  // namespace skidsim::terrain
