#include "vehicle/powertrain.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>

namespace skidsim::vehicle {
namespace {
constexpr double kRpmToRadS = 2.0 * kPi / 60.0;
}

double full_load_power_W(const EngineParameters& e, double speed_rad_s) {
  const double rpm = speed_rad_s / kRpmToRadS;
  const auto& x = e.speed_rpm;
  const auto& y = e.full_load_power_W;
  if (rpm <= x.front()) return y.front() * std::max(0.0, rpm / x.front());
  if (rpm >= x.back()) return y.back();
  const size_t i = static_cast<size_t>(std::upper_bound(x.begin(), x.end(), rpm) - x.begin());
  const double t = (rpm - x[i - 1]) / (x[i] - x[i - 1]);
  return y[i - 1] + t * (y[i] - y[i - 1]);
}

double slew(double position, double lever, double full_travel_s, double dt_s) {
  lever = std::clamp(lever, -1.0, 1.0);
  if (!(full_travel_s > 0.0)) return lever;
  const double step = dt_s / full_travel_s;
  return position + std::clamp(lever - position, -step, step);
}

double engine_torque_N_m(const EngineParameters& e, double throttle, double speed_rad_s) {
  if (speed_rad_s <= 0.0) return 0.0;
  const double idle = e.idle_rpm * kRpmToRadS, rated = e.rated_rpm * kRpmToRadS;
  const double set = idle + std::clamp(throttle, 0.0, 1.0) * (rated - idle);
  // Droop governor: full fuel at the set speed, none droop*rated above it.
  const double fuel = std::clamp((set + e.governor_droop * rated - speed_rad_s) / (e.governor_droop * rated), 0.0, 1.0);
  return fuel * full_load_power_W(e, speed_rad_s) / speed_rad_s;
}

std::array<double, 2> implement_flows_m3_per_s(const ImplementPump& pump, const EngineParameters& e,
                                               double engine_speed_rad_s, double lift, double tilt) {
  const double pump_flow = pump.flow_at_rated_m3_per_s * std::max(0.0, engine_speed_rad_s) / (e.rated_rpm * kRpmToRadS);
  lift = std::clamp(lift, -1.0, 1.0);
  tilt = std::clamp(tilt, -1.0, 1.0);
  const double asked = std::abs(lift) + std::abs(tilt);
  const double share = asked > 1.0 ? 1.0 / asked : 1.0;
  return {lift * share * pump_flow, tilt * share * pump_flow};
}

DriveSideCommand drive_side_command(const DriveParameters& d, const EngineParameters& e, double tyre_radius_m,
                                    double engine_speed_rad_s, double command, double power_available_W,
                                    double wheel_speed_rad_s, bool parking_brake) {
  DriveSideCommand c;
  if (parking_brake) {
    c.target_speed_rad_s = 0.0;
    c.torque_limit_N_m = c.motoring_torque_limit_N_m = d.brake_torque_N_m;
    c.brake = true;
    return c;
  }
  // Pump displacement follows the lever; its flow, the engine speed. Top
  // speed is the spec sheet's: full lever at high idle (light load).
  const double high_idle = e.rated_rpm * kRpmToRadS * (1.0 + e.governor_droop);
  const double speed_fraction = std::max(0.0, engine_speed_rad_s) / high_idle;
  c.target_speed_rad_s = std::clamp(command, -1.0, 1.0) * speed_fraction * d.top_speed_m_per_s / tyre_radius_m;
  const double relief_torque = d.relief_pressure_Pa * d.motor_displacement_m3_per_rad * d.final_drive_ratio * d.efficiency;
  // Power limiting (anti-stall): no more than the engine can give this side.
  const double speed_floor = 0.05 * d.top_speed_m_per_s / tyre_radius_m;
  const double power_torque = d.efficiency * std::max(0.0, power_available_W) /
                              std::max(std::abs(wheel_speed_rad_s), speed_floor);
  c.torque_limit_N_m = relief_torque;
  c.motoring_torque_limit_N_m = std::min(relief_torque, power_torque);
  return c;
}

double advance_drive_side(const DriveParameters& d, const DriveSideCommand& c, double load_torque_N_m, double dt_s,
                          double& wheel_speed_rad_s) {
  const double J = d.side_inertia_kg_m2, K = d.servo_gain_N_m_s;
  // The parking brake locks the side mechanically (no servo droop, no creep)
  // until the tyres' torque exceeds what it holds.
  if (c.brake) {
    if (std::abs(wheel_speed_rad_s) < 1e-9 && std::abs(load_torque_N_m) <= c.torque_limit_N_m) {
      wheel_speed_rad_s = 0.0;
      return load_torque_N_m;
    }
    const double torque = -std::copysign(c.torque_limit_N_m, wheel_speed_rad_s != 0.0 ? wheel_speed_rad_s : -load_torque_N_m);
    const double w = wheel_speed_rad_s + dt_s * (torque - load_torque_N_m) / J;
    // Friction stops the wheel; it does not turn it back.
    wheel_speed_rad_s = (w * wheel_speed_rad_s < 0.0 || wheel_speed_rad_s == 0.0) &&
                                std::abs(load_torque_N_m) <= c.torque_limit_N_m
                            ? 0.0
                            : w;
    return torque;
  }
  // Implicit servo: J (w1 - w0) = dt (K (target - w1) - load).
  const double w1 = (J * wheel_speed_rad_s + dt_s * (K * c.target_speed_rad_s - load_torque_N_m)) / (J + dt_s * K);
  double torque = K * (c.target_speed_rad_s - w1);
  // Driving the wheel (torque along its turning) is bounded by the engine's
  // power too; holding and braking by relief only.
  const bool motoring = torque * wheel_speed_rad_s > 0.0;
  const double limit = motoring ? c.motoring_torque_limit_N_m : c.torque_limit_N_m;
  if (std::abs(torque) <= limit) {
    wheel_speed_rad_s = w1;
    return torque;
  }
  torque = std::copysign(limit, torque);
  wheel_speed_rad_s += dt_s * (torque - load_torque_N_m) / J;
  // A saturated servo still cannot drive the wheel past its target.
  if ((torque > 0.0 && wheel_speed_rad_s > c.target_speed_rad_s) ||
      (torque < 0.0 && wheel_speed_rad_s < c.target_speed_rad_s))
    wheel_speed_rad_s = c.target_speed_rad_s;
  return torque;
}

}  // namespace skidsim::vehicle
