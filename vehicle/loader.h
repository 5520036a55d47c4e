// The loader in Bullet: a Featherstone multibody (floating chassis, revolute
// lift arm and bucket) built from a LoaderDescription, with the hydraulics,
// the hydrostatic drive and the tyres that move it. Each 2 ms step the engine
// calls pre_step (controls -> cylinder motor targets and force bounds, drive,
// tyre forces applied to the chassis), steps the Bullet world, then
// post_step (reads back what the cylinders applied).
//
// The wheels are massless discs lumped into the chassis (thesis ch. 9); their
// spin is the drive's state, one speed per side (both wheels chained).
#pragma once

#include <Eigen/Geometry>
#include <LinearMath/btAlignedObjectArray.h>
#include <LinearMath/btVector3.h>

#include <array>
#include <memory>
#include <vector>

#include "vehicle/loader_description.h"
#include "vehicle/powertrain.h"
#include "vehicle/tyre.h"

class btMultiBody;
class btMultiBodyDynamicsWorld;
class btMultiBodyJointMotor;
class btMultiBodyJointLimitConstraint;
class btMultiBodyLinkCollider;
class btCollisionShape;
class btCollisionObject;

namespace skidsim::vehicle {

// Collision filter groups shared with the engine: the machine's colliders
// touch the ground (firm terrain, obstacles, trucks) and nothing else.
constexpr int kMachineCollisionGroup = 1 << 6;
constexpr int kGroundCollisionGroup = 1 << 7;
constexpr int kTyreProbeGroup = 1 << 8;
constexpr int kAgentCollisionGroup = 1 << 9;  // people on site: detected against the machine only

// What the soil under one wheel does this step (the engine fills it from
// the Wong-Reece wheel on the terrain grid, terrain/wheel_contact.h; firm
// ground is found by Bullet contact tests).
struct SoftWheelContact {
  bool active = false;  // the wheel touches soil
  // The soil's force on the wheel at its hub: W along world up (with its
  // viscous part, per m/s of the hub's vertical speed), the drawbar pull
  // along the wheel's heading at the deflection's slip, and the torque the
  // soil resists a forward spin with (the drive's load).
  double vertical_N = 0.0;
  double vertical_damping_N_s_per_m = 0.0;
  double drawbar_pull_N = 0.0;
  double drive_torque_Nm = 0.0;
  double contact_area_m2 = 0.0;
  Eigen::Vector3d contact_point_m = Eigen::Vector3d::Zero();
  SoilShear shear;  // the lateral shear's (Janosi-Hanamoto over the contact)
};

struct WheelState {
  bool on_ground = false;
  double normal_load_N = 0.0;       // firm and soil together
  double soil_load_N = 0.0;         // the soil's vertical part
  double soil_contact_area_m2 = 0.0;
  double soil_contact_length_m = 0.0;
  bool soil_sheared = false;        // traction at the soil's shear strength
  double slip_ratio = 0.0, slip_angle_rad = 0.0;
  double longitudinal_force_N = 0.0, lateral_force_N = 0.0;
  Eigen::Vector3d contact_point_m = Eigen::Vector3d::Zero();
  TyreDeflection deflection;
};

struct CylinderState {
  double length_m = 0.0;
  double speed_m_per_s = 0.0;     // + extending
  double force_N = 0.0;           // + pushing (extending)
  double pressure_Pa = 0.0;       // in the loaded chamber
  bool at_relief = false;
};

class Loader {
 public:
  // Builds the multibody with its chassis link frame at `chassis_pose`
  // (world) and the implement at the given joint angles, and adds it to `world`.
  Loader(const LoaderDescription& description, btMultiBodyDynamicsWorld& world, const Eigen::Isometry3d& chassis_pose,
         double lift_rad = 0.0, double tilt_rad = 0.0);
  ~Loader();
  Loader(const Loader&) = delete;
  Loader& operator=(const Loader&) = delete;

  // Controls -> hydraulics, drive and tyre forces. `soft` (one per wheel, or
  // null) carries the soil's reaction where the wheel stands on soil.
  void pre_step(const LoaderControls& controls, double dt_s, const SoftWheelContact* soft = nullptr);
  void post_step(double dt_s);

  // An external force on a link (world frame, at a world point), for the
  // payload and for terrain reactions on the bucket. Cleared by each step.
  void add_force(int link, const Eigen::Vector3d& force_N, const Eigen::Vector3d& point_m);

  // The same with a torque (world), as the soil's reaction comes.
  void add_wrench(int link, const Eigen::Vector3d& force_N, const Eigen::Vector3d& torque_Nm,
                  const Eigen::Vector3d& point_m);

  const LoaderDescription& description() const { return d_; }
  // Velocity of a link's centre of mass and its angular velocity, world.
  void link_velocity(int link, Eigen::Vector3d& velocity, Eigen::Vector3d& angular_velocity) const;
  Eigen::Vector3d link_centre_of_mass(int link) const;
  Eigen::Isometry3d link_pose(int link) const;          // link frame in world
  Eigen::Vector3d chassis_velocity() const;             // of the chassis COM, world
  Eigen::Vector3d chassis_angular_velocity() const;     // world
  Eigen::Vector3d centre_of_mass() const;               // whole machine, world
  double joint_angle(int joint) const;
  double joint_speed(int joint) const;
  Eigen::Vector3d wheel_hub(int wheel) const;
  double side_wheel_speed(int side) const { return side_speed_[side]; }
  double engine_speed_rpm() const;
  // What the engine gives this step: the implement pump's shaft power and
  // the drive pumps' (W).
  double engine_output_power_W() const { return implement_power_W_ / d_.implement_pump.efficiency + drive_power_W_; }
  const std::vector<WheelState>& wheels() const { return wheels_; }
  // The tyres' normal loads this step, all of them and the rear axle's
  // (hubs behind the chassis origin): the one measure of the tipping rule,
  // for the world's stability watch, the tasks' tipping warning and the
  // state's tipping margin (each with its own threshold).
  struct AxleLoads {
    double rear_N = 0.0, total_N = 0.0;
  };
  AxleLoads axle_loads() const {
    AxleLoads a;
    for (std::size_t k = 0; k < wheels_.size(); ++k) {
      a.total_N += wheels_[k].normal_load_N;
      if (d_.wheels[k].hub_m.x() < 0.0) a.rear_N += wheels_[k].normal_load_N;
    }
    return a;
  }
  const std::vector<CylinderState>& cylinders() const { return cylinder_state_; }
  btMultiBody& multibody() { return *body_; }

 private:
  void apply_hydraulics(const LoaderControls& c, double dt_s);
  void apply_tyres_and_drive(const LoaderControls& c, double dt_s, const SoftWheelContact* soft);
  bool firm_contact(int wheel, const Eigen::Isometry3d& chassis, Eigen::Vector3d& point, Eigen::Vector3d& normal,
                    double& penetration);

  LoaderDescription d_;
  btMultiBodyDynamicsWorld& world_;
  btMultiBody* body_ = nullptr;
  std::vector<btMultiBodyLinkCollider*> colliders_;
  std::vector<btCollisionShape*> shapes_;
  btCollisionShape* wheel_shape_ = nullptr;
  std::vector<btCollisionObject*> wheel_probes_;
  struct WheelSideContact {
    double depth_m = 0.0;
    Eigen::Vector3d normal = Eigen::Vector3d::UnitX(), point_m = Eigen::Vector3d::Zero();
  };
  std::vector<WheelSideContact> side_contacts_;  // this step's, from firm_contact
  // compTreeLinkVelocities output, sized once (no allocation per call).
  mutable btAlignedObjectArray<btVector3> omega_scratch_, velocity_scratch_;
  std::vector<btMultiBodyJointMotor*> motors_;
  std::vector<btMultiBodyJointLimitConstraint*> limits_;
  std::vector<WheelState> wheels_;
  std::vector<CylinderState> cylinder_state_;
  std::vector<double> cylinder_flow_;     // m^3/s asked this step, + extends
  std::vector<double> hold_angle_;        // latched when a spool closes
  std::vector<bool> holding_;
  std::array<double, 2> side_speed_{};    // rad/s
  std::array<double, 2> pump_stroke_{};   // drive pumps' displacement, -1..1
  std::array<double, 2> spool_{};         // lift and tilt spools, -1..1
  double engine_speed_rad_s_ = 0.0;
  double drive_radius_m_ = 0.0;
  double implement_power_W_ = 0.0;
  double drive_power_W_ = 0.0;
};

}  // namespace skidsim::vehicle
