#include "terrain/soil_mechanics.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {


void require(bool ok, const char* field, double value, const char* range) {
  if (ok) return;
  std::ostringstream msg;
  msg << "soil mechanics: " << field << " = " << value << " must be " << range;
  throw std::invalid_argument(msg.str());
}

// F_h / (gamma g H^2 B) on flat ground: depends on rho and H / B only.
double scaled_flat_wedge(double phi, double rho, double depth_over_width) {
  const double weight = 1.0 / (2.0 * std::tan(rho));
  const double side = std::tan(phi) * (1.0 - std::sin(phi)) * depth_over_width / (6.0 * std::tan(rho));
  return wedge_limit_N(phi, rho, weight, side);
}

// Golden-section search of the rho in (0, pi/2 - phi) that minimises the
// wedge limit (the function is unimodal there: it grows without bound at
// both ends).
double minimising_rho(double phi, double depth_over_width) {
  double lo = 1e-3, hi = 0.5 * kPi - phi - 1e-3;
  const double golden = 0.5 * (std::sqrt(5.0) - 1.0);
  double a = hi - golden * (hi - lo), b = lo + golden * (hi - lo);
  double fa = scaled_flat_wedge(phi, a, depth_over_width), fb = scaled_flat_wedge(phi, b, depth_over_width);
  for (int it = 0; it < 80; ++it) {
    if (fa < fb) {
      hi = b;
      b = a;
      fb = fa;
      a = hi - golden * (hi - lo);
      fa = scaled_flat_wedge(phi, a, depth_over_width);
    } else {
      lo = a;
      a = b;
      fa = fb;
      b = lo + golden * (hi - lo);
      fb = scaled_flat_wedge(phi, b, depth_over_width);
    }
  }
  return 0.5 * (lo + hi);
}

}  // namespace

const char* cutting_model_name(CuttingModel model) {
  return model == CuttingModel::kEarthmoving ? "earthmoving" : "thesis_wedge";
}

bool cutting_model_from_name(const std::string& name, CuttingModel* model) {
  for (const CuttingModel m : {CuttingModel::kEarthmoving, CuttingModel::kThesisWedge})
    if (name == cutting_model_name(m)) {
      *model = m;
      return true;
    }
  return false;
}

CuttingSoil cutting_soil(const SoilMechanics& soil, double bulk_density_kg_m3) {
  CuttingSoil c;
  c.unit_weight_N_per_m3 = bulk_density_kg_m3 * kGravity_m_s2;
  c.cohesion_Pa = 1000.0 * soil.cohesion_kPa;
  c.friction_angle_rad = deg_to_rad(soil.friction_angle_deg);
  c.tool_adhesion_Pa = 1000.0 * soil.tool_adhesion_kPa;
  c.tool_friction_angle_rad = deg_to_rad(soil.tool_friction_angle_deg);
  return c;
}

void validate(const SoilMechanics& s) {
  require(std::isfinite(s.n) && s.n > 0.0 && s.n <= 3.0, "n", s.n, "in (0, 3]");
  require(std::isfinite(s.k_c_kN_per_m_n1) && s.k_c_kN_per_m_n1 >= 0.0, "k_c", s.k_c_kN_per_m_n1, ">= 0");
  require(std::isfinite(s.k_phi_kN_per_m_n2) && s.k_phi_kN_per_m_n2 >= 0.0, "k_phi", s.k_phi_kN_per_m_n2, ">= 0");
  require(s.k_c_kN_per_m_n1 + s.k_phi_kN_per_m_n2 > 0.0, "k_c + k_phi", s.k_c_kN_per_m_n1 + s.k_phi_kN_per_m_n2,
          "> 0");
  require(std::isfinite(s.unload_k0_kPa_per_m) && s.unload_k0_kPa_per_m >= 0.0, "unload_k0", s.unload_k0_kPa_per_m,
          ">= 0");
  require(std::isfinite(s.unload_Au_kPa_per_m2) && s.unload_Au_kPa_per_m2 >= 0.0, "unload_Au",
          s.unload_Au_kPa_per_m2, ">= 0");
  require(s.unload_k0_kPa_per_m + s.unload_Au_kPa_per_m2 > 0.0, "unload_k0 + unload_Au",
          s.unload_k0_kPa_per_m + s.unload_Au_kPa_per_m2, "> 0");
  require(std::isfinite(s.damping_kPa_s_per_m) && s.damping_kPa_s_per_m >= 0.0, "damping", s.damping_kPa_s_per_m,
          ">= 0");
  require(std::isfinite(s.cohesion_kPa) && s.cohesion_kPa >= 0.0, "cohesion_kPa", s.cohesion_kPa, ">= 0");
  require(s.friction_angle_deg > 0.0 && s.friction_angle_deg < 60.0, "friction_angle_deg", s.friction_angle_deg,
          "in (0, 60) deg");
  require(std::isfinite(s.shear_modulus_K_m) && s.shear_modulus_K_m > 0.0, "K_m", s.shear_modulus_K_m, "> 0");
  require(std::isfinite(s.tool_adhesion_kPa) && s.tool_adhesion_kPa >= 0.0, "tool_adhesion_kPa", s.tool_adhesion_kPa,
          ">= 0");
  require(s.tool_friction_angle_deg >= 0.0 && s.tool_friction_angle_deg < 60.0, "tool_friction_angle_deg",
          s.tool_friction_angle_deg, "in [0, 60) deg");
  require(s.wheel_theta_max_c1 >= 0.0 && s.wheel_theta_max_c1 <= 1.0, "wheel_theta_max_c1", s.wheel_theta_max_c1,
          "in [0, 1]");
  require(s.wheel_theta_max_c2 >= 0.0 && s.wheel_theta_max_c1 + s.wheel_theta_max_c2 <= 1.0, "wheel_theta_max_c2",
          s.wheel_theta_max_c2, ">= 0 with c1 + c2 <= 1");
  require(std::isfinite(s.base_stiffness_kPa_per_m) && s.base_stiffness_kPa_per_m > 0.0, "base_stiffness",
          s.base_stiffness_kPa_per_m, "> 0");
}

double bekker_modulus_Pa(const SoilMechanics& soil, double footprint_b_m) {
  const double b = std::max(footprint_b_m, 1e-3);
  return 1000.0 * (soil.k_c_kN_per_m_n1 / b + soil.k_phi_kN_per_m_n2);
}

PressureSlope bekker_loading(double modulus_Pa, double n, double sinkage_m) {
  if (!(sinkage_m > 0.0)) return {};
  const double p = modulus_Pa * std::pow(sinkage_m, n);
  return {p, n * p / sinkage_m};
}

double unload_stiffness_Pa_per_m(const SoilMechanics& soil, double peak_sinkage_m) {
  return 1000.0 * (soil.unload_k0_kPa_per_m + soil.unload_Au_kPa_per_m2 * std::max(peak_sinkage_m, 0.0));
}

double plastic_sinkage_m(const SoilMechanics& soil, double modulus_Pa, double peak_sinkage_m) {
  if (!(peak_sinkage_m > 0.0)) return 0.0;
  const double p = bekker_loading(modulus_Pa, soil.n, peak_sinkage_m).pressure_Pa;
  return std::max(0.0, peak_sinkage_m - p / unload_stiffness_Pa_per_m(soil, peak_sinkage_m));
}

double unload_stiffness_growth_Pa_per_m2(const SoilMechanics& soil) { return 1000.0 * soil.unload_Au_kPa_per_m2; }

ReloadLine reload_line(const SoilMechanics& soil, double modulus_Pa, double peak_sinkage_m) {
  return {peak_sinkage_m, bekker_loading(modulus_Pa, soil.n, peak_sinkage_m).pressure_Pa,
          unload_stiffness_Pa_per_m(soil, peak_sinkage_m)};
}

PressureSlope bekker_pressure(const ReloadLine& line, double modulus_Pa, double n, double sinkage_m) {
  if (sinkage_m >= line.peak_sinkage_m) return bekker_loading(modulus_Pa, n, sinkage_m);
  const double p = line.peak_pressure_Pa - line.stiffness_Pa_per_m * (line.peak_sinkage_m - sinkage_m);
  if (p <= 0.0) return {};
  return {p, line.stiffness_Pa_per_m};
}

PressureSlope bekker_pressure(const SoilMechanics& soil, double modulus_Pa, double peak_sinkage_m,
                              double sinkage_m) {
  if (sinkage_m >= peak_sinkage_m) return bekker_loading(modulus_Pa, soil.n, sinkage_m);
  return bekker_pressure(reload_line(soil, modulus_Pa, peak_sinkage_m), modulus_Pa, soil.n, sinkage_m);
}

double wedge_side_friction_N(double phi_rad, double rho_rad, double density_kg_m3, double depth_m) {
  const double length = depth_m / std::tan(rho_rad);
  return std::tan(phi_rad) * (1.0 - std::sin(phi_rad)) * density_kg_m3 * kGravity_m_s2 * depth_m * depth_m *
         length / 6.0;
}

double wedge_limit_N(double phi_rad, double rho_rad, double wedge_weight_N, double side_friction_N) {
  // (5.6) with sin(delta_t) / sin(phi + rho + delta_t) = 1 / cos(phi + rho)
  // for the vertical interface, delta_t = 90 deg.
  const double c = std::cos(phi_rad + rho_rad);
  return (wedge_weight_N * std::sin(phi_rad + rho_rad) + 2.0 * side_friction_N * std::cos(phi_rad)) / c;
}

WedgeSolution flat_ground_wedge(double phi_rad, double density_kg_m3, double depth_m, double width_m) {
  const double ratio = depth_m / width_m;
  const double rho = minimising_rho(phi_rad, ratio);
  const double scale = density_kg_m3 * kGravity_m_s2 * depth_m * depth_m * width_m;
  return {scale * scaled_flat_wedge(phi_rad, rho, ratio), rho};
}

WedgeAngleTable::WedgeAngleTable(double phi_rad) {
  for (int k = 0; k < kEntries; ++k) rho_[k] = minimising_rho(phi_rad, kMaxRatio * k / (kEntries - 1));
}

double WedgeAngleTable::rho_rad(double depth_over_width) const {
  const double x = std::clamp(depth_over_width, 0.0, kMaxRatio) * (kEntries - 1) / kMaxRatio;
  const int k = std::min(static_cast<int>(x), kEntries - 2);
  const double t = x - k;
  return rho_[k] * (1.0 - t) + rho_[k + 1] * t;
}

}  // namespace skidsim::terrain
