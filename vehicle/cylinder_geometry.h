// Hydraulic cylinder geometry: a cylinder pinned to a joint's parent link at
// `parent_pin` and to its child link at `child_pin` has a length that is a
// function of the joint angle; its derivative is the moment arm that turns
// cylinder force into joint torque (tau = F dl/dq) and cylinder speed into
// joint speed (dq/dt = v / (dl/dq)).
#pragma once

#include <Eigen/Geometry>

#include "vehicle/loader_description.h"

namespace skidsim::vehicle {

struct CylinderKinematics {
  double length_m = 0.0;
  double moment_arm_m = 0.0;  // dl/dq, metres per radian (signed)
};

inline CylinderKinematics cylinder_kinematics(const Cylinder& c, const ImplementJoint& j, double q_rad) {
  const Eigen::Vector3d pin_rotated = Eigen::AngleAxisd(q_rad, j.axis) * c.child_pin_m;
  const Eigen::Vector3d child_pin_in_parent = j.origin.apply(pin_rotated);
  const Eigen::Vector3d along = child_pin_in_parent - c.parent_pin_m;
  const Eigen::Vector3d pin_velocity_per_rad = j.origin.rotation * j.axis.cross(pin_rotated);
  CylinderKinematics k;
  k.length_m = along.norm();
  k.moment_arm_m = k.length_m > 0.0 ? along.dot(pin_velocity_per_rad) / k.length_m : 0.0;
  return k;
}

}  // namespace skidsim::vehicle
