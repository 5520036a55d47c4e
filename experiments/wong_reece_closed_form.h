// The closed form of a rigid wheel on virgin soil (Wong and Reece 1967;
// Wong, "Theory of Ground Vehicles", 2008, 2.7), kept beside the model as
// its benchmark: written apart from terrain/wheel_soil.cpp and evaluated
// differently (composite Simpson over 4000 panels on each side of theta_m,
// the stresses written out as published, the equilibrium sinkage by the
// secant method). It is the independent reference the wheel tests and the
// speed-against-error report compare the model and the simulated wheels
// with; it shares no code with the model (only the soil table's struct).
#pragma once

#include <cmath>

#include "terrain/soil_mechanics.h"

namespace skidsim::closed_form {

struct WongReeceSoil {
  double k_c = 0.0, k_phi = 0.0, n = 1.0;  // Bekker p = (k_c / b + k_phi) z^n, Pa and m
  double c_Pa = 0.0, phi_rad = 0.0, K_m = 0.025;
  double k0_Pa_per_m = 1e7, Au_Pa_per_m2 = 5e8;  // Wong's unloading line k_u = k0 + Au z
  double c1 = 0.4, c2 = 0.15;
  bool lyasko = true;  // slip sinkage z = z0 (1 + s) / (1 - 0.5 s)
  // A smooth rim's friction on the soil: where below phi, the rim slides
  // first and the shear is the interface's, sigma tan(delta) (no adhesion).
  double rim_delta_rad = 1.5707963267948966;
};

struct WongReeceResult {
  double W = 0.0, DP = 0.0, T = 0.0;
};

// A wheel at slip s in (-1, 1) (braked below 0), sinkage z below the surface.
inline WongReeceResult wong_reece_reference(const WongReeceSoil& soil, double r, double b, double z, double s) {
  const double lyasko = soil.lyasko && s > 0.0 ? (1.0 + s) / (1.0 - 0.5 * s) : 1.0;
  const double k = soil.k_c / b + soil.k_phi;
  const double zp = z / lyasko;  // the depth the load presses (Lyasko)
  const double th1 = std::acos(1.0 - zp / r);
  const double thm = (soil.c1 + soil.c2 * s) * th1;
  // Rebound at the rear: the soil springs back by the elastic part p / k_u
  // of its largest pressure, the one at theta_m (a distance in the soil,
  // whatever the slip).
  const double d_max = (std::cos(thm) - std::cos(th1)) * r;
  const double p_max = k * std::pow(d_max, soil.n);
  const double rebound = std::fmin(d_max, p_max / (soil.k0_Pa_per_m + soil.Au_Pa_per_m2 * d_max));
  const double th2 = -std::acos(1.0 - rebound / r);
  auto sigma = [&](double th) {
    double front = th;
    if (th < thm) front = th1 - (th - th2) / (thm - th2) * (th1 - thm);
    const double depth = (std::cos(front) - std::cos(th1)) * r;
    return depth > 0.0 ? k * std::pow(depth, soil.n) : 0.0;
  };
  auto tau = [&](double th) {
    // Driven: the soil moves with the rim, j over the rim's travel (Wong
    // and Reece 1967, eq. 4). Braked: the soil stays with the ground, j over
    // the ground's travel past the wheel, r [(1 + s)(th1 - th) - (sin th1 - sin th)].
    const double j = s >= 0.0 ? r * ((th1 - th) - (1.0 - s) * (std::sin(th1) - std::sin(th)))
                              : r * ((1.0 + s) * (th1 - th) - (std::sin(th1) - std::sin(th)));
    const double strength = soil.rim_delta_rad < soil.phi_rad ? sigma(th) * std::tan(soil.rim_delta_rad)
                                                               : soil.c_Pa + sigma(th) * std::tan(soil.phi_rad);
    const double t = strength * (1.0 - std::exp(-std::fabs(j) / soil.K_m));
    return j >= 0.0 ? t : -t;
  };
  WongReeceResult out;
  auto simpson = [&](double lo, double hi) {
    const int n = 4000;
    const double h = (hi - lo) / n;
    for (int i = 0; i <= n; ++i) {
      const double th = lo + i * h;
      const double w = (i == 0 || i == n) ? 1.0 : (i % 2 ? 4.0 : 2.0);
      const double sg = sigma(th), tu = tau(th);
      out.W += w * h / 3.0 * r * b * (sg * std::cos(th) + tu * std::sin(th));
      out.DP += w * h / 3.0 * r * b * (tu * std::cos(th) - sg * std::sin(th));
      out.T += w * h / 3.0 * r * r * b * tu;
    }
  };
  simpson(th2, thm);
  simpson(thm, th1);
  return out;
}

// The sinkage at which the reference carries `load_N` (secant on W(z) - load).
inline double wong_reece_reference_sinkage(const WongReeceSoil& soil, double r, double b, double load_N, double s) {
  double z0 = 0.01 * r, z1 = 0.2 * r;
  double f0 = wong_reece_reference(soil, r, b, z0, s).W - load_N;
  double f1 = wong_reece_reference(soil, r, b, z1, s).W - load_N;
  for (int it = 0; it < 60 && std::fabs(z1 - z0) > 1e-12; ++it) {
    const double z2 = std::fmax(1e-6, std::fmin(r, z1 - f1 * (z1 - z0) / (f1 - f0)));
    z0 = z1;
    f0 = f1;
    z1 = z2;
    f1 = wong_reece_reference(soil, r, b, z1, s).W - load_N;
  }
  return z1;
}

}  // namespace skidsim::closed_form

namespace skidsim::closed_form {

// A towed wheel: the slip at which the reference's torque vanishes at the
// sinkage that carries the load (bisection on s).
inline double wong_reece_reference_towed_slip(const WongReeceSoil& soil, double r, double b, double load_N) {
  double lo = -0.3, hi = 0.3;
  for (int it = 0; it < 50; ++it) {
    const double s = 0.5 * (lo + hi);
    const double z = wong_reece_reference_sinkage(soil, r, b, load_N, s);
    (wong_reece_reference(soil, r, b, z, s).T > 0.0 ? hi : lo) = s;
  }
  return 0.5 * (lo + hi);
}

}  // namespace skidsim::closed_form

namespace skidsim::closed_form {

// The reference's soil from a soil table's (only the parameters, in SI).
inline WongReeceSoil reference_soil_of(const terrain::SoilMechanics& s) {
  WongReeceSoil r;
  r.k_c = 1000.0 * s.k_c_kN_per_m_n1;
  r.k_phi = 1000.0 * s.k_phi_kN_per_m_n2;
  r.n = s.n;
  r.c_Pa = 1000.0 * s.cohesion_kPa;
  r.phi_rad = s.friction_angle_deg * 3.14159265358979323846 / 180.0;
  r.K_m = s.shear_modulus_K_m;
  r.k0_Pa_per_m = 1000.0 * s.unload_k0_kPa_per_m;
  r.Au_Pa_per_m2 = 1000.0 * s.unload_Au_kPa_per_m2;
  r.c1 = s.wheel_theta_max_c1;
  r.c2 = s.wheel_theta_max_c2;
  r.lyasko = s.wheel_slip_sinkage;
  return r;
}

}  // namespace skidsim::closed_form
