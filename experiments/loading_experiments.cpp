#include "experiments/loading_experiments.h"

#include <algorithm>
#include <cmath>

#include "terrain/body_shapes.h"
#include "terrain/soil_contact.h"
#include "terrain/wheel_contact.h"
#include "experiments/translating_body.h"

namespace skidsim::terrain {

SoilMechanics plate_test_soil(double n) {
  SoilMechanics s;
  s.n = n;
  s.k_c_kN_per_m_n1 = 0.0;
  s.k_phi_kN_per_m_n2 = 1000.0 * kGravity_m_s2 / std::pow(0.15, n) / 1000.0;
  return s;
}

double bekker_plate_depth_m(const SoilMechanics& soil, double mass_kg) {
  return std::pow(mass_kg * kGravity_m_s2 / bekker_modulus_Pa(soil, 1.0), 1.0 / soil.n);
}

PlateLoadingRun run_plate_loading(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double layer_top_m,
                                  double step_dt_s) {
  constexpr double kHalfThickness = 0.05;
  SoilContactModel model(grid, soil);
  OrientedBox plate;
  plate.half_extents_m = {0.5, 0.5, kHalfThickness};
  TranslatingBody body;
  body.mass_kg = mass_kg;
  body.position_m = {0.8137, 0.7731, layer_top_m + kHalfThickness};  // off the cell edges
  BodyReaction r;
  const int max_steps = static_cast<int>(std::lround(10.0 / step_dt_s));
  int still_steps = 0, step = 0;
  for (; step < max_steps && still_steps < 100; ++step) {
    const double t = step * step_dt_s;
    still_steps = t > 1.0 && std::abs(body.velocity_m_s.z()) < 2e-6 ? still_steps + 1 : 0;
    plate.centre_m = body.position_m;
    r = model.interact(0, plate, body.motion());
    body.step(r, {0.0, 0.0, -mass_kg * kGravity_m_s2 * std::min(1.0, t / 1.0)}, step_dt_s);
    grid.step();
  }
  return {layer_top_m - (body.position_m.z() - kHalfThickness), std::abs(body.velocity_m_s.z()), r.force_N.z(),
          step * step_dt_s};
}

double bekker_rigid_wheel_depth_m(const SoilMechanics& soil, double load_N, double radius_m, double width_m) {
  const double k_Pa_per_m_n = 1000.0 * (soil.k_c_kN_per_m_n1 + width_m * soil.k_phi_kN_per_m_n2);
  return std::pow(3.0 * load_N / ((3.0 - soil.n) * k_Pa_per_m_n * std::sqrt(2.0 * radius_m)), 2.0 / (2.0 * soil.n + 1.0));
}

WheelLoadingRun run_rigid_wheel(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double radius_m,
                                double width_m, double speed_m_s, double layer_top_m, double step_dt_s) {
  SoilContactModel model(grid, soil);
  Cylinder wheel;
  wheel.radius_m = radius_m;
  wheel.half_width_m = 0.5 * width_m;
  const Eigen::Vector2d start_m(0.6137, 0.7871);  // off the cell edges
  TranslatingBody body;
  body.mass_kg = mass_kg;
  body.position_m = {start_m.x(), start_m.y(), layer_top_m + radius_m};
  const int steps = static_cast<int>((speed_m_s > 0.0 ? 2.8 / speed_m_s : 6.0) / step_dt_s);
  for (int step = 0; step < steps; ++step) {
    const double t = step * step_dt_s;
    wheel.centre_m = body.position_m;
    BodyMotion motion = body.motion();
    motion.linear_velocity_m_s.x() = speed_m_s;
    motion.angular_velocity_rad_s = {0.0, speed_m_s / radius_m, 0.0};  // rolling: the lowest point is still
    const BodyReaction r = model.interact(0, wheel, motion);
    body.step(r, {0.0, 0.0, -mass_kg * kGravity_m_s2 * std::min(1.0, t / 1.0)}, step_dt_s);
    body.velocity_m_s.x() = speed_m_s;  // towed
    body.velocity_m_s.y() = 0.0;
    body.position_m.x() = start_m.x() + speed_m_s * (t + step_dt_s);
    body.position_m.y() = start_m.y();
    grid.step();
  }
  return {layer_top_m - (body.position_m.z() - radius_m), steps * step_dt_s};
}

SoftWheelRun run_soft_wheel(GranularGrid& grid, const SoilMechanics& soil, double mass_kg, double radius_m,
                            double width_m, double slip, double speed_m_s, double travel_m, double layer_top_m,
                            double step_dt_s, double rim_friction_angle_rad) {
  SoilContactModel model(grid, soil);
  model.set_press_only(0, true);
  Cylinder rim;
  rim.radius_m = radius_m;
  rim.half_width_m = 0.5 * width_m;
  WheelOnGrid wheel;
  wheel.shape = {radius_m, width_m, 0.0, rim_friction_angle_rad};
  WheelContactState state;
  const bool towed = std::isnan(slip);
  const double spin_inertia = 0.5 * mass_kg * radius_m * radius_m;
  // Driven, r omega = v / (1 - s); braked (s < 0), r omega = v (1 + s): the
  // slip (r omega - v) / max(r omega, v) the wheel model takes.
  double omega = towed ? speed_m_s / radius_m
                       : (slip >= 0.0 ? speed_m_s / (radius_m * (1.0 - slip)) : speed_m_s * (1.0 + slip) / radius_m);
  double z = layer_top_m + radius_m, vz = 0.0;
  const Eigen::Vector2d start_m(0.6137, 0.7871);  // off the cell edges
  const double damping = 1000.0 * soil.damping_kPa_s_per_m;
  const int steps = static_cast<int>(std::lround(travel_m / speed_m_s / step_dt_s));
  const int averaged_from = static_cast<int>(0.6 * steps);
  SoftWheelRun out;
  for (int step = 0; step < steps; ++step) {
    const double t = step * step_dt_s;
    const double x = start_m.x() + speed_m_s * t;
    wheel.hub_m = {x, start_m.y(), z};
    const double rolling = omega * radius_m;
    const double s = (rolling - speed_m_s) / std::max({rolling, speed_m_s, 1e-9});
    const WheelGridForces f = wheel_on_grid(grid, model, 0, wheel, s, state);
    // The rut: the wheel's contact map presses the soil it covers.
    rim.centre_m = wheel.hub_m;
    BodyMotion motion;
    motion.reference_point_m = rim.centre_m;
    motion.linear_velocity_m_s = {speed_m_s, 0.0, vz};
    motion.angular_velocity_rad_s = {0.0, omega, 0.0};
    model.interact(0, rim, motion, false);
    // Vertical: the soil's W with Chrono SCM's viscous part over the
    // contact, semi-implicit; the spin of a towed wheel under the soil's torque.
    const double weight = mass_kg * kGravity_m_s2 * std::min(1.0, t / 0.5);
    const double c = damping * f.contact_length_m * width_m;
    vz = (mass_kg * vz + step_dt_s * (f.vertical_N - weight)) / (mass_kg + step_dt_s * c);
    z += step_dt_s * vz;
    if (towed) omega = std::max(0.0, omega - step_dt_s * f.drive_torque_Nm / spin_inertia);
    advance_wheel_contact(speed_m_s * step_dt_s, speed_m_s * step_dt_s, f.contact_length_m, state);
    grid.step();
    if (step >= averaged_from) {
      const double n = steps - averaged_from;
      out.sinkage_m += (layer_top_m - (z - radius_m)) / n;
      out.drawbar_pull_N += f.forward_N / n;
      out.drive_torque_Nm += f.drive_torque_Nm / n;
      out.slip += s / n;
      out.vertical_N += f.vertical_N / n;
    }
  }
  out.simulated_s = steps * step_dt_s;
  return out;
}

}  // namespace skidsim::terrain
