// Penetration of a tool's cutting edge (the bucket's lip driven into a bank
// or a pile): the blunt face of the edge, thickness t across its travel and
// width w, bears on the intact soil ahead of it like a strip footing at the
// depth z of soil standing over it. Terzaghi's bearing capacity with
// Vesic's factors (Vesic 1973, "Analysis of ultimate loads of shallow
// foundations", J. Soil Mech. Found. Div. 99(SM1)) and Brinch Hansen's
// depth factors (Hansen 1970, "A revised and extended formula for bearing
// capacity", Danish Geotechnical Institute Bulletin 28):
//
//   q_ult = c N_c d_c + gamma z N_q d_q + 1/2 gamma t N_gamma
//   N_q = exp(pi tan phi) tan^2(45 deg + phi / 2)       (Prandtl-Reissner)
//   N_c = (N_q - 1) cot phi        (2 + pi for phi = 0)
//   N_gamma = 2 (N_q + 1) tan phi                        (Vesic)
//   d_q = 1 + 2 tan phi (1 - sin phi)^2 k,   k = z / t, or atan(z / t) past z = t
//   d_c = d_q - (1 - d_q) / (N_c tan phi)    (1 + 0.4 k for phi = 0)
//
// and the edge resists F = q_ult t w. The mechanism forms ahead of the
// edge, within a few t, in soil the edge has not cut yet: the overburden z
// there confines it (the soil over the edge behind it rides into the
// bucket and does not). This is the bearing-capacity analogy for tool tips
// of the resistive force models reviewed by Blouin, Hemami and Lipsett
// (2001, J. Aerospace Eng. 14(3)); docs/soil_contact.md.
//
// Plain functions of plain data, SI units; no allocation.
#pragma once

#include "terrain/earthmoving.h"

namespace skidsim::terrain {

struct BearingFactors {
  double n_c = 0.0, n_q = 0.0, n_gamma = 0.0;
};

// Vesic's factors for friction angle phi (rad, in [0, 60) deg).
BearingFactors bearing_factors(double friction_angle_rad);

struct EdgeInSoil {
  double thickness_m = 0.0;   // t: the blunt face across the travel
  double width_m = 0.0;       // w
  double overburden_m = 0.0;  // z: soil standing over the edge, ahead of it
};

struct EdgeResistance {
  double pressure_Pa = 0.0;  // q_ult
  double force_N = 0.0;      // q_ult t w
  // force_N split by term: cohesion, overburden, the soil's own weight.
  double cohesion_term_N = 0.0, overburden_term_N = 0.0, weight_term_N = 0.0;
};

// Zero for an edge not in the soil (z <= 0, t <= 0 or w <= 0).
EdgeResistance edge_penetration(const CuttingSoil& soil, const EdgeInSoil& edge);

}  // namespace skidsim::terrain
