// Material moving between automata (thesis 6.3, 6.4; docs/material.md):
// the ground grid and the automata fixed to bodies (bucket, truck bed).
//   - What crosses a body automaton's edge (its imaginary border cells, 6.3.2)
//     falls from there as a parcel with the body's velocity and lands, after
//     the time its height takes, on whatever automaton is below it, or on
//     firm ground (counted apart) or off the site.
//   - A body tipped past ~85 deg sheds all it holds the same way.
//   - Where the ground's surface reaches a body automaton's edge, the ground
//     cell under the imaginary neighbour flows into the border cell by the
//     ground's own avalanche rule (6.3.3: soil pushed over the lip).
//   - A cutting edge (6.4.2): soil the edge slices from the ground (see
//     SoilContactModel::set_slicing) is held until the body has advanced one
//     of its cells, then put in the frontier row. The body's repose angle is
//     lowered while material slides in.
// Every move is whole quanta between grids of one cell size, so the total
// over ground, bodies, parcels, held slices, firm ground and off-site is
// constant exactly (total_quanta()).
#pragma once

#include <Eigen/Core>

#include <cstdint>
#include <vector>

#include "terrain/body_automaton.h"
#include "terrain/granular_grid.h"
#include "terrain/momentum_flow.h"

namespace skidsim::terrain {

struct FallingParcel {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d velocity_m_s = Eigen::Vector3d::Zero();
  std::int64_t quanta = 0;
  int from_body = -1;
};

// The cutting edge of a bucket-like body: its frontier row is the grid's
// last (i = nx - 1), facing +x.
struct CuttingEdge {
  // The mouth chokes (the edge stops slicing and pushes like any body) once
  // the body holds its heaped capacity (m^3), and opens again below
  // kReopenFraction of it (no chatter between slicing and pushing).
  double capacity_m3 = 1e9;
  static constexpr double kReopenFraction = 0.9;
  // Repose and stop angles drop by this much while material slides in
  // (6.4.2: the vibration of filling).
  double filling_angle_drop_deg = 8.0;
  // How long after the last slice the lowered angles last.
  double filling_hold_s = 0.25;
};

struct ExchangeStats {
  std::int64_t parcels_spawned = 0;
  std::int64_t parcels_landed = 0;
  std::int64_t parcels_forced = 0;  // landed at once because the parcel list was full
  std::int64_t parcels_in_flight_peak = 0;  // the most falling at once (the list holds max_parcels())
  std::int64_t quanta_sliced = 0;
  std::int64_t quanta_over_lip = 0;  // ground into a body (6.3.3)
  // What left the bodies over their edges, per direction (+x: a bucket's
  // lip, -x: its back, +-y: its sides), and shed by tipping.
  std::int64_t quanta_over_edge[4] = {0, 0, 0, 0};
  std::int64_t quanta_shed = 0;
};

class MaterialExchange {
 public:
  // `ground` may be null (a scene with no soil): material reaching the
  // ground then rests on the firm ground plane (set_firm_ground_plane).
  MaterialExchange(GranularGrid* ground, double step_dt_s, std::size_t max_parcels = 16384);

  // Adds a body automaton (not owned; it must outlive the exchange). Its
  // cell size must equal the ground's. Returns its index.
  int add_body(BodyAutomaton* body);
  int body_count() const { return static_cast<int>(bodies_.size()); }
  BodyAutomaton& body(int k) { return *bodies_[static_cast<std::size_t>(k)].automaton; }
  void set_cutting_edge(int body, const CuttingEdge& edge);
  // The ground's fast flow (terrain/momentum_flow.h; not owned, may be
  // null): what lands on the ground joins its flowing layer with the
  // parcel's horizontal velocity (and, where its soil has an impact sheet
  // speed ratio and the landing presses, MomentumFlow::landing_presses,
  // falls through that layer to the bed).
  void set_ground_flow(MomentumFlow* flow);
  // Material let go in the air (a load released from a height; the drop
  // experiment): a parcel like those that leave bodies, in the books from
  // now on.
  void release(const Eigen::Vector3d& at_m, const Eigen::Vector3d& velocity_m_s, std::int64_t quanta) {
    spawn(at_m, velocity_m_s, quanta, -1);
  }
  // Firm ground where there is no automaton: the plane normal . x = offset
  // (normal pointing up, normalised here). Default: z = 0.
  void set_firm_ground_plane(const Eigen::Vector3d& normal, double offset_m);

  // Soil a body's cutting edge sliced from ground cell `ground_cell` this
  // step (already exported from the ground). Held until the body advances.
  void add_sliced(int body, int ground_cell, std::int64_t quanta);
  // False when the body's mouth is choked: the engine then lets its edge
  // push soil instead of slicing it.
  bool mouth_open(int body) const { return !bodies_[static_cast<std::size_t>(body)].choked; }

  // Once per step, after every grid has swept.
  void step();

  // The books, in quanta (all automata share one quantum volume).
  std::int64_t in_flight_quanta() const;
  std::int64_t held_slice_quanta() const;
  std::int64_t on_firm_ground_quanta() const { return on_firm_ground_; }
  std::int64_t beside_site_quanta() const { return off_site_; }  // fell beside the ground grid
  // Everything: in the cells of every automaton, off their open edges,
  // waiting at their edges, falling, held by cutting edges, on firm ground.
  std::int64_t total_quanta() const;
  const std::vector<FallingParcel>& parcels() const { return parcels_; }
  std::size_t max_parcels() const { return max_parcels_; }
  const ExchangeStats& stats() const { return stats_; }
  double quantum_mass_kg() const { return quantum_mass_kg_; }

 private:
  struct Body {
    BodyAutomaton* automaton = nullptr;
    bool cutting = false;
    CuttingEdge edge;
    std::vector<std::int64_t> slice_by_column;  // held for the frontier row, per j
    std::int64_t slice_total = 0;
    double advance_m = 0.0;                      // forward travel since the last deposit
    double since_slice_s = 1e9;
    double since_filling_s = 1e9;
    bool choked = false;
  };
  void emit_edges(int k);
  void shed_all(int k);
  void flow_over_edges(int k);
  void feed_frontier(int k);
  void move_parcels();
  void land(const FallingParcel& p);
  // A parcel reaching the ground's cell: into the grid, and into its fast
  // flow with its horizontal velocity.
  void land_on_ground(int cell, const FallingParcel& p);
  void spawn(const Eigen::Vector3d& at, const Eigen::Vector3d& velocity, std::int64_t quanta, int from_body);
  // The ground cell under a world point; false beside the ground grid (or
  // without one).
  bool ground_cell(const Eigen::Vector3d& at, int* i, int* j) const;

  GranularGrid* ground_ = nullptr;
  MomentumFlow* ground_flow_ = nullptr;
  double dt_s_;
  double cell_size_m_ = 0.0;
  double quantum_mass_kg_ = 0.0;
  Eigen::Vector3d firm_normal_ = Eigen::Vector3d::UnitZ();
  double firm_offset_m_ = 0.0;
  bool below_firm_ground(const Eigen::Vector3d& p) const { return firm_normal_.dot(p) <= firm_offset_m_; }
  std::vector<Body> bodies_;
  std::vector<FallingParcel> parcels_;
  std::size_t max_parcels_;
  std::int64_t on_firm_ground_ = 0;
  std::int64_t off_site_ = 0;  // fell beside a ground grid
  long steps_ = 0;
  ExchangeStats stats_;
};

}  // namespace skidsim::terrain
