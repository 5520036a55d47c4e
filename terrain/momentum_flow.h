// Fast granular flow with momentum on the automaton's grid: a depth-averaged
// shallow granular flow of the Savage-Hutter kind (Savage and Hutter 1989,
// "The motion of a finite mass of granular material down a rough incline",
// J. Fluid Mech. 199), docs/fast_flows.md.
//
// The flowing layer f (quanta per cell, above the static soil) moves with
// velocities on the cells' faces (a staggered grid, so that a peak pushes
// out across every face):
//   df/dt + div(f u) = 0
//   du/dt + (u . grad) u = -g (grad H + (K - 1) grad f) - mu g u / |u|
// with H the surface, K the earth-pressure coefficient (1, hydrostatic, by
// default; Savage-Hutter's (2.23) active and passive values selectable) and
// Coulomb friction mu on the bed: the soil's flowing friction, the mu_s of
// the mu(I) law (Pouliquen 1999, Jop et al. 2006: the angle at which a
// thick flow stops; terrain/flow_law.h), rising in layers a few grains
// thick by Pouliquen's thin-layer law (read on the depth the layer moves
// in: layer_depth), or on a bare hard base the floor's; with rate_friction
// both rise with the layer's inertial number (the mu(I) law's rise).
// Advection is Stelling and Duinmeijer's (2003) momentum-conserving upwind
// form with its cross terms: a face's velocity mixes with what arrives at
// its donor cell from any side, so a layer moving diagonally keeps both
// components. The layer crosses a face as a flux-limited Lax-Wendroff flux
// (minmod; LeVeque 2002), so a front does not run ahead
// of itself by a cell's smear.
//
// Failure: the stable core under the examined cells is the highest surface
// under the terrain whose slope nowhere exceeds the repose angle; all
// material above it fails at once. A column keeps its top while a <
// tan(repose) (0.69 for 34.6 deg; Lajeunesse et al. 2004 measured 0.74).
// Erosion: under a moving layer the core's slope is held to the thick
// layer's flowing friction instead: soil at rest between the stop and start
// angles is metastable, and an avalanche passing over it carries it away
// down to the angle at which a layer as deep as the bed stops (Daerr and
// Douady 1999, "Two types of avalanche behaviour in granular media",
// Nature 399). With the soil's bed start angle (Pouliquen's theta_start of a
// deep bed) the layer carries away what its event laid down, and the bed
// the event found only where that bed, as the failure alone leaves it,
// stands past the start angle: a deep bed at rest below it holds under a
// passing layer (the DEM's erodible bed; with laid_down_holds, what a
// slowing layer lays down joins that bed). This is the fast limit of
// BCRE's exchange between rolling and static grains (Bouchaud et al.
// 1994), whose rate, the flow's speed over a grain, is 10^2-10^4 per
// second: fast beside a collapse's or a dump's second.
// Raining (Larrieu, Staron and Hinch 2006, "Raining into shallow water as a
// description of the collapse of a column of grains", J. Fluid Mech. 554):
// failed material falls freely in its cell and lands on the flowing layer
// with no horizontal momentum, losing its fall's energy at the impact as
// grains do; the hydrostatic alternative (everything failed flows at once)
// over-runs tall columns, because a shallow layer turns the whole column's
// height into horizontal pressure (raining = false keeps it selectable).
// A landing from a body (land) joins the layer with its horizontal
// momentum; with the soil's impact_sheet_speed_ratio c, where the sheet it
// sends out at up to c V (a granular jet on a plate; Cheng et al. 2007)
// would cross a cell before its friction stops it (landing_presses), it
// falls through the moving layer to the bed and its fall presses on the
// layer (the floor's reaction to its momentum flux, shaped as a stagnation
// flow's over its footprint); else it lands on the layer's top and its fall
// is lost.
// Material moves by exact integer transfers between cells (the grid's
// transfer_quanta), so the ledger stays exact; momentum goes with the
// material that carries it.
//
// Where it runs: beside the automaton (which keeps the slow avalanches and
// rest), in sessions whose site turns it on (engine::World::enable_fast_flow:
// what lands from a body joins the layer through land()) and in the collapse
// experiment (experiments/column_collapse.h). Cells start moving when woken
// (wake_all, land) or beside a moving cell. With owns_cells (off by
// default; on in the sessions' flow, session_flow_parameters) the automaton
// leaves the flowing layer's cells to the flow, and a slowing layer lays its
// base down instead (docs/fast_flows.md, "A flow that owns its cells").
#pragma once

#include <array>
#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "terrain/granular_grid.h"

namespace skidsim::terrain {

struct MomentumFlowParameters {
  // Coulomb friction of a moving layer on its bed (deg); 0: the soil's
  // flowing friction (SoilFlowParameters::flowing_friction_deg).
  double bed_friction_deg = 0.0;
  // The grain diameter of the soil's thin-layer friction (m; 0: the
  // soil's, SoilFlowParameters). A dimensionless comparison scales it with
  // the other lengths (experiments/column_collapse.h); the soil's h_stop
  // (min_flow_layer_m), a grain-scale length too, scales with it (not where
  // the soil gives no grain diameter: nothing to scale against).
  double grain_diameter_m = 0.0;
  // Coulomb friction of a layer flowing on the bare hard base, with no
  // static soil under it (deg); 0: the bed friction. A laboratory floor
  // (the DEM columns' rough plane) lets a layer slide on it more easily than
  // on its own grains (dem/calibration/chute.in, measured on both).
  double floor_friction_deg = 0.0;
  // The steepest slope of the stable core (deg): material above it fails; 0: the soil's repose angle.
  double start_friction_deg = 0.0;
  // Earth-pressure coefficient K: 1, hydrostatic (Mangeney-Castelnau et al.
  // 2005 for granular collapses); 0: Savage-Hutter's active and passive
  // values from the internal friction (the repose angle) and the bed
  // friction, whose switch between spreading and converging flow raises a
  // dam-break above its own dam (docs/fast_flows.md), kept selectable.
  double earth_pressure = 1.0;
  // Courant number of a sub-step: (|u| + |v| + sqrt(g K h)) dt / d, at
  // most 0.5 (the bound, docs/fast_flows.md); past it only when
  // study_past_bound is set (a stability study: the tests show it breaking).
  double courant = 0.4;
  bool study_past_bound = false;
  // A slow flow gathers the world's steps: it waits while one sub-step over
  // the time gathered and the next step, T, would stay within `courant`
  // and a layer speeding up at g over T within what the stability bound
  // leaves over it, then moves that time in one sub-step (not under a
  // landing's pressure, nor with wake_all's cells still to fail;
  // docs/fast_flows.md, "Gathering steps"). Sessions gather; false: at
  // least one sub-step every step.
  bool gather_steps = false;
  // A channel's side walls, gap_m apart along the grid's y (0: none): the
  // layer rubs on both with Coulomb friction tan(delta_w) under its
  // hydrostatic side pressure, a deceleration tan(delta_w) g h / gap, h the
  // depth the layer moves in (layer_depth) (Jop,
  // Forterre and Pouliquen 2005, "Crucial role of sidewalls in granular
  // surface flows", J. Fluid Mech. 541).
  double side_wall_gap_m = 0.0;
  double side_wall_friction_deg = 0.0;
  // A moving layer erodes the bed beneath it down to the bed friction (the
  // thick layer's, bed_friction_deg, not the thin-layer law's rise; Daerr
  // and Douady 1999); with the soil's bed_start_angle_deg, only what the
  // flow event laid down (with laid_down_holds, not what a slowing layer
  // lays down) and a bed past that angle (docs/fast_flows.md); false: the
  // core holds the repose angle under moving layers too.
  bool erosion = true;
  // The bed friction rises with the layer's inertial number (the soil's
  // rate_friction_angle_deg and rate_friction_i0, terrain/flow_law.h; Jop,
  // Forterre and Pouliquen 2006), read on the depth the layer moves in; on
  // the hard base (floor_friction_deg set) from the floor's stop friction to
  // the same limit with floor_rate_friction_i0 (0: the floor's does not
  // rise), read on the flowing layer. Off by default: the automaton's
  // deposition on shared cells was measured without it and stands in for
  // the friction's rise (docs/fast_flows.md, "The friction at speed"); with
  // owns_cells the layer's own friction has to stop it, or the mean speed's
  // lay-down (the sessions' soils give no grain size to rise with).
  bool rate_friction = false;
  double floor_rate_friction_i0 = 0.0;
  // The depth of grains a moving layer moves in, which the thin-layer law
  // (Pouliquen 1999) and the side walls read (docs/fast_flows.md, "Which
  // depth the layer moves in").
  //   kMobile (the default): the flowing layer and the bed under it that
  //     erosion may take: what the flow event laid down, and the whole loose
  //     depth where the bed the event found stands past the bed's start
  //     angle (or, with no start angle, wherever a layer moves: kWhole's
  //     depth, every bed under a layer eroding). A thin layer
  //     on a deep bed at rest below its start angle so slows at the friction
  //     of its own thickness and stops, the bed at rest (the DEM's erodible
  //     bed, dem/calibration/erodible.in); a collapsing column's layer moves
  //     with the bed it erodes (Edwards and Gray 2015 on erodible beds).
  //   kFlowing: the flowing layer's alone, wherever it runs.
  //   kWhole: the grains' whole loose depth, static and flowing, as a single
  //     layer models an erodible bed (Edwards and Gray 2015), everywhere.
  enum class LayerDepth { kMobile, kFlowing, kWhole };
  LayerDepth layer_depth = LayerDepth::kMobile;
  // Failed material falls freely and lands without horizontal momentum
  // (Larrieu et al. 2006); false: it joins the flowing layer at once.
  bool raining = true;
  // The flow owns its cells (docs/fast_flows.md, "A flow that owns its
  // cells"): the automaton moves nothing out of a cell that holds a flowing
  // layer (GranularGrid::set_held), and a layer that slows lays its base
  // down as bed (its base comes to rest first, as the DEM's collapses and
  // stopping layers show), by `deposition`. false (the default): the
  // automaton acts on the flow's cells too, where it stands in for that
  // deposition. The cells stay held until the flow's step that finds them
  // at rest; a flow dropped while it moves leaves them held.
  bool owns_cells = false;
  // How a slowing layer lays its base down (owns_cells; docs/fast_flows.md,
  // "A layer coming to rest"). A layer of linear profile u = gamma_dot z
  // over its flowing depth h_f (mean speed gamma_dot h_f / 2) whose every
  // depth the forces slow alike:
  //   kInterface (the default): the static/flowing interface rises where
  //     the speed reaches zero (Lusso, Bouchut, Ern and Mangeney 2017), at
  //     dh_f/dt = -a / gamma_dot; the grains laid down had next to no speed,
  //     so the layer keeps its momentum: slowed by the forces from u0 to u
  //     in a sub-step (its mass fixed), it keeps sqrt(u / u0) of its
  //     thickness and moves at sqrt(u0 u). Its mass centre travels
  //     (2/3) u0^2 / a to rest, as the DEM's layers stopping on their own
  //     grains do (dem/calibration/stopping.in).
  //   kMeanSpeed: it keeps u / u0 of its thickness and moves at u, the
  //     laid-down grains taking the mean speed's momentum with them: twice
  //     the interface's rate, its mass centre at rest after u0^2 / (3 a),
  //     half the DEM's travel; kept for the comparison (docs/fast_flows.md).
  enum class Deposition { kInterface, kMeanSpeed };
  Deposition deposition = Deposition::kInterface;
  // What a slowing layer lays down (owns_cells) joins the bed its event
  // found: with the soil's bed start angle, a passing layer erodes it only
  // where it stands past that angle, as it does a bed at rest (the DEM's
  // collapses: the layers that come to rest under the running grains stay
  // at rest, dem/collapse/results/profile_tube_a*.csv's rest_layers;
  // docs/fast_flows.md, "What a layer lays down"). false: the event's own
  // deposits stay erodible down to the bed it found. Nothing changes for a
  // soil with no bed start angle (the sessions' sands).
  bool laid_down_holds = false;
  // Which thin layer (thinner than h_stop, on a bed of grains) a thicker
  // one feeds, so that it flows on instead of lying down
  // (docs/fast_flows.md, "The front's taper"):
  //   kNextCell (the default): a neighbour at least h_stop thick moving
  //     into it: a front tapering over one cell is fed, one tapering over
  //     several is not, so the finer the cells the more of a front lies down.
  //   kTaper: the taper moving into it, followed upstream cell by cell
  //     (each thicker than the last) to a layer at least h_stop thick: the
  //     front of a layer is pushed on by the layer behind it however many
  //     cells it spans, a rule that does not depend on the cell size.
  enum class FrontFeed { kNextCell, kTaper };
  FrontFeed front_feed = FrontFeed::kNextCell;
  int max_substeps = 64;
};

// The flow the sessions run (docs/fast_flows.md, "Which flow the sessions
// run"): owning its cells with the mean speed's lay-down, its fronts fed
// along their taper, what it lays down holding as bed, and gathering
// steps. The sessions' soils give no grain size, hence no thin-layer law
// and no rise of friction with speed; with the interface's lay-down their
// collapses would run 20-51 % past the published law, with the mean
// speed's within 11 % of it. On top of `base` (a case's floor, grains and
// walls: the report runs the DEM's columns with it).
MomentumFlowParameters session_flow_parameters(MomentumFlowParameters base = {});

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

  // Sizes the per-step lists for `cells` examined cells, so that a busy
  // step does not allocate (they otherwise grow to the largest set seen).
  void reserve_cells(std::size_t cells);
  // Examines every cell that holds material once (after the terrain was
  // set up or changed from outside).
  void wake_all(const GranularGrid& grid);
  // One step of step_dt_s: sub-steps as the fastest moving cell asks.
  void step(GranularGrid& grid);
  // `quanta` just landed in `cell` (already in the grid) from a fall, with
  // the velocity it had (m/s; vz < 0 falling): they join the flowing layer
  // with the horizontal momentum, and the cell is examined at the next step.
  // The vertical momentum is lost at the impact (as the rain's), unless the
  // soil's impact_sheet_speed_ratio c is set: then the landing presses on
  // the layer with the momentum it brings, rho w V for w the landed
  // thickness per second and V its fall speed, spread over the time the
  // stream takes to fall two cells, and speeds it up to a stagnation
  // flow's c V r / R at most (r / R from the footprint's middle to its rim:
  // a granular jet on a plate sends its sheet out at c V); the layer under
  // a pressing stream does not lie down. A landing whose sheet would stop
  // within a cell, (c V)^2 < 2 mu g d, does not press (its fall is lost).
  void land(const GranularGrid& grid, int cell, std::int64_t quanta, double vx_m_s, double vy_m_s, double vz_m_s = 0.0);

  double speed_m_s(int cell) const;
  // The velocity at a cell's centre: the mean of its two faces along each axis.
  double velocity_x_m_s(int cell) const;
  double velocity_y_m_s(int cell) const;
  double flowing_m(int cell) const { return flowing_[cell] * kHeightQuantumM; }
  // Whether a landing at vz_m_s presses on the layer: where the sheet it
  // sends out (c V, slowing at mu g on the bed) would cross a cell,
  // (c V)^2 >= 2 mu g d. Such a parcel passes through the flowing layer
  // (and the rain still falling onto it) and lands on the bed under it (a
  // stream meets the bed, its dead zone, and turns the layer on it:
  // docs/fast_flows.md, "Landing"); a slower one (a spill off the bucket's
  // lip onto the face it digs) is under the grid's resolution, lands on
  // the top and loses its fall as rain does.
  bool landing_presses(double vz_m_s) const {
    return impact_c_ > 0.0 && vz_m_s < 0.0 && impact_c_ * impact_c_ * vz_m_s * vz_m_s >= impact_min_sheet2_m2_s2_;
  }
  double raining_m(int cell) const { return rain_[cell] * kHeightQuantumM; }
  std::size_t moving_cells() const { return moving_.size(); }
  // Nothing moving, nothing woken or landed still to move, no landing's
  // pressure (a flow gathering steps may have cells waiting).
  bool at_rest() const { return moving_.empty() && candidates_.empty() && impacted_.empty(); }
  const std::vector<int>& moving() const { return moving_; }
  int last_substeps() const { return last_substeps_; }
  long substeps_run() const { return substeps_run_; }  // since construction
  long pressed_steps() const { return pressed_steps_; }  // steps with a landing's pressure, since construction
  bool pressing() const { return !impacted_.empty(); }   // a landing's pressure has not ended yet
  double bed_friction_tan() const { return mu_; }
  // The bed friction of a layer h_m thick (the soil's thin-layer law; h_m
  // the depth the layer moves in, layer_depth_m) moving at speed_m_s (with
  // rate_friction, its rise with the inertial number).
  double bed_friction_tan(double h_m, double speed_m_s = 0.0) const {
    const double stop = thin_excess_ > 0.0 ? mu_ + thin_excess_ * std::exp(-h_m * inv_decay_m_) : mu_;
    return rate_mu_ > 0.0 ? rate_rise(stop, rate_i0_, h_m, speed_m_s) : stop;
  }
  double floor_friction_tan() const { return floor_mu_ >= 0.0 ? floor_mu_ : mu_; }
  // A flowing layer h_m thick on the hard base, at speed_m_s.
  double floor_friction_tan(double h_m, double speed_m_s) const {
    return rate_mu_ > 0.0 && floor_rate_i0_ > 0.0 ? rate_rise(floor_friction_tan(), floor_rate_i0_, h_m, speed_m_s) : floor_friction_tan();
  }
  double start_friction_tan() const { return mu_start_; }
  double earth_pressure_active() const { return k_active_; }
  double earth_pressure_passive() const { return k_passive_; }
  // Bytes of state per cell: two face velocities, the flowing and raining
  // layers, the rain's speed, the core, the quanta across two faces in a
  // sub-step and four flags; the moving list comes on top (and, with a bed
  // start angle, an impact sheet ratio or the taper's feed, their fields:
  // docs/fast_flows.md).
  static constexpr std::size_t kStateBytesPerCell =
      4 * sizeof(double) + 4 * sizeof(std::int64_t) + 4 * sizeof(std::uint8_t);

 private:
  // Faces: x-face (i, j) lies between cells (i - 1, j) and (i, j), i in
  // [0, nx]; y-face (i, j) between (i, j - 1) and (i, j), j in [0, ny].
  int x_face(int i, int j) const { return j * (nx_ + 1) + i; }
  int y_face(int i, int j) const { return j * nx_ + i; }
  // A cell's faces towards +x, -x, +y, -y, and the velocity on face `face`
  // of such a direction k.
  std::array<int, 4> faces_of(int cell) const;
  double& face_u(int k, int face) { return k < 2 ? ux_face_[face] : uy_face_[face]; }
  // The cells on a face's minus and plus sides (-1 a drop-off, -2 a wall).
  std::pair<int, int> sides(const GranularGrid& grid, int face, bool x) const;
  inline std::pair<int, int> sides_at(const GranularGrid& grid, int i, int j, bool x) const;  // face (i, j)
  void substep(GranularGrid& grid, double dt_s);
  // Puts the examined cells (candidates_, all listed) in raster order.
  void raster_order_candidates();
  void fail(const GranularGrid& grid, double dt_s);
  // fail's core: the chamfer transform over the examined cells (rise_,
  // bed_floor_m_), and with a bed start angle the found beds with it.
  void relax_core(const GranularGrid& grid);
  template <bool kTrack>
  void relax_core_passes(const GranularGrid& grid);
  // Whether a flowing layer of at least h_stop moves into the cell: a
  // neighbour's across a face, or with FrontFeed::kTaper one at the head of
  // the taper moving into it (the passes that change layers read it before
  // they write any: layer_).
  bool fed(const GranularGrid& grid, int cell) const;
  // Starts a pass that reads fed (its layers and faces fixed until it ends).
  void new_feed_pass();
  // The cell's bed (m): its surface less its flowing layer and its rain.
  double bed_m(const GranularGrid& grid, int cell) const;
  // The bed the flow event found under the cell as the failure alone (no
  // erosion) has left it; its bed now outside an event.
  double found_bed_m(const GranularGrid& grid, int cell) const;
  // Whether that bed stands steeper than the bed's start angle above a side
  // neighbour's.
  bool bed_past_start(const GranularGrid& grid, int cell) const;
  // How low erosion may cut under the cell's layer (m; -inf: anywhere),
  // with a bed start angle or without (fail's floor).
  double erosion_floor_m(const GranularGrid& grid, int cell) const;
  // The depth (m) the cell's moving layer, `flowing_m` thick, moves in
  // (MomentumFlowParameters::layer_depth): down to the erosion's floor.
  double layer_depth_m(const GranularGrid& grid, int cell, double flowing_m) const;
  // Whether the cell's layer, `flowing` quanta, rubs on a floor of its own
  // (floor_friction_deg set, no static soil under the layer).
  bool on_floor(const GranularGrid& grid, int cell, std::int64_t flowing) const {
    return floor_mu_ >= 0.0 && grid.loose_quanta(cell) - flowing - rain_[cell] <= 0 && grid.compacted_m(cell) == 0.0;
  }
  // A layer thinner than h_stop on a bed of grains lies down (fail, settle)
  // unless a layer of at least h_stop feeds it; on a floor of its own it
  // slides on until it stops.
  // The layer under a landing's pressure (impact_sheet_speed_ratio) does
  // not lie down.
  bool lies_down(const GranularGrid& grid, int cell, std::int64_t flowing) const {
    return rain_[cell] == 0 && flowing * kHeightQuantumM < min_layer_m_ && !on_floor(grid, cell, flowing) && !fed(grid, cell) &&
           !(!impacted_.empty() && impact_pressure_[cell] > 0.0);
  }
  // The quanta that arrived at face (i, j)'s donor on its minus side (the
  // cell behind it along the axis) or plus side this sub-step, and the
  // momentum along the face's axis they carried (quanta * m/s).
  struct Arrival {
    double quanta = 0.0, momentum = 0.0;
  };
  inline Arrival arrival(int i, int j, bool x, bool plus_side) const;
  void accelerate(const GranularGrid& grid, double dt_s);
  void transport(GranularGrid& grid, double dt_s);
  void carry_momentum(const GranularGrid& grid);
  void settle(const GranularGrid& grid);
  // owns_cells: the layers that slowed in this sub-step lay down their base
  // (slowed_from_ holds the candidates' speeds before it; `deposition`);
  // the cells with a flowing layer held from the automaton until the next
  // step.
  void lay_down_slowed();
  void hold_flowing_cells(GranularGrid& grid);
  void mark(int cell);
  void mark_face(int face, bool x);
  // The speed of a face from the other direction's four faces around it.
  double cross_speed_at_x_face(int i, int j) const;
  double cross_speed_at_y_face(int i, int j) const;

  int nx_ = 0, ny_ = 0;
  double step_dt_s_ = 0.0, d_ = 0.0;
  double thin_excess_ = 0.0, inv_decay_m_ = 0.0;  // tan theta_2 - tan theta_1, 1 / (A d)
  // rate_friction: tan theta_r (0: off), I_0 on the grains and on the floor, the grain diameter (m).
  double rate_mu_ = 0.0, rate_i0_ = 0.0, floor_rate_i0_ = 0.0, rate_grain_m_ = 0.0;
  // mu(h, I) = mu_stop + (tan theta_r - mu_stop) I / (I_0 + I), I = u d / (h sqrt(g h))
  // (terrain/flow_law.h).
  double rate_rise(double mu_stop, double i0, double h_m, double speed_m_s) const;
  double mu_ = 0.0, bed_start_tan_ = 0.0, floor_mu_ = 0.0, mu_start_ = 0.0, min_layer_m_ = 0.0, wall_mu_over_gap_ = 0.0, k_active_ = 1.0, k_passive_ = 1.0, courant_ = 0.4;
  int max_substeps_ = 64, last_substeps_ = 0;
  bool gather_steps_ = false, woken_all_ = false;  // woken_all_: wake_all's cells not yet moved
  double gathered_s_ = 0.0;                         // the time gathered since the flow last moved (s)
  long substeps_run_ = 0, pressed_steps_ = 0;
  bool raining_ = true, erosion_ = true, owns_cells_ = false, taper_feed_ = false;
  MomentumFlowParameters::Deposition deposition_ = MomentumFlowParameters::Deposition::kInterface;
  bool laid_down_holds_ = false;
  std::vector<double> slowed_from_;  // owns_cells: the candidates' speeds before a sub-step (m/s)
  std::vector<double> slowed_to_;    // kInterface: each candidate's face factor h_f / h_f' (1: none laid down)
  std::vector<int> held_;            // owns_cells: the cells held from the automaton
  MomentumFlowParameters::LayerDepth layer_depth_ = MomentumFlowParameters::LayerDepth::kMobile;
  // The landings' impact (land): the sheet speed ratio c; per cell the
  // landed thickness times its fall speed since the last step (m^2/s: the
  // impulse per area over rho) and the landed thickness (m); the pressure
  // over rho they keep up (m^2/s^2), relaxing over the time the stream
  // takes to fall two cells (a stream's landings come in pulses, one per
  // parcel), the sheet speed c V of the last step's landings there (V
  // their mass-weighted mean fall speed) and the cell's
  // distance from its footprint's middle over the footprint's half-width
  // (r / R); the cells under a pressure listed.
  double impact_c_ = 0.0, impact_min_sheet2_m2_s2_ = 0.0;  // land: the slowest sheet that presses, squared
  std::vector<double> landed_m2_s_, landed_m_;  // shape_impacts: landed_m2_s_ holds the shaped pressure
  std::vector<double> impact_pressure_, impact_sheet_m_s_, impact_reach_;
  std::vector<int> impacted_;
  std::vector<int> impact_depth_, impact_scratch_;  // shape_impacts: cells in from a footprint's edge; its lists
  // The landings' pressure over each footprint (the cells under a pressure,
  // 4-connected): a stagnation flow's, highest at its middle and falling to
  // nothing at its edge (1 - (r / R)^2), bearing the landings' whole
  // momentum; the layer under it speeds up to c V r / R at most.
  void shape_impacts();
  std::vector<double> ux_face_, uy_face_;   // m/s on the faces
  std::vector<std::int64_t> flowing_;       // per cell: quanta of its flowing layer (<= its material)
  std::vector<std::uint8_t> listed_, x_listed_, y_listed_;
  std::vector<int> moving_, candidates_, x_faces_, y_faces_;
  // Per sub-step scratch.
  std::vector<std::pair<int, std::int64_t>> new_flowing_;
  std::vector<double> rise_;  // the core's rise over a cell to its side neighbours (m), by candidates_
  std::vector<std::int64_t> layer_;  // a pass's new flowing layers, by candidates_
  std::vector<double> keep_;  // fail: the share of its faces' momentum a cell keeps as rain lands, by candidates_
  std::vector<std::int64_t> rain_;  // per cell: quanta falling freely onto its flowing layer
  std::vector<double> rain_speed_;  // their speed (m/s)
  std::vector<std::uint8_t> fell_;  // its rain has landed in this event
  // Per cell, with a bed start angle: its bed's level (m) when this flow
  // event reached it, lowered where the failure alone (the start angle,
  // not the erosion) lowers it, raised by what a slowing layer lays down
  // with laid_down_holds (NaN: not in an event; an event ends when nothing
  // moves). Erosion cuts below it only where it stands past the bed's
  // start angle.
  std::vector<double> event_bed_m_;
  // FrontFeed::kTaper: per cell the pass its answer was found in and the
  // answer (a pass walks each taper once), and the walk's cells (sized to
  // the grid: the step does not allocate).
  mutable std::vector<std::uint32_t> fed_stamp_;
  mutable std::vector<std::uint8_t> fed_memo_;
  mutable std::vector<int> fed_path_;
  std::uint32_t feed_pass_ = 0;  // fail and settle begin each pass with new_feed_pass, so a pass is >= 1
  std::vector<int> in_event_;  // the cells holding a level
  std::vector<double> bed_floor_m_;  // fail: how low erosion may cut a cell's core, by candidates_
  std::vector<double> core_;  // per cell: the stable core's surface (m), examined cells only
  std::vector<double> new_x_, new_y_;              // the listed faces' new velocities
  std::vector<std::int64_t> x_sent_, y_sent_;       // quanta across each face this sub-step (signed along +x, +y)
};

}  // namespace skidsim::terrain
