// The BCRE consistency experiment (thesis 4.4.2): a 2 m strip, one row of
// cells, inclined at 55 deg so that every cell flows above the full-flow
// angle (z+ constant), carrying a Gaussian bump of amplitude A = 2 cm and
// width sigma0 = 0.1 m at x0 = 1 m. The excess over the plane diffuses as
// dh/dt = D lap(h), D = v h_r, so
//   u(x, t) = A sigma0 / sigma(t) exp(-(x - x0)^2 / (2 sigma(t)^2)),
//   sigma^2 = sigma0^2 + 2 D t.
// The terrain test asserts its order of convergence; the speed-against-error
// report times it over cells and sub-steps.
#pragma once

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

inline constexpr double kBcreBumpSigma0M = 0.1;  // the bump's initial width

// The strip at t = 0 (default dry sand), stepped every `step_dt_s`, its
// sweep held to `bound_fraction` of the stability bound. Every cell starts
// flowing on its first step, as on a running slope.
GranularGrid bcre_bump_strip(double cell_m, double step_dt_s, double bound_fraction = 1.0);

// The largest |u - u_exact| over the middle metre at time `t_s`, relative
// to A.
double bcre_bump_error(const GranularGrid& strip, double t_s);

}  // namespace skidsim::terrain
