// The loader as data: what the URDF (links, joints, inertias, collision boxes,
// visual meshes) and its parameter side file (cylinders, pumps, engine, drive,
// tyres) say about the machine. Plain structs, no Bullet: io/loader_files.cpp
// fills them, vehicle/loader_multibody.cpp turns them into a btMultiBody.
//
// Frames: z up, x forward. Every pose is of a child frame in its parent's
// frame. The chassis link frame sits midway between the axles, at axle height.
#pragma once

#include "common/physical_constants.h"
#include <Eigen/Geometry>

#include <array>
#include <string>
#include <vector>

namespace skidsim::vehicle {

struct Pose {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero();
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();
  Eigen::Vector3d apply(const Eigen::Vector3d& p) const { return position_m + rotation * p; }
};

struct CollisionBox {
  Pose pose;  // in the link frame
  Eigen::Vector3d half_extents_m = Eigen::Vector3d::Zero();
};

// A triangle mesh read by assimp (vertices in the link frame, scale applied).
struct VisualMesh {
  std::string path;  // absolute
  Pose pose;         // in the link frame
  std::vector<Eigen::Vector3f> vertices_m;
  std::vector<std::array<unsigned, 3>> triangles;
};

struct RigidLink {
  std::string name;
  double mass_kg = 0.0;
  Pose com;                                       // centre of mass frame in the link frame
  Eigen::Vector3d principal_inertia_kg_m2 = Eigen::Vector3d::Zero();  // about `com` axes
  std::vector<CollisionBox> collision;
  std::vector<VisualMesh> visuals;
  int urdf_line = 0;
};

// A revolute joint of the implement (lift arm, bucket): child link `child`
// turns about `axis` (unit, in the joint frame) through [lower, upper].
struct ImplementJoint {
  std::string name;
  Pose origin;  // joint frame in the parent link frame (child link frame at q = 0)
  Eigen::Vector3d axis = Eigen::Vector3d::UnitY();
  double lower_rad = 0.0, upper_rad = 0.0;
  int urdf_line = 0;
};

// A hydraulic cylinder between a pin on the joint's parent link and a pin on
// its child link (both in their link frames). Its length sets the joint angle.
struct Cylinder {
  std::string name;
  int joint = -1;  // index into LoaderDescription::joints
  Eigen::Vector3d parent_pin_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d child_pin_m = Eigen::Vector3d::Zero();
  double bore_m = 0.0, rod_m = 0.0;
  double min_length_m = 0.0, max_length_m = 0.0;  // pin to pin, fully retracted / extended
  double relief_pressure_Pa = 0.0;
  int line = 0;
  double piston_area_m2() const { return 0.25 * kPi * bore_m * bore_m; }
  double annulus_area_m2() const {
    return piston_area_m2() - 0.25 * kPi * rod_m * rod_m;
  }
};

// Diesel engine: full-load power against speed (a table), all-speed governor.
struct EngineParameters {
  std::vector<double> speed_rpm;  // ascending
  std::vector<double> full_load_power_W;
  double idle_rpm = 0.0, rated_rpm = 0.0;
  double inertia_kg_m2 = 0.0;     // crank, flywheel and pumps
  double governor_droop = 0.0;    // fraction of rated speed from no load to full load
  double friction_torque_N_m = 0.0;  // friction and accessories, against the crank
};

// A fixed-displacement gear pump for the implement (lift and tilt share it).
struct ImplementPump {
  double flow_at_rated_m3_per_s = 0.0;
  double efficiency = 1.0;
  double spool_time_s = 0.0;  // a valve spool's travel from closed to fully open
};

// Hydrostatic drive, one pump and motor per side; both wheels of a side are
// chained (same speed).
struct DriveParameters {
  double top_speed_m_per_s = 0.0;  // full lever, engine at high idle
  double relief_pressure_Pa = 0.0;
  double motor_displacement_m3_per_rad = 0.0;  // motor displacement / (2 pi)
  double final_drive_ratio = 1.0;              // motor turns per wheel turn
  double efficiency = 1.0;
  double side_inertia_kg_m2 = 0.0;             // both wheels, chains and motor, at the wheel
  double servo_gain_N_m_s = 0.0;               // flow servo stiffness, at the wheel
  double brake_torque_N_m = 0.0;               // per side, parking brake
  double pump_stroke_time_s = 0.0;             // swashplate from zero to full displacement
};

// Tyre: Magic Formula (Pacejka) with combined-slip weighting, a first-order
// contact-patch deflection (relaxation length) for smooth standstill, and a
// radial spring on firm ground.
struct TyreParameters {
  double radius_m = 0.0, width_m = 0.0;
  double radial_stiffness_N_per_m = 0.0, radial_damping_N_s_per_m = 0.0;
  double relaxation_x_m = 0.0, relaxation_y_m = 0.0;
  double low_speed_damping_N_s_per_m = 0.0;  // below low_speed_m_per_s only
  double low_speed_m_per_s = 0.0;
  // Pure slip: F = D sin(C atan(B s - E (B s - atan(B s)))), D = mu Fz.
  double Bx = 0, Cx = 0, Ex = 0, mu_x = 0;
  double By = 0, Cy = 0, Ey = 0, mu_y = 0;
  // Combined slip weighting: G = cos(C atan(B s)), B = r1 cos(atan(r2 s_other)).
  double rBx1 = 0, rBx2 = 0, Cxa = 1;
  double rBy1 = 0, rBy2 = 0, Cyk = 1;
  double rolling_resistance = 0.0;  // coefficient on firm ground
  // On soft soil the carcass flattens where the soil would press it harder
  // than the inflation pressure and the carcass's own stiffness (Wong,
  // Theory of Ground Vehicles, 2008, 2.7.2, p_i + p_c); 0: a rigid wheel.
  double inflation_pressure_Pa = 0.0;
  double carcass_pressure_Pa = 0.0;
  double ground_pressure_limit_Pa() const {
    return inflation_pressure_Pa > 0.0 ? inflation_pressure_Pa + carcass_pressure_Pa : 0.0;
  }
};

struct Wheel {
  std::string name;
  Eigen::Vector3d hub_m = Eigen::Vector3d::Zero();  // in the chassis frame
  int side = 0;  // 0 left, 1 right
  std::vector<VisualMesh> visuals;  // in the wheel frame (axle along y)
};

// The inside of the bucket, for the automaton that carries its load (thesis
// 6.4.1, terrain/body_automaton.h). The container frame has the bucket
// link's axes (x towards the cutting edge, y across, z up from the floor
// with the bucket level) and its origin at the floor's back corner.
struct BucketInterior {
  bool present = false;
  Eigen::Vector3d origin_m = Eigen::Vector3d::Zero();  // in the bucket link frame
  double length_m = 0.0;   // back wall to cutting edge, walls included
  double width_m = 0.0;    // side plate to side plate
  double back_height_m = 0.0;
  double side_height_front_m = 0.0;  // side plates' top above the floor at the cutting edge
  double heel_radius_m = 0.0;
  double plate_thickness_m = 0.04;   // floor and back plates, for their contact with the soil
  double cutting_edge_length_m = 0.25;  // the strip of floor behind the edge that rides the cut
  double bottom_clearance_rad = 0.14;   // its bottom's rise towards the heel
  // The edge's blunt face across its travel, which bears on the soil ahead
  // (terrain/edge_penetration.h): a worn bolt-on edge's tip.
  double cutting_edge_thickness_m = 0.02;
  // Filling (6.4.2): the mouth chokes (the edge pushes instead of slicing)
  // once the bucket holds its heaped capacity; the repose angle on the
  // bucket drops while material slides in; in a soil cut by the thesis's
  // wedge an empty bucket's slicing edge meets this share of the blade's
  // wedge, a full one all of it (the earthmoving soils bear on the edge
  // instead: cutting_edge_thickness_m).
  double heaped_volume_m3 = 0.38;
  double filling_angle_drop_deg = 8.0;
  double edge_resistance = 0.2;
  // The load-spreading kernel (6.5) for the load on the bucket.
  double spreading_eps = 0.4;
  double spreading_block_cells = 1.5;
};

struct LoaderDescription {
  std::string urdf_path, parameters_path;
  // links[0] is the chassis (floating base), then one link per joint, each
  // child of an earlier one (lift arm, bucket).
  std::vector<RigidLink> links;
  std::vector<ImplementJoint> joints;   // joints[i] moves links[i + 1]
  std::vector<int> joint_parent_link;   // index into links
  std::vector<Cylinder> cylinders;
  std::vector<Wheel> wheels;
  EngineParameters engine;
  ImplementPump implement_pump;
  DriveParameters drive;
  TyreParameters tyre;
  // Where the bucket's payload sits (in the bucket link frame) and how much
  // a struck-full bucket holds: used by the tipping and rating checks.
  Eigen::Vector3d bucket_load_centre_m = Eigen::Vector3d::Zero();
  double bucket_volume_m3 = 0.0;
  BucketInterior bucket_interior;
  double total_mass_kg() const {
    double m = 0.0;
    for (const RigidLink& l : links) m += l.mass_kg;
    return m;
  }
  int link_index(const std::string& name) const {
    for (size_t i = 0; i < links.size(); ++i)
      if (links[i].name == name) return static_cast<int>(i);
    return -1;
  }
};

}  // namespace skidsim::vehicle
