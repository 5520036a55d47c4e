// What a loader description implies on paper, without simulating it: its
// implement's forward kinematics, and the figures of a specification sheet
// (static tipping load by moment balance, rated operating capacity, cycle
// times from flow and piston area, travel speed, push force). `skidsim check`
// prints them; the tests compare the simulation with them.
#pragma once

#include <Eigen/Geometry>

#include "vehicle/loader_description.h"

namespace skidsim::vehicle {

// Frame of link `link` (0 chassis, 1 lift arm, 2 bucket) in the chassis
// frame, for the lift and tilt joint angles.
Eigen::Isometry3d implement_link_frame(const LoaderDescription& d, int link, double lift_rad, double tilt_rad);

// SAE J818 rates a loader with its hinge pin at the farthest forward reach:
// the lift angle that puts it there.
double rating_lift_angle(const LoaderDescription& d);

struct LoaderFigures {
  double mass_kg = 0.0;
  double static_tipping_load_kg = 0.0;  // at the load centre, arm at rating reach, bucket level, rigid tyres
  double rated_operating_capacity_kg = 0.0;  // 50 % of the tipping load (wheeled skid steers)
  double hinge_pin_height_m = 0.0;      // fully raised, standing on its tyres
  double arm_travel_deg = 0.0;
  double lift_time_s = 0.0, lower_time_s = 0.0;  // full arm travel at rated engine speed
  double dump_time_s = 0.0, curl_time_s = 0.0;   // full bucket travel
  double top_speed_km_h = 0.0;
  double push_force_kN = 0.0;           // both sides at drive relief
};

LoaderFigures loader_figures(const LoaderDescription& d);

}  // namespace skidsim::vehicle
