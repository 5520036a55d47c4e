#include "terrain/wheel_soil.h"

#include <algorithm>
#include <array>
#include <cmath>

namespace skidsim::terrain {
namespace {

// Gauss-Legendre nodes and weights on [-1, 1] (Newton on P_n from the
// Chebyshev guesses), computed once.
constexpr int kNodes = 16;
struct GaussLegendre {
  std::array<double, kNodes> x{}, w{};
  GaussLegendre() {
    for (int i = 0; i < kNodes; ++i) {
      double z = std::cos(kPi * (i + 0.75) / (kNodes + 0.5));
      double dp = 1.0;
      for (int it = 0; it < 100; ++it) {
        double p0 = 1.0, p1 = z;
        for (int k = 2; k <= kNodes; ++k) {
          const double p2 = ((2.0 * k - 1.0) * z * p1 - (k - 1.0) * p0) / k;
          p0 = p1;
          p1 = p2;
        }
        dp = kNodes * (z * p1 - p0) / (z * z - 1.0);
        const double step = p1 / dp;
        z -= step;
        if (std::abs(step) < 1e-15) break;
      }
      x[i] = z;
      w[i] = 2.0 / ((1.0 - z * z) * dp * dp);
    }
  }
};
const GaussLegendre& gauss() {
  static const GaussLegendre g;
  return g;
}

// Everything the stresses at one angle need, fixed for one evaluation.
struct Contact {
  double r = 0.0, width = 0.0;
  double theta1 = 0.0, theta2 = 0.0, thetam = 0.0;
  double cos_theta1 = 1.0, sin_theta1 = 0.0;
  double modulus = 0.0;
  double cohesion = 0.0, tan_phi = 0.0, K = 0.0;
  double rim_clock = 1.0, ground_clock = 1.0;  // a and b of the shear displacement
  double flat_depth = 0.0;                     // the flattened bottom's depth below the entry surface
  SoilHistory history;
  ReloadLine reload;  // a rut's, computed once per evaluation
  const SoilMechanics* soil = nullptr;
};

// The soil's pressure at depth `d` below the surface ahead: its loading
// curve, or the reload line of a rut (soil_mechanics.h bekker_pressure).
double pressure_at_depth(const Contact& c, double d) {
  if (!(d > 0.0)) return 0.0;
  const double depth = c.history.surface_depth_m + std::min(d, c.flat_depth);
  return bekker_pressure(c.reload, c.modulus, c.soil->n, depth).pressure_Pa;
}

// Normal stress at theta (cos_theta its cosine): the front directly, the
// rear mapped onto it (Wong-Reece 1967 part I, eq. 7).
double normal_stress(const Contact& c, double theta, double cos_theta) {
  double cos_front = cos_theta;
  if (theta < c.thetam)
    cos_front = std::cos(c.theta1 - (theta - c.theta2) / (c.thetam - c.theta2) * (c.theta1 - c.thetam));
  return pressure_at_depth(c, c.r * (cos_front - c.cos_theta1));
}

struct Sums {
  double W = 0.0, DP = 0.0, T = 0.0;
};

void integrate(const Contact& c, double lo, double hi, Sums& s) {
  if (!(hi > lo)) return;
  const GaussLegendre& g = gauss();
  const double half = 0.5 * (hi - lo), mid = 0.5 * (hi + lo);
  for (int k = 0; k < kNodes; ++k) {
    const double th = mid + half * g.x[k];
    const double wt = half * g.w[k];
    const double cs = std::cos(th), sn = std::sin(th);
    const double sigma = normal_stress(c, th, cs);
    const double j = c.r * (c.rim_clock * (c.theta1 - th) - c.ground_clock * (c.sin_theta1 - sn));
    const double tau = (c.cohesion + sigma * c.tan_phi) * std::copysign(1.0 - std::exp(-std::abs(j) / c.K), j);
    // The flattened bottom keeps the rim's directions: it only caps the
    // stresses (a flat strip at the same depth differs by the cos of its
    // small angles, and the hand-over stays continuous).
    s.W += wt * (sigma * cs + tau * sn) * c.r;
    s.DP += wt * (tau * cs - sigma * sn) * c.r;
    s.T += wt * tau * c.r * c.r;
  }
}

}  // namespace

double slip_sinkage_factor(double slip) {
  const double s = std::clamp(slip, 0.0, 1.0);
  return (1.0 + s) / (1.0 - 0.5 * s);
}

WheelSoilForces wong_reece(const WheelShape& wheel, const SoilMechanics& soil, double sinkage_m, double slip,
                           const SoilHistory& history) {
  WheelSoilForces out;
  const double r = wheel.radius_m;
  if (!(sinkage_m > 0.0) || !(r > 0.0) || !(wheel.width_m > 0.0)) return out;
  const double s = std::clamp(slip, -1.0, 1.0);
  // Slip sinkage: the stresses are those of the depth the load presses.
  const double z = std::min(sinkage_m, r) / (soil.wheel_slip_sinkage ? slip_sinkage_factor(s) : 1.0);
  Contact c;
  c.soil = &soil;
  c.history = history;
  c.r = r;
  c.width = wheel.width_m;
  c.modulus = bekker_modulus_Pa(soil, wheel.width_m);
  if (history.peak_sinkage_m > 0.0) c.reload = reload_line(soil, c.modulus, history.peak_sinkage_m);
  // The weaker of the soil and the rim-soil interface shears (WheelShape).
  const bool rim_slides = deg_to_rad(soil.friction_angle_deg) > wheel.rim_friction_angle_rad;
  c.cohesion = rim_slides ? 0.0 : 1000.0 * soil.cohesion_kPa;
  c.tan_phi = std::tan(rim_slides ? wheel.rim_friction_angle_rad : deg_to_rad(soil.friction_angle_deg));
  c.K = soil.shear_modulus_K_m;
  // The faster surface's clock (the rim's when driven, the ground's when braked).
  c.rim_clock = s >= 0.0 ? 1.0 : 1.0 + s;
  c.ground_clock = s >= 0.0 ? 1.0 - s : 1.0;
  c.theta1 = std::acos(1.0 - z / r);
  c.cos_theta1 = std::cos(c.theta1);
  c.sin_theta1 = std::sin(c.theta1);
  c.thetam = std::clamp(soil.wheel_theta_max_c1 + soil.wheel_theta_max_c2 * s, 0.0, 1.0) * c.theta1;
  // A tyre flattens below the depth where the soil's pressure reaches its
  // inflation and carcass pressures (Wong 2008, 2.7.2).
  // The largest stress is the front's at theta_m; where the soil would
  // press the tyre harder than its limit, the tyre's bottom flattens at the
  // depth where the soil's pressure equals it.
  c.flat_depth = z;
  const double deepest_stressed = r * (std::cos(c.thetam) - c.cos_theta1);
  if (wheel.ground_pressure_limit_Pa > 0.0 &&
      pressure_at_depth(c, deepest_stressed) > wheel.ground_pressure_limit_Pa) {
    double lo = 0.0, hi = deepest_stressed;
    for (int it = 0; it < 60; ++it) {
      const double m = 0.5 * (lo + hi);
      (pressure_at_depth(c, m) > wheel.ground_pressure_limit_Pa ? hi : lo) = m;
    }
    c.flat_depth = lo;
    out.flat_half_angle_rad = std::acos(std::clamp(1.0 - (deepest_stressed - c.flat_depth) / r, -1.0, 1.0));
  }
  // The rear: the soil springs back along its unloading line (Wong's k_u)
  // by the elastic part of the deepest pressing, and the rim leaves it where
  // it rises above that level.
  const double pressed = std::min(deepest_stressed, c.flat_depth);
  const double deepest = history.surface_depth_m + pressed;
  const double peak = std::max(history.peak_sinkage_m, deepest);
  const double rebound = std::max(0.0, deepest - plastic_sinkage_m(soil, c.modulus, peak));
  // The flattened tyre leaves the rut shallower by its deflection.
  const double deflection = deepest_stressed - pressed;
  c.theta2 = -std::acos(std::clamp(1.0 - (deflection + std::min(rebound, pressed)) / r, -1.0, 1.0));
  c.thetam = std::max(c.thetam, c.theta2);

  // Split where the integrand has a kink: theta_m, and where the cap
  // starts and ends on either side of it.
  std::array<double, 5> cuts{c.theta2, c.thetam, c.thetam, c.thetam, c.theta1};
  if (c.flat_depth < deepest_stressed) {
    cuts[2] = std::acos(std::clamp(c.cos_theta1 + c.flat_depth / r, -1.0, 1.0));  // front
    const double f = (c.theta1 - cuts[2]) / (c.theta1 - c.thetam);                     // its rear image
    cuts[3] = c.theta2 + f * (c.thetam - c.theta2);
  }
  std::sort(cuts.begin(), cuts.end());
  Sums sums;
  for (size_t k = 0; k + 1 < cuts.size(); ++k) integrate(c, cuts[k], cuts[k + 1], sums);

  out.vertical_N = wheel.width_m * sums.W;
  out.drawbar_pull_N = wheel.width_m * sums.DP;
  out.drive_torque_Nm = wheel.width_m * sums.T;
  out.entry_rad = c.theta1;
  out.exit_rad = c.theta2;
  out.max_stress_rad = c.thetam;
  out.max_normal_stress_Pa = pressure_at_depth(c, deepest_stressed);
  out.contact_length_m = r * (c.sin_theta1 - std::sin(c.theta2));
  out.shear_strength_N = c.cohesion * out.contact_length_m * wheel.width_m + std::max(0.0, out.vertical_N) * c.tan_phi;
  return out;
}

double wong_reece_sinkage_m(const WheelShape& wheel, const SoilMechanics& soil, double load_N, double slip,
                            const SoilHistory& history) {
  double lo = 0.0, hi = wheel.radius_m;
  if (!(load_N > 0.0)) return 0.0;
  if (wong_reece(wheel, soil, hi, slip, history).vertical_N < load_N) return hi;
  for (int it = 0; it < 80; ++it) {
    const double m = 0.5 * (lo + hi);
    (wong_reece(wheel, soil, m, slip, history).vertical_N < load_N ? lo : hi) = m;
  }
  return 0.5 * (lo + hi);
}

}  // namespace skidsim::terrain
