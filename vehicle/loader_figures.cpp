#include "vehicle/loader_figures.h"
#include "common/physical_constants.h"

#include <cmath>

#include "vehicle/cylinder_geometry.h"

namespace skidsim::vehicle {
namespace {


Eigen::Isometry3d joint_transform(const ImplementJoint& j, double q) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = (j.origin.rotation * Eigen::AngleAxisd(q, j.axis)).toRotationMatrix();
  t.translation() = j.origin.position_m;
  return t;
}

// Seconds for a cylinder to run its joint's whole range on the full pump flow.
double stroke_time(const LoaderDescription& d, const Cylinder& c, bool extending) {
  const ImplementJoint& j = d.joints[c.joint];
  const double stroke = std::abs(cylinder_kinematics(c, j, j.upper_rad).length_m -
                                 cylinder_kinematics(c, j, j.lower_rad).length_m);
  const double area = extending ? c.piston_area_m2() : c.annulus_area_m2();
  return stroke * area / d.implement_pump.flow_at_rated_m3_per_s;
}

}  // namespace

Eigen::Isometry3d implement_link_frame(const LoaderDescription& d, int link, double lift_rad, double tilt_rad) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  if (link >= 1) t = t * joint_transform(d.joints[0], lift_rad);
  if (link >= 2) t = t * joint_transform(d.joints[1], tilt_rad);
  return t;
}

double rating_lift_angle(const LoaderDescription& d) {
  const ImplementJoint& arm = d.joints[0];
  double best_q = arm.lower_rad, best_x = -1e300;
  for (int k = 0; k <= 2000; ++k) {
    const double q = arm.lower_rad + (arm.upper_rad - arm.lower_rad) * k / 2000.0;
    const double x = implement_link_frame(d, 2, q, 0.0).translation().x();
    if (x > best_x) {
      best_x = x;
      best_q = q;
    }
  }
  return best_q;
}

LoaderFigures loader_figures(const LoaderDescription& d) {
  LoaderFigures f;
  f.mass_kg = d.total_mass_kg();
  // Bucket level at the rating reach: its pitch in the chassis frame is zero.
  const double lift = rating_lift_angle(d);
  double tilt = 0.0;
  {
    // Solve pitch(bucket) = 0 for the tilt angle (one dimension, bisection).
    auto pitch = [&](double q) {
      const Eigen::Matrix3d r = implement_link_frame(d, 2, lift, q).linear();
      return std::atan2(-r(2, 0), r(0, 0));
    };
    double lo = d.joints[1].lower_rad, hi = d.joints[1].upper_rad;
    if (pitch(lo) * pitch(hi) < 0.0) {
      for (int k = 0; k < 60; ++k) {
        const double mid = 0.5 * (lo + hi);
        (pitch(lo) * pitch(mid) <= 0.0 ? hi : lo) = mid;
      }
      tilt = 0.5 * (lo + hi);
    }
  }
  // Moment balance about the front axle's contact line (rigid tyres: the
  // contact under the hub).
  double front_x = -1e300;
  for (const Wheel& w : d.wheels) front_x = std::max(front_x, w.hub_m.x());
  double restoring = 0.0;
  for (size_t l = 0; l < d.links.size(); ++l) {
    const double x = (implement_link_frame(d, static_cast<int>(l), lift, tilt) * d.links[l].com.position_m).x();
    restoring += d.links[l].mass_kg * (front_x - x);
  }
  const double load_x = (implement_link_frame(d, static_cast<int>(d.links.size()) - 1, lift, tilt) * d.bucket_load_centre_m).x();
  f.static_tipping_load_kg = restoring / (load_x - front_x);
  f.rated_operating_capacity_kg = 0.5 * f.static_tipping_load_kg;
  const ImplementJoint& arm = d.joints[0];
  f.hinge_pin_height_m = d.tyre.radius_m + implement_link_frame(d, 2, arm.upper_rad, 0.0).translation().z();
  f.arm_travel_deg = (arm.upper_rad - arm.lower_rad) * 180.0 / kPi;
  for (const Cylinder& c : d.cylinders) {
    // Which way the cylinder moves to raise / dump: the sign of its moment arm.
    const bool grows = cylinder_kinematics(c, d.joints[c.joint], 0.5 * (d.joints[c.joint].lower_rad + d.joints[c.joint].upper_rad)).moment_arm_m > 0.0;
    const double up = stroke_time(d, c, grows), down = stroke_time(d, c, !grows);
    if (c.joint == 0) {
      f.lift_time_s = up;
      f.lower_time_s = down;
    } else {
      f.dump_time_s = up;
      f.curl_time_s = down;
    }
  }
  f.top_speed_km_h = 3.6 * d.drive.top_speed_m_per_s;
  const double side_torque = d.drive.relief_pressure_Pa * d.drive.motor_displacement_m3_per_rad *
                             d.drive.final_drive_ratio * d.drive.efficiency;
  f.push_force_kN = 2.0 * side_torque / d.tyre.radius_m / 1e3;
  return f;
}

}  // namespace skidsim::vehicle
