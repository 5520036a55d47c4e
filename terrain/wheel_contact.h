// A wheel on the terrain grid by the Wong-Reece theory (terrain/wheel_soil.h,
// docs/soil_contact.md "Wheels"): the grid gives the level of the soil where
// the wheel's contact begins and the history of the soil there; the theory
// gives the stresses, integrated over the contact rather than summed over
// cells, so the forces do not depend on the cell size beyond that level.
// The wheel's contact map still presses its rut into the grid
// (SoilContactModel::interact); its own forces are not used for a wheel.
#pragma once

#include <Eigen/Core>

#include "terrain/granular_grid.h"
#include "terrain/soil_contact.h"
#include "terrain/wheel_soil.h"

namespace skidsim::terrain {

struct WheelOnGrid {
  Eigen::Vector3d hub_m = Eigen::Vector3d::Zero();
  Eigen::Vector2d heading = Eigen::Vector2d::UnitX();  // the wheel plane's forward, horizontal, unit
  WheelShape shape;
};

// What a wheel remembers of its contact between steps.
struct WheelContactState {
  // Which side of the contact carries the load, -1 (backwards) .. +1
  // (forwards): a rolling wheel loads the soil ahead of it and leaves the
  // soil behind unloaded; it changes over about half a contact length of
  // travel, so a wheel at rest keeps the contact it stopped with (no
  // jitter) and one lowered onto the soil starts level (0).
  double lead = 0.0;
  // The soil met ahead on either side (forwards, backwards), as read from
  // the grid and followed over travel: the level of its surface and how far
  // loads had lowered it. A wheel at rest keeps what it met (the cells at the
  // edge of its contact change hands step to step; the soil it stands on
  // does not), a rolling one takes the new reading within a few cm of travel.
  struct SideMemory {
    bool set = false;
    double level_m = 0.0;
    double lowering_m = 0.0;
  };
  SideMemory side[2];
  double last_moved_m = 0.0;  // the hub's horizontal travel past the rut's play, the last step
  double play_m = 0.0;        // where the hub stands in its rut's play along the heading
  // The share of the contact that lies on soil (follow_soil_share), or -1
  // while the wheel is off the soil.
  double soil_share = -1.0;
};

struct WheelGridForces {
  bool in_soil = false;
  double vertical_N = 0.0;
  double forward_N = 0.0;       // along `heading`
  double drive_torque_Nm = 0.0; // what the soil resists a forward spin with
  double sinkage_m = 0.0;       // the lowest point below the soil ahead (load-weighted over the sides)
  double contact_length_m = 0.0;
  double shear_strength_N = 0.0;
  int cell = -1;                // the cell under the hub (its soil region)
};

// The wheel's sinkage below the soil's surface at the front of its contact
// along `direction`: the surface read from the first two cells ahead that
// the rim does not reach below their surface and the wheel's contact map
// (`body_id` in `model`) did not press last step (cells the wheel is not
// pressing, whatever the cell size and heading), extrapolated back along
// their slope to where the rim meets it (so a wheel climbing a slope meets
// the surface at its entry, not a cell above it); averaged over lines
// across the width. False where no soil lies ahead.
struct SoilAhead {
  double sinkage_m = 0.0;
  int cell = -1;  // the first cell ahead on the middle line: its rut history
};
bool soil_level_ahead(const GranularGrid& grid, const SoilContactModel& model, int body_id,
                      const Eigen::Vector3d& hub_m, const Eigen::Vector2d& direction, double radius_m, double width_m,
                      SoilAhead* ahead);

// The soil's force on a wheel at `slip_forward` ((r omega - v) / max(...)
// in the heading's sense: positive driving forwards). Both sides of the
// contact are weighted by `state.lead`; advance the state with
// advance_wheel_contact after the step.
WheelGridForces wheel_on_grid(const GranularGrid& grid, const SoilContactModel& model, int body_id,
                              const WheelOnGrid& wheel, double slip_forward, WheelContactState& state);

// After the step: moves the loaded side towards the travel (`travel_m`
// along the heading, taken through a play of +-5 % of the contact in the
// rut; exact
// exponential approach over half the contact length) and notes how far the
// hub moved over the ground past that play (`moved_m`, horizontally, any
// direction) for the side memories.
void advance_wheel_contact(double travel_m, double moved_m, double contact_length_m, WheelContactState& state);

// The share of a wheel's contact that lies on soil: its footprint (the
// contact's length along the heading, centred under the hub, by the width)
// sampled at 8 x 3 points, each counting the soil under it up to 1 cm deep
// (a bare or thinly covered base, or ground off the grid, is firm ground
// the tyre meets through the engine's contact tests). It depends on where
// the wheel stands, not on which cells its contact map holds this step
// (measured from those, a standing wheel's share flickered as the cells at
// the edge of its contact changed hands: a parked machine shook).
double soil_share_under(const GranularGrid& grid, const WheelOnGrid& wheel, double contact_length_m);

// Followed over travel (the side memories' exponential approach), so a
// wheel rolling onto the soil from firm ground hands its load over smoothly;
// the first measure after the wheel was off the soil is taken as it is.
double follow_soil_share(double measured, WheelContactState& state);

// Off the soil: the next contact starts its share afresh.
inline void forget_soil_share(WheelContactState& state) { state.soil_share = -1.0; }

}  // namespace skidsim::terrain
