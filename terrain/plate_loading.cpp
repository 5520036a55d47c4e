#include "terrain/plate_loading.h"

#include <algorithm>
#include <cmath>

#include "terrain/body_shapes.h"
#include "terrain/soil_contact.h"
#include "terrain/translating_body.h"

namespace skidsim::terrain {

SoilMechanics plate_test_soil(double n) {
  SoilMechanics s;
  s.n = n;
  s.k_c_kN_per_m_n1 = 0.0;
  s.k_phi_kN_per_m_n2 = 1000.0 * kGravity_m_s2 / std::pow(0.15, n) / 1000.0;
  return s;
}

double bekker_plate_depth_m(const SoilMechanics& soil, double mass_kg) {
  return std::pow(mass_kg * kGravity_m_s2 / bekker_modulus_Pa(soil, 1.0), 1.0 / soil.n);
}

PlateLoadingRun run_plate_loading(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double layer_top_m,
                                  double step_dt_s) {
  constexpr double kHalfThickness = 0.05;
  SoilContactModel model(grid, soil);
  OrientedBox plate;
  plate.half_extents_m = {0.5, 0.5, kHalfThickness};
  TranslatingBody body;
  body.mass_kg = mass_kg;
  body.position_m = {0.8137, 0.7731, layer_top_m + kHalfThickness};  // off the cell edges
  BodyReaction r;
  const int max_steps = static_cast<int>(std::lround(10.0 / step_dt_s));
  int still_steps = 0, step = 0;
  for (; step < max_steps && still_steps < 100; ++step) {
    const double t = step * step_dt_s;
    still_steps = t > 1.0 && std::abs(body.velocity_m_s.z()) < 2e-6 ? still_steps + 1 : 0;
    plate.centre_m = body.position_m;
    r = model.interact(0, plate, body.motion());
    body.step(r, {0.0, 0.0, -mass_kg * kGravity_m_s2 * std::min(1.0, t / 1.0)}, step_dt_s);
    grid.step();
  }
  return {layer_top_m - (body.position_m.z() - kHalfThickness), std::abs(body.velocity_m_s.z()), r.force_N.z(),
          step * step_dt_s};
}

}  // namespace skidsim::terrain
