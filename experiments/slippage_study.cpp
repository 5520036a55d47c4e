#include "experiments/slippage_study.h"

#include <algorithm>
#include <cmath>

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

SlideOvershoot slide_overshoot_at(const SoilFlowParameters& soil_in, double courant) {
  SoilFlowParameters soil = soil_in;
  soil.model = GroundModel::kSlippage;
  const double cell = 0.05;
  // One sweep a step at exactly `courant` once the wedges slide at full speed.
  const double dt = courant * cell / soil.rolling_speed_m_per_s;
  GridSpec spec;
  spec.cell_size_m = cell;
  spec.slide_courant_limit = courant;
  spec.slide_beyond_bound_for_study = true;
  SlideOvershoot out;

  spec.nx = 60;
  spec.ny = 1;
  GranularGrid strip(spec, soil, dt, 1);
  for (int i = 20; i < 40; ++i) strip.set_material_m(i, 0, 1.0);
  const auto variation = [&]() {
    double tv = 0.0;
    for (int i = 0; i + 1 < spec.nx; ++i) tv += std::abs(strip.surface_m(i + 1, 0) - strip.surface_m(i, 0));
    return tv;
  };
  double tv = variation();
  for (int k = 0; k < 400 && !strip.at_rest(); ++k) {
    strip.step();
    const double now = variation();
    out.strip_variation_rise_m = std::max(out.strip_variation_rise_m, now - tv);
    tv = now;
  }

  spec.nx = spec.ny = 61;
  GranularGrid yard(spec, soil, dt, 1);
  for (int j = 0; j < 61; ++j)
    for (int i = 0; i < 61; ++i)
      if (cell * std::hypot(i - 30, j - 30) <= 0.25) yard.set_material_m(i, j, 1.0);
  const auto highest = [&]() {
    double h = 0.0;
    for (int j = 0; j < 61; ++j)
      for (int i = 0; i < 61; ++i) h = std::max(h, yard.surface_m(i, j));
    return h;
  };
  double top = highest();
  for (int k = 0; k < 400 && !yard.at_rest(); ++k) {
    yard.step();
    const double now = highest();
    out.yard_top_rise_m = std::max(out.yard_top_rise_m, now - top);
    top = now;
  }
  return out;
}

}  // namespace skidsim::terrain
