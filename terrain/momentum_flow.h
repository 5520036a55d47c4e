// Fast granular flow with momentum on the automaton's grid: a depth-averaged
// shallow granular flow of the Savage-Hutter kind (Savage and Hutter 1989,
// "The motion of a finite mass of granular material down a rough incline",
// J. Fluid Mech. 199), docs/terrain_model.md section "Fast flows".
//
// Each moving cell carries a velocity u (m/s, in the grid's plane) for the
// material it holds:
//   dh/dt + div(h u) = 0
//   du/dt + (u . grad) u = -g (grad b + K grad h) - mu g u / |u|
// with b the base, h the material, K the earth-pressure coefficient (active
// where the flow spreads, passive where it converges; Savage-Hutter (2.23))
// and Coulomb friction mu on the bed. A cell at rest starts when the driving
// acceleration exceeds g tan(repose); a moving one stops when friction takes
// its speed in a step (the thesis's stop angle is the moving friction).
// Material moves by exact integer transfers between cells (the grid's
// transfer_quanta), so the ledger stays exact; momentum goes with the
// material that carries it.
//
// Prototype scope: the collapse experiment (experiments/column_collapse.h)
// runs it beside the automaton; sessions do not use it yet. Cells start
// moving when woken (wake_all) or beside a moving cell.
#pragma once

#include <cstdint>
#include <vector>

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

struct MomentumFlowParameters {
  // Coulomb friction of a moving layer on its bed (deg); 0: the soil's stop angle.
  double bed_friction_deg = 0.0;
  // The angle whose tangent a cell at rest must be driven past to start (deg); 0: the soil's repose angle.
  double start_friction_deg = 0.0;
  // Earth-pressure coefficient K; 0: Savage-Hutter's active and passive
  // values from the internal friction (the repose angle) and the bed friction.
  double earth_pressure = 0.0;
  // Courant number of a sub-step: (|u| + |v| + sqrt(g K h)) dt / d.
  double courant = 0.4;
  // A channel's side walls, gap_m apart along the grid's y (0: none): the
  // layer rubs on both with Coulomb friction tan(delta_w) under its
  // hydrostatic side pressure, a deceleration tan(delta_w) g f / gap (Jop,
  // Forterre and Pouliquen 2005, "Crucial role of sidewalls in granular
  // surface flows", J. Fluid Mech. 541).
  double side_wall_gap_m = 0.0;
  double side_wall_friction_deg = 0.0;
  int max_substeps = 64;
};

// Savage-Hutter (2.23): K = 2 sec^2(phi) (1 -+ sqrt(1 - cos^2(phi) sec^2(delta))) - 1,
// active (-) and passive (+); delta <= phi.
double earth_pressure_active(double phi_deg, double delta_deg);
double earth_pressure_passive(double phi_deg, double delta_deg);

class MomentumFlow {
 public:
  // Throws std::invalid_argument when the fastest flow the grid's tallest
  // column could make (a fall from its whole height: sqrt(2 g H) +
  // sqrt(g K H)) would need more than max_substeps sub-steps per step.
  MomentumFlow(const GranularGrid& grid, const MomentumFlowParameters& params, double step_dt_s);

  // Examines every cell that holds material once (after the terrain was
  // set up or changed from outside).
  void wake_all(const GranularGrid& grid);
  // One step of step_dt_s: sub-steps as the fastest moving cell asks.
  void step(GranularGrid& grid);

  double speed_m_s(int cell) const;
  double velocity_x_m_s(int cell) const { return ux_[cell]; }
  double velocity_y_m_s(int cell) const { return uy_[cell]; }
  double flowing_m(int cell) const { return flowing_[cell] * kHeightQuantumM; }
  std::size_t moving_cells() const { return moving_.size(); }
  const std::vector<int>& moving() const { return moving_; }
  int last_substeps() const { return last_substeps_; }
  double bed_friction_tan() const { return mu_; }
  double start_friction_tan() const { return mu_start_; }
  double earth_pressure_active() const { return k_active_; }
  double earth_pressure_passive() const { return k_passive_; }
  // Bytes of state per cell (velocity, flags); the moving list comes on top.
  static constexpr std::size_t kStateBytesPerCell = 2 * sizeof(double) + sizeof(std::int64_t) + sizeof(std::uint8_t);

 private:
  void substep(GranularGrid& grid, double dt_s);
  void accelerate(const GranularGrid& grid, double dt_s);
  void transport(GranularGrid& grid, double dt_s);
  void mark(int cell);

  double step_dt_s_ = 0.0, d_ = 0.0;
  double mu_ = 0.0, mu_start_ = 0.0, tan_stop_ = 0.0, min_layer_m_ = 0.0, wall_mu_over_gap_ = 0.0, k_active_ = 1.0, k_passive_ = 1.0, courant_ = 0.4;
  int max_substeps_ = 64, last_substeps_ = 0;
  std::vector<double> ux_, uy_;
  std::vector<std::uint8_t> listed_;
  std::vector<int> moving_, candidates_;
  // Per sub-step scratch: what each listed cell sends along +x, -x, +y, -y.
  struct Out {
    int cell;
    std::int64_t q[4];
    double ux, uy;
    std::int64_t flowing;  // the flowing layer's quanta
  };
  std::vector<Out> outs_;
  std::vector<double> mom_x_, mom_y_;  // momentum arriving, quanta m/s
  std::vector<std::int64_t> flowing_;   // per cell: quanta of its flowing layer (<= its material)
  std::vector<std::int64_t> arriving_, leaving_;  // per sub-step: flowing quanta in and out
};

}  // namespace skidsim::terrain
