// Soil mechanics for bodies touching the terrain (thesis ch. 5,
// docs/soil_contact.md): Bekker pressure-sinkage with Wong's
// unloading/reloading line, the Mohr-Coulomb shear bound, and the fracture
// wedge limit of a vertical interface (Perumpral 1983 via Nouguier 2000).
// Plain functions of plain data, SI units throughout.
#pragma once

#include "common/physical_constants.h"
#include "terrain/earthmoving.h"
#include <array>
#include <string>

namespace skidsim::terrain {

enum class VerticalLoadModel {
  kBekker,          // compressible: pressure from sinkage (3.19, 5.4.1)
  kIncompressible,  // the same pressure, but the plastic part of the sinkage
                    // pushes material out from under the load (5.3)
};

// What bounds the soil's resistance to an interface pushing it sideways.
enum class CuttingModel {
  kEarthmoving,  // the fundamental earthmoving equation, McKyes and Ali's 3-D
                 // form (terrain/earthmoving.h): the tool's rake, soil-tool
                 // friction and adhesion, cohesion, surcharge, side crescents
  kThesisWedge,  // the thesis's wedge (5.6): a smooth vertical face in a
                 // cohesionless soil, Perumpral's side friction
};

// The names a soil table and the push job give the cutting models
// ("earthmoving", "thesis_wedge"); false for any other name.
const char* cutting_model_name(CuttingModel model);
bool cutting_model_from_name(const std::string& name, CuttingModel* model);

struct SoilMechanics {
  VerticalLoadModel model = VerticalLoadModel::kBekker;
  // The thesis's wedge stays the default until the earthmoving equation is
  // checked against the DEM reference in sessions (docs/soil_contact.md).
  CuttingModel cutting = CuttingModel::kThesisWedge;
  // Bekker (3.19): p = (k_c / b + k_phi) z^n; Wong's table in kN/m^(n+1) and
  // kN/m^(n+2), so p comes out in kPa.
  double n = 1.1;
  double k_c_kN_per_m_n1 = 0.99;
  double k_phi_kN_per_m_n2 = 1528.43;
  // Wong's unloading/reloading line: from the largest sinkage z_max reached,
  // p = p(z_max) - k_u (z_max - z) with k_u = k_0 + A_u z_max.
  double unload_k0_kPa_per_m = 10000.0;
  double unload_Au_kPa_per_m2 = 500000.0;
  // Viscous part of the contact pressure, per m/s of sinkage rate (the
  // damping of Chrono's SCM terrain; it stops a body ringing on the elastic
  // line).
  double damping_kPa_s_per_m = 30.0;
  // Mohr-Coulomb of the soil (wedge, Janosi-Hanamoto) and of the soil-tool
  // contact (5.4.2: tau_max = (a + sigma_n tan(delta)) A).
  double cohesion_kPa = 1.04;
  double friction_angle_deg = 28.0;
  double shear_modulus_K_m = 0.025;
  double tool_adhesion_kPa = 0.0;
  double tool_friction_angle_deg = 20.0;
  // Wheels (terrain/wheel_soil.h): Wong and Reece's angle of the largest
  // normal stress, theta_m = (c1 + c2 s) theta_1 (1967 part I: c1 ~ 0.4,
  // c2 ~ 0.15), and Lyasko's slip sinkage (on) or none.
  double wheel_theta_max_c1 = 0.4;
  double wheel_theta_max_c2 = 0.15;
  bool wheel_slip_sinkage = true;
  // Stiffness of the hard base under the soil (a very stiff penalty; the
  // reaction reports it so an engine can apply it implicitly).
  double base_stiffness_kPa_per_m = 1.0e6;
};

// Throws std::invalid_argument naming the field when a value is out of range.
void validate(const SoilMechanics& soil);

// The earthmoving equation's soil (terrain/earthmoving.h) from this one, in
// SI units, for a bulk density (kg/m^3).
CuttingSoil cutting_soil(const SoilMechanics& soil, double bulk_density_kg_m3);

using skidsim::kGravity_m_s2;  // common/physical_constants.h: one gravity for the project

// k_c / b + k_phi in Pa / m^n, for a footprint whose smaller side is b.
double bekker_modulus_Pa(const SoilMechanics& soil, double footprint_b_m);

// Pressure (Pa) and its derivative (Pa/m) at sinkage z on the loading curve.
struct PressureSlope {
  double pressure_Pa = 0.0;
  double slope_Pa_per_m = 0.0;
};
PressureSlope bekker_loading(double modulus_Pa, double n, double sinkage_m);

// Unload/reload line slope k_u (Pa/m) from the largest sinkage reached,
// k0 + A_u z_max, and its growth with z_max, A_u (Pa/m^2).
double unload_stiffness_Pa_per_m(const SoilMechanics& soil, double peak_sinkage_m);
double unload_stiffness_growth_Pa_per_m2(const SoilMechanics& soil);

// The reload line of a soil loaded to `peak_sinkage_m`: its top p(z_max) and
// slope k_u, for evaluating many depths of one rut (bekker_pressure).
struct ReloadLine {
  double peak_sinkage_m = 0.0;
  double peak_pressure_Pa = 0.0;
  double stiffness_Pa_per_m = 0.0;
};
ReloadLine reload_line(const SoilMechanics& soil, double modulus_Pa, double peak_sinkage_m);

// Plastic part of a peak sinkage: what stays when the load is removed,
// z_max - p(z_max) / k_u (zero when the line would rebound past the start).
double plastic_sinkage_m(const SoilMechanics& soil, double modulus_Pa, double peak_sinkage_m);

// Contact pressure of the compressible model at total sinkage z (from the
// undisturbed surface) with history `peak_sinkage_m`: the loading curve past
// the peak, the reload line below it, never negative.
PressureSlope bekker_pressure(const SoilMechanics& soil, double modulus_Pa, double peak_sinkage_m,
                              double sinkage_m);
// The same with the rut's reload line computed once.
PressureSlope bekker_pressure(const ReloadLine& line, double modulus_Pa, double n, double sinkage_m);

// Fracture wedge of a vertical interface (5.6), as corrected in
// docs/soil_contact.md: with tool face angle delta_t = 90 deg,
//   F_h = W tan(phi + rho) + 2 F_l cos(phi) / cos(phi + rho),
//   F_l = tan(phi) (1 - sin(phi)) gamma g H^2 L / 6,  L = H / tan(rho).
// No soil-tool friction on the face: the interface is vertical by
// construction of the contact map (5.2.3) and is taken as smooth.
double wedge_side_friction_N(double phi_rad, double rho_rad, double density_kg_m3, double depth_m);
double wedge_limit_N(double phi_rad, double rho_rad, double wedge_weight_N, double side_friction_N);

// The analytic limit on flat ground for a blade of width B at depth H,
// minimised over rho (the reference the tests compare with), and the rho
// that minimises it.
struct WedgeSolution {
  double force_N = 0.0;
  double rho_rad = 0.0;
};
WedgeSolution flat_ground_wedge(double phi_rad, double density_kg_m3, double depth_m, double width_m);

// rho* as a function of H / B, tabulated once per soil (the thesis: "rho is
// precomputed so it costs nothing during the simulation").
class WedgeAngleTable {
 public:
  WedgeAngleTable() = default;
  explicit WedgeAngleTable(double phi_rad);
  double rho_rad(double depth_over_width) const;

 private:
  static constexpr int kEntries = 65;
  static constexpr double kMaxRatio = 4.0;  // H / B beyond this uses the last entry
  std::array<double, kEntries> rho_{};
};

}  // namespace skidsim::terrain
