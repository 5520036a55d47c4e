#include "terrain/flow_law.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace skidsim::terrain {
namespace {


double tan_deg(double deg) { return std::tan(deg * kPi / 180.0); }

[[noreturn]] void bad_field(const SoilFlowParameters& soil, const char* field,
                            double value, const char* expected) {
  std::ostringstream msg;
  msg << "soil '" << soil.name << "': field " << field << " = " << value
      << " is out of range (expected " << expected << ")";
  throw std::invalid_argument(msg.str());
}

}  // namespace

void validate(const SoilFlowParameters& soil) {
  if (!(soil.bulk_density_kg_m3 > 0.0) || !std::isfinite(soil.bulk_density_kg_m3))
    bad_field(soil, "bulk_density_kg_m3", soil.bulk_density_kg_m3, "> 0");
  if (!(soil.repose_angle_deg > 0.0 && soil.repose_angle_deg < 89.0))
    bad_field(soil, "repose_angle_deg", soil.repose_angle_deg, "in (0, 89)");
  if (!(soil.stop_angle_deg > 0.0 && soil.stop_angle_deg <= soil.repose_angle_deg))
    bad_field(soil, "stop_angle_deg", soil.stop_angle_deg,
              "in (0, repose_angle_deg]");
  if (!(soil.rolling_speed_m_per_s > 0.0) || !std::isfinite(soil.rolling_speed_m_per_s))
    bad_field(soil, "rolling_speed_m_per_s", soil.rolling_speed_m_per_s, "> 0");
  if (!(soil.rolling_layer_m > 0.0) || !std::isfinite(soil.rolling_layer_m))
    bad_field(soil, "rolling_layer_m", soil.rolling_layer_m, "> 0");
  // The transport flux must stay below z+ tan(beta) for the stability bound.
  if (!(soil.min_flow_layer_m >= 0.0 &&
        soil.min_flow_layer_m <= soil.rolling_layer_m * tan_deg(soil.stop_angle_deg)))
    bad_field(soil, "min_flow_layer_m", soil.min_flow_layer_m,
              "in [0, rolling_layer_m * tan(stop_angle_deg)]");
  if (!(soil.slip_cohesion_Pa >= 0.0 && soil.slip_cohesion_Pa <= 1.0e6))
    bad_field(soil, "slip_cohesion_Pa", soil.slip_cohesion_Pa, "in [0, 1e6]");
  if (!(soil.slip_friction_angle_deg >= 0.0 && soil.slip_friction_angle_deg < 89.0))
    bad_field(soil, "slip_friction_angle_deg", soil.slip_friction_angle_deg, "in [0, 89)");
  if (!(soil.flowing_friction_angle_deg >= 0.0 && soil.flowing_friction_angle_deg <= soil.repose_angle_deg))
    bad_field(soil, "flowing_friction_angle_deg", soil.flowing_friction_angle_deg, "in [0, repose_angle_deg]");
  if (!(soil.grain_diameter_m >= 0.0 && soil.grain_diameter_m <= 1.0))
    bad_field(soil, "grain_diameter_m", soil.grain_diameter_m, "in [0, 1]");
  if (soil.bed_start_angle_deg != 0.0 &&
      !(soil.bed_start_angle_deg >= soil.flowing_friction_deg() && soil.bed_start_angle_deg <= soil.repose_angle_deg))
    bad_field(soil, "bed_start_angle_deg", soil.bed_start_angle_deg, "0 or in [flowing friction, repose_angle_deg]");
  if (!(soil.impact_sheet_speed_ratio >= 0.0 && soil.impact_sheet_speed_ratio <= 1.0))
    bad_field(soil, "impact_sheet_speed_ratio", soil.impact_sheet_speed_ratio, "in [0, 1]");
  if (soil.grain_diameter_m > 0.0 || soil.thin_layer_friction_angle_deg != 0.0 || soil.thin_layer_decay_grains != 0.0) {
    if (!(soil.thin_layer_friction_angle_deg >= soil.flowing_friction_deg() && soil.thin_layer_friction_angle_deg < 89.0))
      bad_field(soil, "thin_layer_friction_angle_deg", soil.thin_layer_friction_angle_deg, "in [flowing friction, 89)");
    if (!(soil.thin_layer_decay_grains > 0.0 && soil.thin_layer_decay_grains <= 1000.0))
      bad_field(soil, "thin_layer_decay_grains", soil.thin_layer_decay_grains, "in (0, 1000]");
  }
  if (soil.rate_friction_angle_deg != 0.0 || soil.rate_friction_i0 != 0.0) {
    if (!(soil.grain_diameter_m > 0.0))
      bad_field(soil, "rate_friction_angle_deg", soil.rate_friction_angle_deg, "set only with grain_diameter_m");
    const double min_deg = std::max(soil.flowing_friction_deg(), soil.thin_layer_friction_angle_deg);
    if (!(soil.rate_friction_angle_deg >= min_deg && soil.rate_friction_angle_deg < 89.0))
      bad_field(soil, "rate_friction_angle_deg", soil.rate_friction_angle_deg, "in [flowing and thin-layer friction, 89)");
    if (!(soil.rate_friction_i0 > 0.0 && soil.rate_friction_i0 <= 10.0))
      bad_field(soil, "rate_friction_i0", soil.rate_friction_i0, "in (0, 10]");
  }
}

FlowLaw derive_flow_law(const SoilFlowParameters& soil, double cell_size_m,
                        double step_dt_s, int max_substeps, double bound_fraction) {
  validate(soil);
  if (!(cell_size_m > 0.0) || !std::isfinite(cell_size_m))
    throw std::invalid_argument("cell_size_m must be > 0");
  if (!(step_dt_s > 0.0) || !std::isfinite(step_dt_s))
    throw std::invalid_argument("step_dt_s must be > 0");

  // (4.11) for one whole step, then the sub-steps the bound asks for.
  const double z_plus_step = step_dt_s * soil.rolling_speed_m_per_s * soil.rolling_layer_m / cell_size_m;
  const double ratio = z_plus_step / cell_size_m;  // = dt v h_r / d^2
  // In double: a huge ratio must not wrap around an int.
  const double bound = kMaxZPlusOverCell * bound_fraction;
  const double needed = std::max(1.0, std::ceil(ratio / bound - 1e-12));
  if (!(needed <= max_substeps)) {
    std::ostringstream msg;
    msg << "soil '" << soil.name << "': the avalanche sweep is unstable at cell size "
        << cell_size_m << " m: dt*v*h_r/d^2 = " << ratio << " exceeds the bound "
        << bound << " and would need " << needed
        << " sub-steps per step (limit " << max_substeps
        << "). Use larger cells, a smaller rolling_speed_m_per_s or rolling_layer_m, or"
        << " allow more sub-steps.";
    throw std::invalid_argument(msg.str());
  }

  const int substeps = static_cast<int>(needed);
  FlowLaw law;
  law.tan_repose = tan_deg(soil.repose_angle_deg);
  law.tan_stop = tan_deg(soil.stop_angle_deg);
  law.transport_excess = soil.min_flow_layer_m / soil.rolling_layer_m;
  law.substeps = substeps;
  law.sweep_dt_s = step_dt_s / substeps;
  law.z_plus_per_sweep_m = z_plus_step / substeps;
  law.cell_size_m = cell_size_m;
  return law;
}

}  // namespace skidsim::terrain
