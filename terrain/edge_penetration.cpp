#include "terrain/edge_penetration.h"

#include <cmath>

#include "common/physical_constants.h"

namespace skidsim::terrain {

BearingFactors bearing_factors(double friction_angle_rad) {
  BearingFactors f;
  const double t = std::tan(friction_angle_rad);
  const double half = std::tan(0.25 * kPi + 0.5 * friction_angle_rad);
  f.n_q = std::exp(kPi * t) * half * half;
  // N_c's limit as phi -> 0 is 2 + pi (Prandtl's punch); below 1e-6 rad the
  // quotient loses its digits.
  f.n_c = friction_angle_rad > 1e-6 ? (f.n_q - 1.0) / t : 2.0 + kPi;
  f.n_gamma = 2.0 * (f.n_q + 1.0) * t;
  return f;
}

EdgeResistance edge_penetration(const CuttingSoil& soil, const EdgeInSoil& edge) {
  EdgeResistance out;
  if (!(edge.overburden_m > 0.0) || !(edge.thickness_m > 0.0) || !(edge.width_m > 0.0)) return out;
  const double phi = soil.friction_angle_rad;
  const BearingFactors n = bearing_factors(phi);
  // Hansen's depth factors: k grows with z / t, and stops growing (pi / 2)
  // for a deep edge.
  const double ratio = edge.overburden_m / edge.thickness_m;
  const double k = ratio <= 1.0 ? ratio : std::atan(ratio);
  const double tan_phi = std::tan(phi);
  const double d_q = 1.0 + 2.0 * tan_phi * std::pow(1.0 - std::sin(phi), 2) * k;
  const double d_c = phi > 1e-6 ? d_q - (1.0 - d_q) / (n.n_c * tan_phi) : 1.0 + 0.4 * k;
  const double gamma = soil.unit_weight_N_per_m3;
  const double area = edge.thickness_m * edge.width_m;
  out.cohesion_term_N = area * soil.cohesion_Pa * n.n_c * d_c;
  out.overburden_term_N = area * gamma * edge.overburden_m * n.n_q * d_q;
  out.weight_term_N = area * 0.5 * gamma * edge.thickness_m * n.n_gamma;
  out.force_N = out.cohesion_term_N + out.overburden_term_N + out.weight_term_N;
  out.pressure_Pa = out.force_N / area;
  return out;
}

}  // namespace skidsim::terrain
