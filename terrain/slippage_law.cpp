#include "terrain/slippage_law.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {


}  // namespace

SliceFailure slice_failure(const SlippageLaw& law, double step_m, double run_m) {
  SliceFailure out;
  if (!(step_m > 0.0) || !(run_m > 0.0)) return out;
  const double theta = std::atan2(step_m, run_m);  // the slice's top
  const double phi = law.phi_rad;
  if (theta <= phi) return out;
  // (3.2) rewritten: F(alpha) = 1 where gamma (h cos a - d sin a) sin(a - phi)
  // = 2 c cos(phi). With h cos a - d sin a = rho sin(theta - a) the left side
  // is rho/2 [cos(theta + phi - 2a) - cos(theta - phi)], largest at
  // a = (theta + phi) / 2, where it is rho sin^2((theta - phi) / 2): the
  // minimum of F is below 1 exactly when that exceeds the cohesion length.
  const double rho = std::hypot(step_m, run_m);
  const double half = std::sin(0.5 * (theta - phi));
  if (rho * half * half <= law.cohesion_length_m) return out;
  // (3.4): the smaller of the two angles with F = 1 is beta_0. For c = 0 it
  // is phi (Mohr-Coulomb's infinite slope).
  const double k = std::min(1.0, std::cos(theta - phi) + 2.0 * law.cohesion_length_m / rho);
  const double beta0 = 0.5 * (theta + phi - std::acos(k));
  const double h0 = run_m * std::tan(beta0);
  const double excess = step_m - h0;
  if (!(excess > 0.0)) return out;
  // (3.7) divided by gamma (m^2): the net force on the wedge between the
  // failure plane and the top, per unit width. log1p keeps it accurate for
  // a small excess, where it tends to (run excess / 2) sin(beta_0).
  const double log_term = std::log1p(excess * (step_m + h0) / (h0 * h0 + run_m * run_m));
  const double force_m2 = 0.25 * run_m * run_m * log_term * std::cos(beta0) +
                          0.5 * run_m * (excess - run_m * (theta - beta0)) * std::sin(beta0);
  const double area_m2 = 0.5 * run_m * excess;
  out.fails = true;
  out.critical_angle_rad = beta0;
  out.excess_m = excess;
  out.accel_m_s2 = std::max(0.0, kGravity_m_s2 * force_m2 / area_m2);
  return out;
}

double critical_step_m(const SlippageLaw& law, double run_m) {
  const double phi = law.phi_rad;
  if (law.cohesion_length_m <= 0.0) return run_m * std::tan(phi);
  // rho sin^2((theta - phi)/2) with rho = run / cos(theta) grows with theta
  // from 0 at phi to infinity at 90 deg: one root, found by bisection.
  double lo = phi, hi = 0.5 * kPi;
  for (int k = 0; k < 200; ++k) {
    const double mid = 0.5 * (lo + hi);
    const double s = std::sin(0.5 * (mid - phi));
    (run_m / std::cos(mid) * s * s > law.cohesion_length_m ? hi : lo) = mid;
  }
  return run_m * std::tan(0.5 * (lo + hi));
}

double culmann_critical_height_m(double cohesion_Pa, double friction_angle_deg, double unit_weight_N_m3) {
  return 4.0 * cohesion_Pa / unit_weight_N_m3 * std::tan(0.25 * kPi + 0.5 * friction_angle_deg * kPi / 180.0);
}

SlippageLaw derive_slippage_law(const SoilFlowParameters& soil, double cell_size_m, double step_dt_s, int max_substeps,
                                double bound_fraction, double courant_limit, bool allow_beyond_bound) {
  validate(soil);
  if (!(cell_size_m > 0.0) || !std::isfinite(cell_size_m)) throw std::invalid_argument("cell_size_m must be > 0");
  if (!(step_dt_s > 0.0) || !std::isfinite(step_dt_s)) throw std::invalid_argument("step_dt_s must be > 0");
  if (!(courant_limit > 0.0) || !(courant_limit <= (allow_beyond_bound ? 16.0 : kMaxSlideCourant))) {
    std::ostringstream msg;
    msg << "slippage model: Courant limit " << courant_limit << " is outside (0, " << kMaxSlideCourant
        << "], the bound of the explicit slide";
    throw std::invalid_argument(msg.str());
  }
  SlippageLaw law;
  law.cell_size_m = cell_size_m;
  law.phi_rad = soil.slip_friction_deg() * kPi / 180.0;
  const double unit_weight = soil.bulk_density_kg_m3 * kGravity_m_s2;
  law.cohesion_length_m = 2.0 * soil.slip_cohesion_Pa * std::cos(law.phi_rad) / unit_weight;
  law.max_speed_m_s = soil.rolling_speed_m_per_s;
  law.courant_limit = courant_limit * bound_fraction;
  const double courant_step = law.max_speed_m_s * step_dt_s / cell_size_m;
  const double needed = std::max(1.0, std::ceil(courant_step / law.courant_limit - 1e-12));
  if (!(needed <= max_substeps)) {
    std::ostringstream msg;
    msg << "soil '" << soil.name << "': the slippage model is unstable at cell size " << cell_size_m
        << " m: v_max*dt/d = " << courant_step << " exceeds the bound " << law.courant_limit << " and would need "
        << needed << " sub-steps per step (limit " << max_substeps
        << "). Use larger cells, a smaller rolling_speed_m_per_s, or allow more sub-steps.";
    throw std::invalid_argument(msg.str());
  }
  law.substeps = static_cast<int>(needed);
  law.sweep_dt_s = step_dt_s / law.substeps;
  return law;
}

}  // namespace skidsim::terrain
