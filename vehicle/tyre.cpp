#include "vehicle/tyre.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>

namespace skidsim::vehicle {
namespace {

// Pacejka (4.49): y = D sin(C atan(B x - E (B x - atan(B x)))).
double pure_slip(double B, double C, double D, double E, double x) {
  const double Bx = B * x;
  return D * std::sin(C * std::atan(Bx - E * (Bx - std::atan(Bx))));
}

// One step of dx/dt = drive - rate x, exact for constant drive and rate.
double relax(double x, double drive, double rate, double dt) {
  if (rate * dt < 1e-9) return x + drive * dt;
  const double decay = std::exp(-rate * dt);
  return x * decay + drive * (1.0 - decay) / rate;
}

// Below low_speed the patch's spring has little damping of its own: add
// some, fading out smoothly (Pacejka 7.2, "low speed" damping).
void add_low_speed_damping(const TyreParameters& p, const TyreKinematics& k, TyreForce& f) {
  const double v = std::abs(k.contact_speed_x);
  if (v >= p.low_speed_m_per_s) return;
  const double w = 0.5 * (1.0 + std::cos(kPi * v / p.low_speed_m_per_s));
  f.longitudinal_N -= w * p.low_speed_damping_N_s_per_m * (k.contact_speed_x - k.rolling_speed);
  f.lateral_N -= w * p.low_speed_damping_N_s_per_m * k.contact_speed_y;
}

void cap_force(TyreForce& f, double limit) {
  const double magnitude = std::hypot(f.longitudinal_N, f.lateral_N);
  if (magnitude > limit && magnitude > 0.0) {
    const double s = limit / magnitude;
    f.longitudinal_N *= s;
    f.lateral_N *= s;
  }
}

}  // namespace

TyreForce magic_formula(const TyreParameters& p, double slip_ratio, double slip_angle_rad, double normal_load_N) {
  const double Fz = std::max(0.0, normal_load_N);
  const double fx0 = pure_slip(p.Bx, p.Cx, p.mu_x * Fz, p.Ex, slip_ratio);
  const double fy0 = pure_slip(p.By, p.Cy, p.mu_y * Fz, p.Ey, slip_angle_rad);
  // Combined slip (Pacejka 4.E50-4.E57 without shifts): each force is
  // weighted down by the other slip.
  const double Bxa = p.rBx1 * std::cos(std::atan(p.rBx2 * slip_ratio));
  const double Byk = p.rBy1 * std::cos(std::atan(p.rBy2 * slip_angle_rad));
  const double Gxa = std::cos(p.Cxa * std::atan(Bxa * slip_angle_rad));
  const double Gyk = std::cos(p.Cyk * std::atan(Byk * slip_ratio));
  return {fx0 * Gxa, fy0 * Gyk};
}

double deflection_slip_ratio(const TyreParameters& p, const TyreDeflection& u) {
  return std::clamp(u.x_m / p.relaxation_x_m, -1.0, 1.0);
}

double deflection_slip_angle(const TyreParameters& p, const TyreDeflection& u) {
  return std::atan(u.y_m / p.relaxation_y_m);
}

TyreForce firm_tyre_force(const TyreParameters& p, const TyreDeflection& u, const TyreKinematics& k) {
  const double Fz = k.normal_load_N;
  if (!(Fz > 0.0)) return {};
  TyreForce f = magic_formula(p, deflection_slip_ratio(p, u), deflection_slip_angle(p, u), Fz);
  add_low_speed_damping(p, k, f);
  cap_force(f, std::max(p.mu_x, p.mu_y) * Fz);  // never more than friction gives
  return f;
}

SoilTyreForce soil_tyre_force(const TyreParameters& p, const TyreDeflection& u, const SoilShear& soil,
                              const TyreKinematics& k, double contact_area_m2, double drawbar_pull_N) {
  SoilTyreForce out;
  const double W = k.normal_load_N;
  if (!(W > 0.0) || !(soil.contact_length_m > 0.0)) return out;
  const double strength = soil.cohesion_Pa * contact_area_m2 + W * std::tan(soil.friction_angle_rad);
  const double t = std::tan(deflection_slip_angle(p, u));
  const double x = std::abs(t) * soil.contact_length_m / soil.shear_modulus_K_m;  // j_max / K
  // 1 - (1 - e^-x) / x, by its series where x is small (no cancellation).
  const double mobilised = x < 1e-4 ? 0.5 * x - x * x / 6.0 : 1.0 - (1.0 - std::exp(-x)) / x;
  out.force.longitudinal_N = drawbar_pull_N;
  out.force.lateral_N = std::copysign(strength * mobilised, t);
  out.at_strength = mobilised > 0.9 || std::abs(deflection_slip_ratio(p, u)) > 0.5;
  // The low-speed damping on the deflection's rate (advance_deflection's
  // du/dt): it settles the patch's spring and, unlike damping the slip
  // speed, adds nothing to the steady pull of a slipping wheel (the
  // Wong-Reece pull already is the soil's whole answer to that slip).
  const double v = std::abs(k.contact_speed_x);
  if (v < p.low_speed_m_per_s) {
    const double w = 0.5 * (1.0 + std::cos(kPi * v / p.low_speed_m_per_s));
    const double travel = std::max(v, std::abs(k.rolling_speed));
    const double rate_x = -(k.contact_speed_x - k.rolling_speed) - u.x_m * travel / p.relaxation_x_m;
    const double rate_y = -k.contact_speed_y - u.y_m * (travel + std::abs(k.contact_speed_y)) / p.relaxation_y_m;
    out.force.longitudinal_N += w * p.low_speed_damping_N_s_per_m * rate_x;
    out.force.lateral_N += w * p.low_speed_damping_N_s_per_m * rate_y;
  }
  out.force.lateral_N = std::clamp(out.force.lateral_N, -strength, strength);
  return out;
}

void advance_deflection(const TyreParameters& p, const TyreKinematics& k, double dt_s, TyreDeflection& u) {
  const double slip_x = k.contact_speed_x - k.rolling_speed;
  const double travel = std::max(std::abs(k.contact_speed_x), std::abs(k.rolling_speed));
  u.x_m = relax(u.x_m, -slip_x, travel / p.relaxation_x_m, dt_s);
  u.y_m = relax(u.y_m, -k.contact_speed_y, (travel + std::abs(k.contact_speed_y)) / p.relaxation_y_m, dt_s);
  // A tyre off the ground springs back.
  if (!(k.normal_load_N > 0.0)) u = {};
}

}  // namespace skidsim::vehicle
