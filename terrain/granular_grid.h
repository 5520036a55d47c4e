// The granular cellular automaton (thesis ch. 4, docs/terrain_model.md): a
// regular grid of columns of material on a hard base, relaxed by avalanches.
//
// Material is kept as an exact integer amount per cell (quanta of
// kHeightQuantumM metres of material height, i.e. kHeightQuantumM * d^2 m^3),
// so every transfer conserves material exactly and the result of a sweep
// does not depend on the order in which cells are visited.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <array>
#include <cstdint>
#include <vector>

#include "terrain/flow_law.h"
#include "terrain/slippage_law.h"

namespace skidsim::terrain {

// 2^-30 m of material height: sub-nanometre resolution, 8.6e9 m of range in
// int64, and exact conversion to double for columns below 8e6 m.
inline constexpr double kHeightQuantumM = 1.0 / 1073741824.0;

// Limits that keep every amount and sum far inside int64 and float range:
// the material a single column may hold, and the base heights.
inline constexpr double kMaxColumnM = 1000.0;
inline constexpr double kMaxBaseAbsM = 100000.0;

enum class EdgeKind : std::uint8_t {
  kClosed,  // a wall: nothing crosses it
  kOpen,    // a drop-off: material crossing it is counted as lost off-site
};

enum Edge : int { kEdgeXMin = 0, kEdgeXMax = 1, kEdgeYMin = 2, kEdgeYMax = 3 };

struct GridSpec {
  int nx = 0;
  int ny = 0;
  double cell_size_m = 0.05;
  // World position of the centre of cell (0, 0); cell (i, j) is at
  // origin + d * (i, j).
  Eigen::Vector2d origin_m = Eigen::Vector2d::Zero();
  std::array<EdgeKind, 4> edges = {EdgeKind::kClosed, EdgeKind::kClosed,
                                   EdgeKind::kClosed, EdgeKind::kClosed};
  // Share of the sweep's stability bound (kMaxZPlusOverCell) the flow law
  // may use. An automaton on a tilting body (set_world_up) uses 1/2: world
  // slopes steepen the local height differences by up to 1/cos^2 of the
  // tilt, and the margin keeps the sweep free of checkerboards to ~45 deg.
  double flow_bound_fraction = 1.0;
  // Slippage model only (SoilFlowParameters::model): the Courant number
  // v dt / d its sub-steps keep. Above kMaxSlideCourant only with
  // slide_beyond_bound_for_study (the report shows what happens there).
  double slide_courant_limit = kMaxSlideCourant;
  bool slide_beyond_bound_for_study = false;
};

// Every amount of material the automaton has seen, in quanta. The invariant
// initial + added + imported == in_cells + removed + exported + sum(off_site)
// holds exactly. `added`/`removed` are external actions (a hopper, a test);
// `imported`/`exported` are exchanges with other automata of the same cell
// size (terrain/material_exchange.h), which balance across the scene.
struct MaterialLedger {
  std::int64_t initial = 0;
  std::int64_t added = 0;
  std::int64_t removed = 0;
  std::int64_t imported = 0;
  std::int64_t exported = 0;
  std::array<std::int64_t, 4> off_site = {0, 0, 0, 0};
  std::int64_t in_cells = 0;
  std::int64_t off_site_total() const {
    return off_site[0] + off_site[1] + off_site[2] + off_site[3];
  }
  bool balanced() const {
    return initial + added + imported == in_cells + removed + exported + off_site_total();
  }
};

// What the last step did (for benchmarks, statistics and the progress line).
struct StepStats {
  std::int64_t cells_checked = 0;  // cell visits over all sub-steps
  std::int64_t cells_toppled = 0;  // visits that sent material
  std::int64_t moved_quanta = 0;   // material moved between cells
  int substeps = 0;
};

class GranularGrid {
 public:
  // Throws std::invalid_argument on a bad spec or soil, or when the flow step
  // would need more than `max_substeps` sweeps per step to stay stable.
  GranularGrid(const GridSpec& spec, const SoilFlowParameters& soil, double step_dt_s,
               int max_substeps = 64);

  const GridSpec& spec() const { return spec_; }
  const SoilFlowParameters& soil() const { return soil_; }
  const FlowLaw& flow_law() const { return law_; }
  GroundModel ground_model() const { return soil_.model; }
  // The slippage model as resolved for this grid (only meaningful when
  // ground_model() is kSlippage), and the speed of a cell's sliding wedge.
  const SlippageLaw& slippage_law() const { return slip_; }
  double slide_speed_m_s(int i, int j) const { return slide_speed_.empty() ? 0.0 : slide_speed_[index(i, j)]; }
  // Slippage model: the disturbed material lying loose on top of a cell's
  // column (dumped, pushed, slid or poured there since the initial state).
  // It has lost the soil's cohesion (remoulded), so it slides at phi while
  // the intact soil under it keeps its strength.
  double loose_material_m(int i, int j) const {
    return loose_.empty() ? 0.0 : std::min(loose_[index(i, j)], quanta_[index(i, j)]) * kHeightQuantumM;
  }
  int nx() const { return spec_.nx; }
  int ny() const { return spec_.ny; }
  double cell_size_m() const { return spec_.cell_size_m; }
  int index(int i, int j) const { return j * spec_.nx + i; }
  bool contains(int i, int j) const { return i >= 0 && j >= 0 && i < spec_.nx && j < spec_.ny; }

  // State (4.1.3): base B, material h, surface H = B + h, flowing flag I.
  double base_m(int i, int j) const { return base_m_[index(i, j)]; }
  // Loose material only: what the surface and the avalanches see. Material
  // compacted under a body (compacted_m) is counted apart.
  double material_m(int i, int j) const { return quanta_[index(i, j)] * kHeightQuantumM; }
  double surface_m(int i, int j) const { return surface_m_[index(i, j)]; }
  std::int64_t material_quanta(int i, int j) const { return quanta_[index(i, j)]; }
  bool flowing(int i, int j) const { return (flags_[index(i, j)] & kFlowing) != 0; }
  // tan of the steepest slope down which cell (i, j) could send material: the
  // quantity the sweep compares with tan(alpha) or tan(alpha_I). Zero for an
  // empty cell.
  double downhill_slope_tan(int i, int j) const;

  double quantum_volume_m3() const { return kHeightQuantumM * spec_.cell_size_m * spec_.cell_size_m; }
  double quantum_mass_kg() const { return quantum_volume_m3() * soil_.bulk_density_kg_m3; }
  // M = dx dy gamma h (4.1.3).
  double material_mass_kg(int i, int j) const { return quanta_[index(i, j)] * quantum_mass_kg(); }
  // Loose plus compacted material, over all cells.
  std::int64_t total_quanta() const;
  double total_volume_m3() const { return total_quanta() * quantum_volume_m3(); }
  MaterialLedger ledger() const;

  // Initial state. set_* counts towards the ledger's `initial`, not `added`,
  // and wakes the cell and its neighbours. Throws std::invalid_argument for a
  // cell outside the grid, a non-finite or negative amount, a column over
  // kMaxColumnM or a base beyond kMaxBaseAbsM.
  void set_base_m(int i, int j, double base_m);
  void set_material_m(int i, int j, double material_m);

  // External actions f1/f2 (4.3.3), applied between steps: a hopper pouring,
  // a bucket digging. Amounts are rounded to whole quanta; the functions
  // return the volume actually added or removed (removal is limited to what
  // the cell holds: a cell never goes below its base).
  double add_material_m3(int i, int j, double volume_m3);
  double remove_material_m3(int i, int j, double volume_m3);

  // --- Exchange with other automata (terrain/material_exchange.h) ---
  // Exact moves of loose material in quanta: export is limited to what the
  // cell holds and returns what left; imported material arrives moving.
  std::int64_t export_quanta(int cell, std::int64_t quanta);
  void import_quanta(int cell, std::int64_t quanta);
  // Open edges hand what crosses them to the caller instead of counting it
  // off-site (6.3.2: the imaginary neighbours of the border cells). The
  // material waits per border slot (edge_slot) until taken; the ledger counts
  // it as exported when it crosses.
  void capture_edge_outflow(bool on);
  // Border slot of the face of cell (i, j) towards direction d (+x, -x, +y,
  // -y) on the grid's edge: 2 (nx + ny) slots in all.
  int edge_slot(int i, int j, int direction) const;
  int edge_slot_count() const { return 2 * (spec_.nx + spec_.ny); }
  // The border cell and outward direction of a slot.
  void edge_slot_cell(int slot, int* i, int* j, int* direction) const;
  std::int64_t take_edge_outflow(int slot) {
    if (edge_outflow_.empty()) return 0;  // not captured
    const std::int64_t q = edge_outflow_[static_cast<std::size_t>(slot)];
    edge_outflow_[static_cast<std::size_t>(slot)] = 0;
    return q;
  }
  std::int64_t pending_edge_outflow() const;
  // (6.3.2) The imaginary neighbour of a border slot is at the border cell's
  // base unless another automaton's surface stands higher there (a bucket's
  // lip against the pile it digs into): then that surface, in this grid's
  // height units. NaN: none. Only with edge capture on.
  void set_edge_neighbour_height(int slot, double height_m) {
    if (!edge_neighbour_m_.empty()) edge_neighbour_m_[static_cast<std::size_t>(slot)] = height_m;
  }

  // --- An automaton fixed to a moving body (thesis 6.2) ---
  // World up expressed in the grid's frame (A^T z). Slopes are then the world
  // slopes of (6.2) between surface points, so material on a tilted base
  // slides, and spills over an open edge once the tilt exceeds the repose
  // angle. (0, 0, 1) is an ordinary level grid. Wakes the cells that hold
  // material when the tilt changed by more than ~0.06 deg since they were
  // last woken for it.
  void set_world_up(const Eigen::Vector3d& up_in_grid);
  const Eigen::Vector3d& world_up() const { return up_; }
  // Thresholds of the flow law (the soil's repose and stop angles unless
  // set): lowered while material slides into a vibrating bucket (6.4.2).
  void set_flow_angles_deg(double repose_deg, double stop_deg);
  // Counts every change of the cells' material (sweeps that moved material,
  // exchanges, external actions): a cache of anything computed from the
  // state is valid while this is unchanged.
  std::uint64_t revision() const { return revision_; }

  // Flow record, for drawing the sand that slides (thesis 8.2, the sum
  // over a cell's flows F_a E_a): per cell, the quanta its avalanche fluxes
  // sent along +x and +y (those sent along -x, -y count negative), summed
  // since record_flow(true). Off (empty) unless asked for; it never changes
  // the state. Material pushed by bodies is not avalanche flow.
  void record_flow(bool on);
  const std::vector<std::int64_t>& flow_record_x() const { return flow_x_; }
  const std::vector<std::int64_t>& flow_record_y() const { return flow_y_; }

  // --- Soil-body interaction (terrain/soil_contact.h drives these) ---
  // A cell a body covers completely: no avalanche flux crosses its faces
  // (the body is in the way), in either direction.
  void set_covered(int cell, bool covered);
  bool covered(int cell) const { return (flags_[cell] & kCovered) != 0; }
  // A cell whose material another model owns while it moves (the fast flow
  // with MomentumFlowParameters::owns_cells): the avalanche sends nothing out
  // of it; what arrives stays. The per-cell flags are allocated on first use.
  void set_held(int cell, bool held);
  bool held(int cell) const { return held_count_ != 0 && held_[cell] != 0; }
  // Compaction (Bekker plastic sinkage, thesis 5.4.1): loose material of the
  // cell becomes compacted material, which keeps its mass (the ledger counts
  // it in cells) but no longer stands in the column, so the surface drops.
  // Limited to the loose material there; returns the quanta compacted.
  std::int64_t compact_quanta(int cell, std::int64_t quanta);
  // Height the cell's compacted material would have if loose again.
  double compacted_m(int cell) const { return compacted_.empty() ? 0.0 : compacted_[cell] * kHeightQuantumM; }
  // Loose material pushed by a body from one cell to another (5.7): exact,
  // limited to what `from` holds; returns the quanta moved. `to` < 0 sends it
  // off-site across `edge` (an open edge).
  std::int64_t transfer_quanta(int from, int to, std::int64_t quanta, Edge edge = kEdgeXMin);
  std::int64_t loose_quanta(int cell) const { return quanta_[cell]; }
  double surface_at(int cell) const { return surface_m_[cell]; }
  float base_at(int cell) const { return base_m_[cell]; }

  // One simulation step: law.substeps synchronous avalanche sweeps over the
  // active cells. Does not allocate once the active set has reached its
  // largest size so far.
  void step();
  const StepStats& last_step() const { return last_step_; }

  // Cells that the next sweep must examine (cells whose 3 x 3 neighbourhood
  // changed). Zero for a terrain at rest.
  // Sizes the sweep's lists for `cells` active cells (capped at the grid),
  // so that a busy step does not allocate: the lists otherwise grow to the
  // largest active set seen so far.
  void reserve_active_cells(std::size_t cells);
  std::size_t active_cell_count() const { return pending_all_ ? quanta_.size() : pending_.size(); }
  bool at_rest() const { return !pending_all_ && pending_.empty(); }

  // Order-independence check: when non-zero, every sparse sweep visits its
  // active cells in an order shuffled with this seed. The result must not
  // change.
  void set_sweep_shuffle_seed(std::uint64_t seed) { shuffle_seed_ = seed; }

  // How a sweep visits cells. kAuto walks the active list while it is small
  // and the whole grid, row by row, once more than 1/kDenseFraction of the
  // cells are active. Both give bit-identical results (tested); the others
  // exist to test and benchmark that.
  enum class SweepMode { kAuto, kSparse, kDense };
  // A dense sweep costs about 13-21 ns per cell of the grid, a sparse one
  // 35-46 ns per active cell (measured, `skidsim bench` and the blade push):
  // the dense one pays off above about 1/3 of the grid active.
  static constexpr std::size_t kDenseFraction = 3;
  void set_sweep_mode(SweepMode mode) { mode_ = mode; }

  // Bytes of per-cell state: material quanta, base, the cached surface
  // height and the flags. The sweep's scratch comes on top (scratch_bytes()):
  // about 28 bytes per active cell for the lists; a dense sweep keeps only
  // three rows.
  static constexpr std::size_t kStateBytesPerCell =
      sizeof(std::int64_t) + sizeof(float) + sizeof(double) + sizeof(std::uint8_t);
  std::size_t scratch_bytes() const;

 private:
  static constexpr std::uint8_t kFlowing = 1;  // I (4.5)
  static constexpr std::uint8_t kQueued = 2;   // in pending_
  static constexpr std::uint8_t kChanged = 4;  // changed in this sweep (a sparse sweep's second phase)
  // Between sweeps the same bit says that wake has queued the cell's whole
  // 3 x 3 block, so that waking it again is one test (the fast flow wakes a
  // cell at each of its transfers). The cell is in its own block, hence in
  // pending_, and both bits are cleared where pending_ is taken.
  static constexpr std::uint8_t kBlockQueued = kChanged;
  static constexpr std::uint8_t kCovered = 128;  // a body fills the cell

  // Outflow of one active cell towards its neighbours +x, -x, +y, -y.
  struct CellFlux {
    std::uint32_t cell;
    std::array<std::int32_t, 4> out;
  };

  void check_cell(const char* what, int i, int j) const;
  // Queue a cell's 3 x 3 neighbourhood for the next sweep (once a sweep).
  void wake(int cell) {
    if (!(flags_[cell] & kBlockQueued)) wake_block(cell);
  }
  void wake_block(int cell);
  void refresh_surface(int cell) {
    surface_m_[cell] = base_m_[cell] + quanta_[cell] * kHeightQuantumM;
    ++revision_;
  }
  // What crosses an open edge: off-site, or held for the caller.
  void send_over_edge(std::uint32_t cell, int direction, std::int64_t quanta);
  // Slippage model's loose layer (loose_material_m): arrivals lie on top;
  // departures take the top first.
  void loosen(std::size_t cell, std::int64_t quanta) {
    if (!loose_.empty()) loose_[cell] += quanta;
  }
  void take_from_top(std::size_t cell, std::int64_t quanta) {
    if (!loose_.empty()) loose_[cell] = std::max<std::int64_t>(0, loose_[cell] - quanta);
  }
  void wake_material_cells();
  void sweep();
  void sweep_sparse();
  void sweep_dense();
  // Per face of a cell (+x, -x, +y, -y): the drop to the neighbour across it
  // (m, > 0 downhill) and the tangential height difference across the face
  // (m per cell), both centred on the face.
  struct FaceGeometry {
    double drop[4];
    double tangential[4];
  };
  // From the 3 x 3 surface heights around a cell. The normal and tangential
  // differences are both centred on the face, so the slope magnitude is
  // second-order accurate in every direction: on a cone's diagonals a
  // one-sided estimate adds about 0.35 d/r to the slope and squares the cone.
  static FaceGeometry face_geometry_from(double here, double e, double w, double n, double s, double ne,
                                         double nw, double se, double sw) {
    return {{here - e, here - w, here - n, here - s},
            {(n + ne - s - se) * 0.25, (n + nw - s - sw) * 0.25, (e + ne - w - nw) * 0.25,
             (e + se - w - sw) * 0.25}};
  }
  FaceGeometry face_geometry(std::uint32_t cell) const;  // any cell, edges included
  // Face geometry of a tilted grid: each drop and tangential difference
  // replaced by d times the world slope of the vector between the surface
  // points (6.2).
  void tilt_faces(FaceGeometry& g) const;
  // No drop across a face of, or towards, a covered cell.
  void block_covered_faces(std::uint32_t cell, FaceGeometry& g) const;
  void compute_flux(std::uint32_t cell, const FaceGeometry& g, CellFlux& flux) const;
  // Rounds a cell's four face fluxes (quanta + 0.5) and scales them down to
  // what the cell holds.
  static std::array<std::int32_t, 4> clamp_to_available(const double q[4], std::int64_t available);
  void dense_row_fluxes(int j, std::array<std::int32_t, 4>* out);
  void gather_row(int j, const std::array<std::int32_t, 4>* below, const std::array<std::int32_t, 4>* here,
                  const std::array<std::int32_t, 4>* above);
  void sparse_fluxes();
  // Phase 1 for the slippage model (terrain/slippage_law.h): per active cell,
  // the wedge's speed (5.1) and the face fluxes (4.2).
  void slippage_fluxes();
  static constexpr std::size_t kFluxBlock = 64;

  GridSpec spec_;
  SoilFlowParameters soil_;
  FlowLaw law_;
  SlippageLaw slip_;
  std::vector<float> slide_speed_;  // slippage model: per cell, m/s
  std::vector<std::int64_t> loose_;  // slippage model: per cell, quanta of loose material on top
  std::vector<std::int64_t> quanta_;
  std::vector<float> base_m_;
  std::vector<double> surface_m_;  // base + material, kept in step with both
  std::vector<std::uint8_t> flags_;
  std::vector<std::int64_t> compacted_;  // allocated by the first compaction
  std::vector<std::int64_t> flow_x_, flow_y_;  // record_flow
  // What the avalanche may send out of a cell: nothing where it is held.
  std::int64_t sendable_quanta(std::uint32_t cell) const { return held_count_ != 0 && held_[cell] ? 0 : quanta_[cell]; }
  std::vector<std::uint8_t> held_;  // per cell, once a cell was held (set_held)
  std::int64_t held_count_ = 0;
  std::int64_t covered_count_ = 0;      // cells with kCovered: zero keeps the sweep's fast path
  std::vector<std::uint32_t> pending_;  // cells to examine in the next sweep
  std::vector<std::uint32_t> current_;  // cells examined in this sweep
  std::vector<std::uint32_t> changed_;
  std::vector<CellFlux> flux_;                   // sparse sweep: per active cell
  std::vector<std::array<std::int32_t, 4>> dense_rows_;  // dense sweep: 3 rows of cell fluxes
  std::vector<double> row_q_;                             // dense sweep: one row of face fluxes
  std::size_t changed_count_ = 0;                         // dense sweep: cells changed
  SweepMode mode_ = SweepMode::kAuto;
  // After a dense sweep that changed many cells the next sweep is dense too:
  // the active set is then "every cell" and is not listed.
  bool pending_all_ = false;
  MaterialLedger ledger_;
  StepStats last_step_;
  std::uint64_t shuffle_seed_ = 0;
  std::uint64_t sweep_count_ = 0;
  std::vector<std::int64_t> edge_outflow_;  // per border slot, while captured
  std::vector<double> edge_neighbour_m_;    // per border slot, NaN: the cell's base
  bool capture_edges_ = false;
  bool tilted_ = false;
  Eigen::Vector3d up_ = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d up_woken_ = Eigen::Vector3d::UnitZ();  // tilt at the last wake
  std::uint64_t revision_ = 0;
};

}  // namespace skidsim::terrain
