#include "terrain/wheel_contact.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace skidsim::terrain {
namespace {

// The cell containing a point, or false off the grid.
bool cell_at(const GranularGrid& grid, const Eigen::Vector2d& p, int* i, int* j) {
  const GridSpec& spec = grid.spec();
  const double fi = std::floor((p.x() - spec.origin_m.x()) / spec.cell_size_m + 0.5);
  const double fj = std::floor((p.y() - spec.origin_m.y()) / spec.cell_size_m + 0.5);
  if (!(fi >= 0.0 && fj >= 0.0 && fi < grid.nx() && fj < grid.ny())) return false;
  *i = static_cast<int>(fi);
  *j = static_cast<int>(fj);
  return true;
}

// The steepest surface slope the extrapolation believes (a repose slope is
// under 1; a step between cells is not a slope to extrapolate).
constexpr double kMaxSlope = 1.0;

// The travel over which a wheel takes a new reading of the soil ahead
// (WheelContactState::SideMemory): a few cm, short against a contact.
constexpr double kMemoryTravel_m = 0.02;

// A step's travel under which a wheel stands still for its memories.
constexpr double kStandingStill_m = 1e-6;

// Half the play of a wheel in its rut, in contact lengths (1.5-2 cm for the
// loader's tyre on sand; advance_wheel_contact).
constexpr double kRutPlay = 0.05;

// The share of the load under which a side of the contact is left out.
constexpr double kNegligibleSide = 1e-3;

// A rut's history from how far it lies below the undisturbed surface: the
// peak sinkage whose plastic part that is (plastic_sinkage_m grows with the
// peak; bisection). Taken from the cell's lowering, not its recorded peak,
// so a cell the wheel's own front only grazed counts as the virgin soil it
// still is.
SoilHistory rut_history(const SoilMechanics& soil, double modulus_Pa, double lowering_m) {
  SoilHistory h;
  if (!(lowering_m > 0.0)) return h;
  h.surface_depth_m = lowering_m;
  // Newton's method on z_max - p / k_u = lowering (p = k z^n, k_u = k0 +
  // A_u z), from the lowering plus its elastic part, kept inside the
  // bracket [lowering, lowering + 0.5 m] by bisection where a step leaves it.
  double lo = lowering_m, hi = lowering_m + 0.5;
  double m = std::min(hi, lowering_m + bekker_loading(modulus_Pa, soil.n, lowering_m).pressure_Pa /
                                           unload_stiffness_Pa_per_m(soil, lowering_m));
  for (int it = 0; it < 60; ++it) {
    const PressureSlope p = bekker_loading(modulus_Pa, soil.n, m);
    const double k_u = unload_stiffness_Pa_per_m(soil, m);
    const double f = m - p.pressure_Pa / k_u - lowering_m;
    (f < 0.0 ? lo : hi) = m;
    const double dk_u = unload_stiffness_growth_Pa_per_m2(soil);
    const double df = 1.0 - (p.slope_Pa_per_m * k_u - p.pressure_Pa * dk_u) / (k_u * k_u);
    double next = df > 0.0 ? m - f / df : 0.5 * (lo + hi);
    if (!(next > lo && next < hi)) next = 0.5 * (lo + hi);
    if (std::abs(next - m) < 1e-12) break;
    m = next;
  }
  h.peak_sinkage_m = m;
  return h;
}

}  // namespace

bool soil_level_ahead(const GranularGrid& grid, const SoilContactModel& model, int body_id,
                      const Eigen::Vector3d& hub_m, const Eigen::Vector2d& direction, double radius_m, double width_m,
                      SoilAhead* ahead) {
  const double d = grid.cell_size_m();
  const Eigen::Vector2d across(-direction.y(), direction.x());
  // A cell's nearest point to the axle along the direction: its centre's
  // distance less half its extent along it.
  const double half_extent = 0.5 * d * (std::abs(direction.x()) + std::abs(direction.y()));
  const double bottom = hub_m.z() - radius_m;
  const auto rim_z = [&](double t) {
    return std::abs(t) < radius_m ? hub_m.z() - std::sqrt(radius_m * radius_m - t * t)
                                  : std::numeric_limits<double>::infinity();
  };
  const int lines = std::max(2, static_cast<int>(std::ceil(width_m / d)) + 1);
  double sum = 0.0;
  int found = 0;
  for (int k = 0; k < lines; ++k) {
    const double offset = width_m * ((k + 0.5) / lines - 0.5);
    const Eigen::Vector2d line = hub_m.head<2>() + offset * across;
    // Walk out from the axle to the first two cells the rim does not reach
    // below their surface (cells this wheel is not pressing).
    double level[2] = {0.0, 0.0}, at[2] = {0.0, 0.0};
    int clear = 0, last_cell = -1, first_clear = -1;
    for (double t = 0.0; t < radius_m + 4.0 * d && clear < 2; t += 0.5 * d) {
      int i = 0, j = 0;
      if (!cell_at(grid, line + t * direction, &i, &j)) break;
      const int cell = grid.index(i, j);
      if (cell == last_cell) continue;
      last_cell = cell;
      const Eigen::Vector2d centre = grid.spec().origin_m + d * Eigen::Vector2d(i, j);
      const double t_centre = (centre - line).dot(direction);
      const double surface = grid.surface_m(i, j);
      if (t_centre <= 0.0 || surface >= rim_z(t_centre - half_extent) ||
          model.in_contact_map(body_id, static_cast<std::uint32_t>(cell))) {
        clear = 0;  // pressed, or the rim still under the surface: look further
        continue;
      }
      if (clear == 0) first_clear = cell;
      level[clear] = surface;
      at[clear] = t_centre;
      ++clear;
    }
    if (clear == 0) continue;
    // Extrapolated back along the two cells' slope to where the rim meets
    // the surface (three fixed-point steps from the level at the first).
    const double slope =
        clear == 2 && at[1] - at[0] > 0.25 * d ? std::clamp((level[1] - level[0]) / (at[1] - at[0]), -kMaxSlope, kMaxSlope) : 0.0;
    double z = level[0] - bottom;
    for (int it = 0; it < 3; ++it) {
      const double c = std::clamp(1.0 - z / radius_m, -1.0, 1.0);
      const double entry = radius_m * std::sqrt(1.0 - c * c);
      z = level[0] + slope * (entry - at[0]) - bottom;
    }
    sum += z;
    if (ahead->cell < 0 || k == lines / 2) ahead->cell = first_clear;
    ++found;
  }
  if (found == 0) return false;
  ahead->sinkage_m = sum / found;
  return true;
}

WheelGridForces wheel_on_grid(const GranularGrid& grid, const SoilContactModel& model, int body_id,
                              const WheelOnGrid& wheel, double slip_forward, WheelContactState& state) {
  WheelGridForces out;
  int hi = 0, hj = 0;
  if (!cell_at(grid, wheel.hub_m.head<2>(), &hi, &hj)) return out;
  out.cell = grid.index(hi, hj);
  const SoilMechanics& soil = model.soil_at_cell(out.cell);
  const double modulus = bekker_modulus_Pa(soil, wheel.shape.width_m);
  const double r = wheel.shape.radius_m;
  const double lowest = wheel.hub_m.z() - r;
  // The two sides: forwards (+1) and backwards (-1), each weighted by how
  // much of the load it carries.
  // A side carrying under kNegligibleSide of it is left out (its memory
  // forgotten), the other taking the whole: a wheel rolling steadily one
  // way evaluates one side (the load moves by under 0.1 % of the
  // difference between the sides' as it goes).
  double weights[2] = {0.5 * (1.0 + state.lead), 0.5 * (1.0 - state.lead)};
  for (int side = 0; side < 2; ++side)
    if (weights[side] < kNegligibleSide) weights[side] = 0.0, weights[1 - side] = 1.0;
  for (int side = 0; side < 2; ++side) {
    if (!(weights[side] > 0.0)) {
      state.side[side].set = false;
      continue;
    }
    const double sense = side == 0 ? 1.0 : -1.0;
    const Eigen::Vector2d direction = sense * wheel.heading;
    WheelContactState::SideMemory& memory = state.side[side];
    // A wheel standing still (under a micrometre a step: it would follow a
    // new reading by under 1/20000 of the difference) keeps its memory
    // without reading the grid again.
    if (!memory.set || state.last_moved_m >= kStandingStill_m) {
      SoilAhead ahead;
      if (!soil_level_ahead(grid, model, body_id, wheel.hub_m, direction, r, wheel.shape.width_m, &ahead)) {
        memory.set = false;
        continue;
      }
      // Followed over travel (WheelContactState::SideMemory): exact
      // exponential approach over kMemoryTravel_m of it.
      const double level = ahead.sinkage_m + lowest;
      const double lowering = ahead.cell >= 0 ? model.plastic_lowering_m(ahead.cell) : 0.0;
      if (!memory.set) {
        memory = {true, level, lowering};
      } else {
        const double follow = 1.0 - std::exp(-state.last_moved_m / kMemoryTravel_m);
        memory.level_m += follow * (level - memory.level_m);
        memory.lowering_m += follow * (lowering - memory.lowering_m);
      }
    }
    const double sinkage = memory.level_m - lowest;
    if (!(sinkage > 0.0)) continue;
    // The soil there: a rut's reload line from the deepest a load pressed
    // it (its spring-back already taken), else virgin soil.
    const SoilHistory history = rut_history(soil, modulus, memory.lowering_m);
    const WheelSoilForces f = wong_reece(wheel.shape, soil, sinkage, sense * slip_forward, history);
    const double w = weights[side];
    out.in_soil = true;
    out.vertical_N += w * f.vertical_N;
    out.forward_N += w * sense * f.drawbar_pull_N;
    out.drive_torque_Nm += w * sense * f.drive_torque_Nm;
    out.sinkage_m += w * sinkage;
    out.contact_length_m += w * f.contact_length_m;
    out.shear_strength_N += w * f.shear_strength_N;
  }
  return out;
}

void advance_wheel_contact(double travel_m, double moved_m, double contact_length_m, WheelContactState& state) {
  // The travel along the heading through the rut's play (a backlash of
  // +-kRutPlay of the contact): a wheel rocking in its rut by less than that neither
  // shifts its load to the other side nor meets new soil; rolling, the
  // contact follows the travel past the play as before, and sideways
  // motion as it comes. (Followed at once, the millimetres a machine rocks
  // by after a drop shifted its wheels' load between the sides a step late
  // and kept the rocking going.)
  const double sideways = std::max(0.0, moved_m - std::abs(travel_m));
  const double half_play = kRutPlay * contact_length_m;
  const double play = state.play_m + travel_m;
  state.play_m = std::clamp(play, -half_play, half_play);
  const double passed = play - state.play_m;
  state.last_moved_m = std::abs(passed) + sideways;
  if (passed == 0.0) return;
  const double target = passed > 0.0 ? 1.0 : -1.0;
  const double length = std::max(0.5 * contact_length_m, 1e-3);
  state.lead = target + (state.lead - target) * std::exp(-std::abs(passed) / length);
}

double soil_share_under(const GranularGrid& grid, const WheelOnGrid& wheel, double contact_length_m) {
  constexpr int kAlong = 8, kAcross = 3;
  constexpr double kFullDepth_m = 0.01;  // soil this deep or deeper counts whole
  const Eigen::Vector2d across(-wheel.heading.y(), wheel.heading.x());
  double sum = 0.0;
  for (int a = 0; a < kAlong; ++a) {
    for (int c = 0; c < kAcross; ++c) {
      const Eigen::Vector2d p = wheel.hub_m.head<2>() + contact_length_m * ((a + 0.5) / kAlong - 0.5) * wheel.heading +
                                wheel.shape.width_m * ((c + 0.5) / kAcross - 0.5) * across;
      int i = 0, j = 0;
      if (cell_at(grid, p, &i, &j)) sum += std::min(1.0, grid.material_m(i, j) / kFullDepth_m);
    }
  }
  return sum / (kAlong * kAcross);
}

double follow_soil_share(double measured, WheelContactState& state) {
  if (state.soil_share < 0.0) {
    state.soil_share = measured;
  } else {
    const double follow = 1.0 - std::exp(-state.last_moved_m / kMemoryTravel_m);
    state.soil_share += follow * (measured - state.soil_share);
  }
  return state.soil_share;
}

}  // namespace skidsim::terrain
