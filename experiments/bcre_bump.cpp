#include "experiments/bcre_bump.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>

namespace skidsim::terrain {
namespace {

constexpr double kStripM = 2.0, kX0 = 1.0, kAmplitudeM = 0.02, kBaseM = 0.5;
const double kSlope = std::tan(55.0 * kPi / 180.0);

double exact_bump_m(double x, double t_s) {
  const SoilFlowParameters soil;
  const double s2 = kBcreBumpSigma0M * kBcreBumpSigma0M + 2.0 * soil.rolling_speed_m_per_s * soil.rolling_layer_m * t_s;
  return kAmplitudeM * kBcreBumpSigma0M / std::sqrt(s2) * std::exp(-(x - kX0) * (x - kX0) / (2.0 * s2));
}

double x_of(const GranularGrid& g, int i) { return (i + 0.5) * g.cell_size_m(); }

}  // namespace

GranularGrid bcre_bump_strip(double cell_m, double step_dt_s, double bound_fraction) {
  GridSpec spec;
  spec.nx = static_cast<int>(std::lround(kStripM / cell_m));
  spec.ny = 1;
  spec.cell_size_m = cell_m;
  spec.flow_bound_fraction = bound_fraction;
  GranularGrid g(spec, SoilFlowParameters{}, step_dt_s, 100000);
  for (int i = 0; i < spec.nx; ++i) g.set_material_m(i, 0, kBaseM + kSlope * x_of(g, i) + exact_bump_m(x_of(g, i), 0.0));
  return g;
}

double bcre_bump_error(const GranularGrid& strip, double t_s) {
  double worst = 0.0;
  for (int i = 0; i < strip.nx(); ++i) {
    const double x = x_of(strip, i);
    if (std::abs(x - kX0) > 0.5) continue;
    const double u = strip.material_m(i, 0) - kBaseM - kSlope * x;
    worst = std::max(worst, std::abs(u - exact_bump_m(x, t_s)));
  }
  return worst / kAmplitudeM;
}

}  // namespace skidsim::terrain
