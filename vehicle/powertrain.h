// The engine and the two pumps it turns (thesis ch. 9; Buzdugan et al. 1999
// for pump and cylinder): an all-speed governed diesel with a full-load power
// curve; a fixed-displacement implement pump shared by the lift and tilt
// valves; and a hydrostatic drive, one variable pump and motor per side.
// Everything here is plain arithmetic on plain state: no Bullet.
#pragma once

#include <array>

#include "vehicle/loader_description.h"

namespace skidsim::vehicle {

// The operator's controls, each in [-1, 1] (throttle in [0, 1]).
struct LoaderControls {
  double drive_left = 0.0, drive_right = 0.0;  // + forward
  double lift = 0.0;                            // + raises
  double tilt = 0.0;                            // + dumps, - curls back
  double throttle = 1.0;
  bool parking_brake = false;
};

double full_load_power_W(const EngineParameters& e, double speed_rad_s);

// A lever's effect follows the lever no faster than its valve or pump can
// move: `position` goes toward `lever` at 1 / full_travel_s per second (a
// spool opening, a pump's swashplate stroking).
double slew(double position, double lever, double full_travel_s, double dt_s);

// The governor's torque at `speed` for a throttle: full-load torque until
// the droop line, falling to zero at high idle.
double engine_torque_N_m(const EngineParameters& e, double throttle, double speed_rad_s);

// Implement valves: the flow each cylinder gets (m^3/s, + extends) when the
// pump turns at `engine_speed`. Pressure-compensated spools: the flow follows
// the spool, shared in proportion when the spools ask for more than the pump has.
std::array<double, 2> implement_flows_m3_per_s(const ImplementPump& pump, const EngineParameters& e,
                                               double engine_speed_rad_s, double lift, double tilt);

// One side of the hydrostatic drive. The wheel speed follows the pump's
// command (flow) through a stiff servo, its torque bounded by the relief
// valve, and while it drives the wheel also by the engine power the side may
// take (holding and braking cost the engine nothing: no flow).
struct DriveSideCommand {
  double target_speed_rad_s = 0.0;
  double torque_limit_N_m = 0.0;  // relief (holding, braking); the brake's when braked
  // While the motor drives the wheel (torque and speed the same way) the
  // pump can give no more than the engine's power: anti-stall.
  double motoring_torque_limit_N_m = 0.0;
  bool brake = false;  // parking brake: locked up to torque_limit
};

DriveSideCommand drive_side_command(const DriveParameters& d, const EngineParameters& e, double tyre_radius_m,
                                    double engine_speed_rad_s, double command, double power_available_W,
                                    double wheel_speed_rad_s, bool parking_brake);

// Advances a side's wheel speed by dt under the servo (implicit: stable for
// any servo gain) and the tyres' torque on it (`load_torque`, resisting +).
// Returns the motor torque applied.
double advance_drive_side(const DriveParameters& d, const DriveSideCommand& c, double load_torque_N_m, double dt_s,
                          double& wheel_speed_rad_s);

}  // namespace skidsim::vehicle
