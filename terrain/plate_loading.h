// The plate-loading experiment behind Bekker's pressure-sinkage law (3.19),
// as the thesis runs it (7.3.1, table 7.6, fig. 7.10): a rigid 1 m x 1 m
// plate loaded onto a flat soil layer until it stops. The terrain tests
// assert its result and the speed-against-error report times it.
#pragma once

#include "terrain/granular_grid.h"
#include "terrain/soil_mechanics.h"

namespace skidsim::terrain {

// Soil with Bekker exponent n whose k_phi puts a 1000 kg plate 0.15 m deep
// (k_c = 0), so every n gives sinkages of centimetres, as in table 7.6.
SoilMechanics plate_test_soil(double n);

// Bekker (3.19) for the 1 m x 1 m plate: z = (m g / A / (k_c / b + k_phi))^(1/n).
double bekker_plate_depth_m(const SoilMechanics& soil, double mass_kg);

struct PlateLoadingRun {
  double sinkage_m = 0.0;        // below the layer's top
  double final_speed_m_s = 0.0;  // vertical, at the end
  double supported_N = 0.0;      // the soil's vertical force at the end
  double simulated_s = 0.0;
};

// The plate (0.1 m thick) on `grid`, a flat layer `layer_top_m` high: its
// weight applied over 1 s (a quasi-static plate-loading test) and held
// until it has stopped (10 s in all at most), stepping the grid with it.
// The plate's edges fall off the cell edges, so partly covered cells must
// carry their share.
PlateLoadingRun run_plate_loading(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double layer_top_m,
                                  double step_dt_s);

}  // namespace skidsim::terrain
