// The fundamental earthmoving equation (Reece 1964) in McKyes and Ali's
// three-dimensional form (McKyes and Ali 1977; McKyes 1985, "Soil Cutting
// and Tillage", ch. 4): the passive failure of the soil in front of a flat
// tool of width w, its tip at depth d, its face at rake alpha from the
// horizontal (90 deg: vertical; less: the face leans back and the soil rides
// up it), a straight failure plane from the tip to the surface at beta, and
// the two side crescents. Per the tool,
//
//   P = w (gamma d^2 N_gamma + c d N_c + q d N_q + c_a d N_a)           (4.12)
//
// the force of the soil on the face, inclined at the soil-tool friction
// angle delta to the face's normal, plus the adhesion c_a along the face;
// beta is the angle that minimises P. With D = cos(alpha + delta) +
// sin(alpha + delta) cot(beta + phi), r = d (cot alpha + cot beta) (the
// failure zone's length at the surface) and rho' the crescents' angle,
// cos rho' = cot alpha / (cot alpha + cot beta):
//
//   N_gamma = r / (2 d) [1 + 2 r sin(rho') / (3 w)] / D
//   N_c     = [1 + cot beta cot(beta + phi)] [1 + r sin(rho') / w] / D
//   N_q     = r / d [1 + r sin(rho') / w] / D
//   N_a     = [1 - cot alpha cot(beta + phi)] / D
//
// Without the crescents (a blade as wide as the cut, or `side_crescents`
// false) the factors are those of the plane wedge, which is Coulomb's
// passive earth pressure on a rough inclined wall; with alpha = 90 deg and
// delta = 0 it is Rankine's.
//
// Plain functions of plain data, SI units; no allocation.
#pragma once

namespace skidsim::terrain {

struct CuttingSoil {
  double unit_weight_N_per_m3 = 0.0;   // gamma g of the soil in front
  double cohesion_Pa = 0.0;            // c
  double friction_angle_rad = 0.0;     // phi
  double tool_adhesion_Pa = 0.0;       // c_a
  double tool_friction_angle_rad = 0.0;  // delta
};

struct CuttingTool {
  double depth_m = 0.0;     // d: the tip below the soil surface in front
  double width_m = 0.0;     // w
  double rake_rad = 0.0;    // alpha, in (0, pi): 90 deg vertical
  double surcharge_Pa = 0.0;  // q: the weight per area of soil heaped on the failure zone
  bool side_crescents = true;
  // McKyes and Ali load the crescents with q too (a surcharge over the
  // whole ground). A heap pushed up in front of the tool lies on the
  // central wedge only: false leaves the crescents out of N_q.
  bool surcharge_on_crescents = true;
};

struct CuttingForce {
  double failure_angle_rad = 0.0;  // beta, minimising the force
  double rupture_m = 0.0;          // r
  double crescent_angle_rad = 0.0; // rho'
  double n_gamma = 0.0, n_c = 0.0, n_q = 0.0, n_a = 0.0;
  double face_force_N = 0.0;  // P, at delta to the face's normal
  // The force the soil puts on the tool, resolved along the travel
  // (horizontal, opposing it) and the vertical (positive down: the face
  // is pulled into the soil when alpha + delta < 90 deg, pushed up past it).
  double horizontal_N = 0.0;
  double vertical_down_N = 0.0;
  // horizontal_N split by term: weight, cohesion, surcharge, adhesion (the
  // adhesion term includes the adhesion along the face, c_a d w cot alpha).
  double weight_term_N = 0.0, cohesion_term_N = 0.0, surcharge_term_N = 0.0, adhesion_term_N = 0.0;
};

// The force at a given failure angle beta (no minimisation); zero where
// beta is outside the mechanism's range (the wedge would not close).
CuttingForce mckyes_ali_at(const CuttingSoil& soil, const CuttingTool& tool, double beta_rad);

// The force with beta minimising P: a scan then golden-section refinement to
// 1e-6 rad. Zero for a tool not in the soil (d <= 0 or w <= 0).
CuttingForce mckyes_ali(const CuttingSoil& soil, const CuttingTool& tool);

// The range of beta over which the mechanism closes, (0, upper).
double max_failure_angle_rad(const CuttingSoil& soil, double rake_rad);

// Throws std::invalid_argument naming the field when a value is out of range
// (negative weight, cohesion or adhesion; phi or delta outside [0, 60) deg;
// delta > phi is allowed; rake outside [5, 150] deg).
void validate(const CuttingSoil& soil, const CuttingTool& tool);

}  // namespace skidsim::terrain
