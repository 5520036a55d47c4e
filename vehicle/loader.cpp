#include "vehicle/loader.h"
#include "common/physical_constants.h"

#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCompoundShape.h>
#include <BulletCollision/CollisionShapes/btCylinderShape.h>
#include <BulletCollision/CollisionShapes/btTriangleShape.h>
#include <BulletCollision/CollisionDispatch/btCollisionObjectWrapper.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "vehicle/cylinder_geometry.h"

namespace skidsim::vehicle {
namespace {

constexpr double kRpmToRadS = 2.0 * kPi / 60.0;
// A face steeper than 50 degrees to the chassis is no ground for a tyre:
// it only pushes the tyre away (a wall, a step's riser).
constexpr double kGroundFaceCos = 0.64;
// A triangle's contact whose normal is more than 18 deg off the triangle's
// own is an artefact of its edge.
constexpr double kTriangleNormalCos = 0.95;
// Fastest joint speed a cylinder motor is asked for, rad/s (near a cylinder's
// dead centre the flow would ask for more).
constexpr double kMaxJointSpeed = 3.0;

btVector3 bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
Eigen::Vector3d eig(const btVector3& v) { return {v.x(), v.y(), v.z()}; }
btQuaternion bt(const Eigen::Quaterniond& q) { return btQuaternion(q.x(), q.y(), q.z(), q.w()); }
Eigen::Quaterniond eig(const btQuaternion& q) { return Eigen::Quaterniond(q.w(), q.x(), q.y(), q.z()); }

Eigen::Isometry3d iso(const Pose& p) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = p.rotation.toRotationMatrix();
  t.translation() = p.position_m;
  return t;
}

btTransform bt(const Eigen::Isometry3d& t) {
  return btTransform(bt(Eigen::Quaterniond(t.linear())), bt(Eigen::Vector3d(t.translation())));
}

}  // namespace

Loader::Loader(const LoaderDescription& description, btMultiBodyDynamicsWorld& world,
               const Eigen::Isometry3d& chassis_pose, double lift_rad, double tilt_rad)
    : d_(description), world_(world) {
  const int num_links = static_cast<int>(d_.joints.size());
  const RigidLink& chassis = d_.links[0];
  body_ = new btMultiBody(num_links, chassis.mass_kg, bt(chassis.principal_inertia_kg_m2), false, false);
  for (int j = 0; j < num_links; ++j) {
    const RigidLink& child = d_.links[j + 1];
    const RigidLink& parent = d_.links[d_.joint_parent_link[j]];
    const ImplementJoint& joint = d_.joints[j];
    // Bullet's link frames are the centre-of-mass frames.
    const Eigen::Quaterniond parent_com = parent.com.rotation;
    const Eigen::Quaterniond child_com_in_parent = joint.origin.rotation * child.com.rotation;
    const Eigen::Quaterniond parent_to_this = child_com_in_parent.conjugate() * parent_com;
    const Eigen::Vector3d axis_in_com = child.com.rotation.conjugate() * joint.axis;
    const Eigen::Vector3d parent_com_to_pivot = parent_com.conjugate() * (joint.origin.position_m - parent.com.position_m);
    const Eigen::Vector3d pivot_to_com = child.com.rotation.conjugate() * child.com.position_m;
    body_->setupRevolute(j, child.mass_kg, bt(child.principal_inertia_kg_m2), d_.joint_parent_link[j] - 1,
                         bt(parent_to_this), bt(axis_in_com), bt(parent_com_to_pivot), bt(pivot_to_com), true);
  }
  body_->finalizeMultiDof();
  body_->setLinearDamping(0.0);
  body_->setAngularDamping(0.0);
  body_->setHasSelfCollision(false);
  body_->setCanSleep(false);
  body_->setBaseWorldTransform(bt(chassis_pose * iso(chassis.com)));
  const double start[2] = {lift_rad, tilt_rad};
  for (int j = 0; j < num_links && j < 2; ++j)
    if (!(start[j] >= d_.joints[j].lower_rad && start[j] <= d_.joints[j].upper_rad))
      throw std::invalid_argument("joint '" + d_.joints[j].name + "': start angle " + std::to_string(start[j]) +
                                  " rad is outside its limits");
  if (num_links > 0) body_->setJointPos(0, lift_rad);
  if (num_links > 1) body_->setJointPos(1, tilt_rad);
  world_.addMultiBody(body_, kMachineCollisionGroup, kGroundCollisionGroup | kAgentCollisionGroup);

  // Colliders: each link's boxes in a compound, placed in its COM frame.
  for (int l = 0; l <= num_links; ++l) {
    const RigidLink& link = d_.links[l];
    if (link.collision.empty()) continue;
    auto* compound = new btCompoundShape();
    shapes_.push_back(compound);
    const Eigen::Isometry3d com_inv = iso(link.com).inverse();
    for (const CollisionBox& box : link.collision) {
      auto* shape = new btBoxShape(bt(box.half_extents_m));
      shapes_.push_back(shape);
      compound->addChildShape(bt(com_inv * iso(box.pose)), shape);
    }
    auto* col = new btMultiBodyLinkCollider(body_, l - 1);
    col->setCollisionShape(compound);
    col->setFriction(0.6);
    col->setRestitution(0.0);
    colliders_.push_back(col);
    if (l == 0) body_->setBaseCollider(col);
    else body_->getLink(l - 1).m_collider = col;
  }
  btAlignedObjectArray<btQuaternion> scratch_q;
  btAlignedObjectArray<btVector3> scratch_v;
  body_->updateCollisionObjectWorldTransforms(scratch_q, scratch_v);
  for (auto* col : colliders_) world_.addCollisionObject(col, kMachineCollisionGroup, kGroundCollisionGroup | kAgentCollisionGroup);

  // Cylinders: one velocity motor per joint, its bound set each step; the
  // stroke's ends are the joint limits.
  for (int j = 0; j < num_links; ++j) {
    auto* motor = new btMultiBodyJointMotor(body_, j, 0.0, 0.0);
    world_.addMultiBodyConstraint(motor);
    motors_.push_back(motor);
    auto* limit = new btMultiBodyJointLimitConstraint(body_, j, d_.joints[j].lower_rad, d_.joints[j].upper_rad);
    world_.addMultiBodyConstraint(limit);
    limits_.push_back(limit);
  }
  // Firm-ground probes: one cylinder per wheel, never added to the world.
  wheel_shape_ = new btCylinderShape(btVector3(d_.tyre.radius_m, 0.5 * d_.tyre.width_m, d_.tyre.radius_m));
  wheel_shape_->setMargin(0.005);
  side_contacts_.assign(d_.wheels.size(), {});
  for (size_t w = 0; w < d_.wheels.size(); ++w) {
    auto* probe = new btCollisionObject();
    probe->setCollisionShape(wheel_shape_);
    wheel_probes_.push_back(probe);
  }
  omega_scratch_.resize(num_links + 1);
  velocity_scratch_.resize(num_links + 1);
  wheels_.resize(d_.wheels.size());
  cylinder_state_.resize(d_.cylinders.size());
  cylinder_flow_.assign(d_.cylinders.size(), 0.0);
  hold_angle_.assign(d_.joints.size(), 0.0);
  holding_.assign(d_.joints.size(), false);
  engine_speed_rad_s_ = d_.engine.idle_rpm * kRpmToRadS;
  // The drive is calibrated on the rolling radius under the machine's own
  // weight, so that a full lever gives the rated top speed.
  const double static_deflection =
      kGravity_m_s2 * d_.total_mass_kg() / (static_cast<double>(d_.wheels.size()) * d_.tyre.radial_stiffness_N_per_m);
  drive_radius_m_ = d_.tyre.radius_m - static_deflection / 3.0;
}

Loader::~Loader() {
  for (auto* m : motors_) {
    world_.removeMultiBodyConstraint(m);
    delete m;
  }
  for (auto* l : limits_) {
    world_.removeMultiBodyConstraint(l);
    delete l;
  }
  for (auto* c : colliders_) {
    world_.removeCollisionObject(c);
    delete c;
  }
  world_.removeMultiBody(body_);
  delete body_;
  for (auto* s : shapes_) delete s;
  for (auto* p : wheel_probes_) delete p;
  delete wheel_shape_;
}

Eigen::Isometry3d Loader::link_pose(int link) const {
  Eigen::Isometry3d com_world = Eigen::Isometry3d::Identity();
  if (link == 0) {
    com_world.linear() = eig(body_->getWorldToBaseRot()).conjugate().toRotationMatrix();
    com_world.translation() = eig(body_->getBasePos());
  } else {
    const btMatrix3x3 r = body_->localFrameToWorld(link - 1, btMatrix3x3::getIdentity());
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b) com_world.linear()(a, b) = r[a][b];
    com_world.translation() = eig(body_->localPosToWorld(link - 1, btVector3(0, 0, 0)));
  }
  return com_world * iso(d_.links[link].com).inverse();
}

Eigen::Vector3d Loader::chassis_velocity() const { return eig(body_->getBaseVel()); }
Eigen::Vector3d Loader::chassis_angular_velocity() const { return eig(body_->getBaseOmega()); }
double Loader::joint_angle(int joint) const { return body_->getJointPos(joint); }
double Loader::joint_speed(int joint) const { return body_->getJointVel(joint); }
double Loader::engine_speed_rpm() const { return engine_speed_rad_s_ / kRpmToRadS; }

Eigen::Vector3d Loader::centre_of_mass() const {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  double mass = 0.0;
  for (size_t l = 0; l < d_.links.size(); ++l) {
    sum += d_.links[l].mass_kg * (link_pose(static_cast<int>(l)) * d_.links[l].com.position_m);
    mass += d_.links[l].mass_kg;
  }
  return sum / mass;
}

Eigen::Vector3d Loader::wheel_hub(int wheel) const { return link_pose(0) * d_.wheels[wheel].hub_m; }

void Loader::add_wrench(int link, const Eigen::Vector3d& force_N, const Eigen::Vector3d& torque_Nm,
                        const Eigen::Vector3d& point_m) {
  add_force(link, force_N, point_m);
  if (link == 0) body_->addBaseTorque(bt(torque_Nm));
  else body_->addLinkTorque(link - 1, bt(torque_Nm));
}

Eigen::Vector3d Loader::link_centre_of_mass(int link) const {
  return link == 0 ? eig(body_->getBasePos()) : eig(body_->localPosToWorld(link - 1, btVector3(0, 0, 0)));
}

void Loader::link_velocity(int link, Eigen::Vector3d& velocity, Eigen::Vector3d& angular_velocity) const {
  if (link == 0) {
    velocity = eig(body_->getBaseVel());
    angular_velocity = eig(body_->getBaseOmega());
    return;
  }
  // Bullet gives every link's velocities in its own (centre of mass) frame.
  body_->compTreeLinkVelocities(&omega_scratch_[0], &velocity_scratch_[0]);
  const btMatrix3x3 r = body_->localFrameToWorld(link - 1, btMatrix3x3::getIdentity());
  velocity = eig(r * velocity_scratch_[link]);
  angular_velocity = eig(r * omega_scratch_[link]);
}

void Loader::add_force(int link, const Eigen::Vector3d& force_N, const Eigen::Vector3d& point_m) {
  if (link == 0) {
    body_->addBaseForce(bt(force_N));
    body_->addBaseTorque(bt((point_m - eig(body_->getBasePos())).cross(force_N)));
  } else {
    const Eigen::Vector3d com = eig(body_->localPosToWorld(link - 1, btVector3(0, 0, 0)));
    body_->addLinkForce(link - 1, bt(force_N));
    body_->addLinkTorque(link - 1, bt((point_m - com).cross(force_N)));
  }
}

void Loader::pre_step(const LoaderControls& controls, double dt_s, const SoftWheelContact* soft) {
  apply_hydraulics(controls, dt_s);
  apply_tyres_and_drive(controls, dt_s, soft);
  // Engine: the governor's torque against the pumps' (semi-implicit in speed).
  const double w = std::max(engine_speed_rad_s_, 1.0);
  const double load = (implement_power_W_ / d_.implement_pump.efficiency + drive_power_W_) / w;
  const double torque = engine_torque_N_m(d_.engine, controls.throttle, engine_speed_rad_s_) -
                        (engine_speed_rad_s_ > 0.0 ? d_.engine.friction_torque_N_m : 0.0);
  engine_speed_rad_s_ = std::max(0.0, engine_speed_rad_s_ + dt_s * (torque - load) / d_.engine.inertia_kg_m2);
}

void Loader::apply_hydraulics(const LoaderControls& c, double dt_s) {
  spool_[0] = slew(spool_[0], c.lift, d_.implement_pump.spool_time_s, dt_s);
  spool_[1] = slew(spool_[1], c.tilt, d_.implement_pump.spool_time_s, dt_s);
  const std::array<double, 2> flows =
      implement_flows_m3_per_s(d_.implement_pump, d_.engine, engine_speed_rad_s_, spool_[0], spool_[1]);
  for (size_t i = 0; i < d_.cylinders.size(); ++i) {
    const Cylinder& cyl = d_.cylinders[i];
    const int j = cyl.joint;
    const double q = body_->getJointPos(j);
    const CylinderKinematics k = cylinder_kinematics(cyl, d_.joints[j], q);
    const double flow = j == 0 ? flows[0] : flows[1];
    cylinder_flow_[i] = flow;
    btMultiBodyJointMotor* motor = motors_[j];
    const double area = flow >= 0.0 ? cyl.piston_area_m2() : cyl.annulus_area_m2();
    // The force bound follows the chamber that carries the load, known from
    // the last step's force: pushing loads the piston side, pulling the rod
    // side (a load lowered on the piston side is held to its relief, not the
    // rod side's; Bullet's motor row is symmetric, so the bound is chosen).
    const double loaded_area =
        cylinder_state_[i].force_N >= 0.0 ? cyl.piston_area_m2() : cyl.annulus_area_m2();
    // A closed spool locks the cylinder (load-holding valves): hold the angle
    // it had, up to the relief force on the piston side.
    if (flow == 0.0) {
      if (!holding_[j]) hold_angle_[j] = q;
      holding_[j] = true;
      motor->setVelocityTarget(0.0, 1.0);
      motor->setPositionTarget(hold_angle_[j], 0.2);
      motor->setMaxAppliedImpulse(cyl.relief_pressure_Pa * loaded_area * std::abs(k.moment_arm_m) * dt_s);
      continue;
    }
    holding_[j] = false;
    // Flow-limited speed (Q / A), relief-limited force (p_relief A).
    const double cylinder_speed = flow / area;
    const double joint_speed =
        std::clamp(cylinder_speed / (std::abs(k.moment_arm_m) > 1e-6 ? k.moment_arm_m : 1e-6), -kMaxJointSpeed,
                   kMaxJointSpeed);
    motor->setPositionTarget(0.0, 0.0);
    motor->setVelocityTarget(joint_speed, 1.0);
    motor->setMaxAppliedImpulse(cyl.relief_pressure_Pa * loaded_area * std::abs(k.moment_arm_m) * dt_s);
  }
}

namespace {
// The deepest point where a wheel's cylinder meets firm ground.
struct DeepestContact : btCollisionWorld::ContactResultCallback {
  struct Point {
    double depth = 0.0;
    btVector3 normal{0, 0, 1}, point{0, 0, 0};
  };
  const btCollisionObject* wheel = nullptr;
  btVector3 up{0, 0, 1};
  Point ground, side;  // faces the tyre stands on; steep ones (a wall, a step's riser)
  btScalar addSingleResult(btManifoldPoint& cp, const btCollisionObjectWrapper* a, int, int,
                           const btCollisionObjectWrapper* b, int, int) override {
    const double d = -cp.getDistance();
    // m_normalWorldOnB points from B to A: towards the wheel when the wheel is A.
    const bool wheel_is_a = a->getCollisionObject() == wheel;
    const btVector3 n = wheel_is_a ? cp.m_normalWorldOnB : -cp.m_normalWorldOnB;
    // A heightfield is met triangle by triangle: a triangle ending just past
    // the tyre's side reports a sideways normal (Bullet separates the pair
    // the shortest way) although the ground there is flat. Such contacts,
    // far from the triangle's own normal, are artefacts of its edges.
    const btCollisionObjectWrapper* ground_side = wheel_is_a ? b : a;
    if (ground_side->getCollisionShape()->getShapeType() == TRIANGLE_SHAPE_PROXYTYPE) {
      const auto* t = static_cast<const btTriangleShape*>(ground_side->getCollisionShape());
      btVector3 face = ground_side->getWorldTransform().getBasis() *
                       (t->m_vertices1[1] - t->m_vertices1[0]).cross(t->m_vertices1[2] - t->m_vertices1[0]);
      if (face.length2() > 0.0) {
        face.normalize();
        if (std::abs(face.dot(n)) < kTriangleNormalCos) return 0;
      }
    }
    Point& p = n.dot(up) >= kGroundFaceCos ? ground : side;
    if (d > p.depth) {
      p.depth = d;
      p.normal = n;
      p.point = wheel_is_a ? cp.getPositionWorldOnB() : cp.getPositionWorldOnA();
    }
    return 0;
  }
};
}  // namespace

bool Loader::firm_contact(int wheel, const Eigen::Isometry3d& chassis, Eigen::Vector3d& point, Eigen::Vector3d& normal,
                          double& penetration) {
  // The tyre's cylinder against firm ground (planes, boxes, the sites'
  // bases): Bullet's contact test gives the disc's true penetration, at
  // face, edge or corner alike.
  btCollisionObject& probe = *wheel_probes_[wheel];
  probe.setWorldTransform(btTransform(bt(Eigen::Quaterniond(chassis.linear())), bt(Eigen::Vector3d(chassis * d_.wheels[wheel].hub_m))));
  DeepestContact hit;
  hit.wheel = &probe;
  hit.up = bt(Eigen::Vector3d(chassis.linear().col(2)));
  hit.m_collisionFilterGroup = kTyreProbeGroup;
  hit.m_collisionFilterMask = kGroundCollisionGroup;
  world_.contactTest(&probe, hit);
  // A steep face only pushes the tyre away (no traction from a wall).
  WheelSideContact& side = side_contacts_[wheel];
  side.depth_m = hit.side.depth;
  side.normal = eig(hit.side.normal).normalized();
  side.point_m = eig(hit.side.point);
  if (!(hit.ground.depth > 0.0)) return false;
  penetration = hit.ground.depth;
  normal = eig(hit.ground.normal).normalized();
  // Bullet puts the contact at one end of the cylinder, the end chosen by
  // the sign of a tiny roll: the load acts on the tyre's mid-plane.
  const Eigen::Vector3d hub = chassis * d_.wheels[wheel].hub_m, axle = chassis.linear().col(1);
  point = eig(hit.ground.point);
  point -= axle * (point - hub).dot(axle);
  return true;
}

void Loader::apply_tyres_and_drive(const LoaderControls& c, double dt_s, const SoftWheelContact* soft) {
  const Eigen::Isometry3d chassis = link_pose(0);
  const Eigen::Vector3d axle = chassis.linear().col(1);
  const Eigen::Vector3d com = eig(body_->getBasePos());
  const Eigen::Vector3d v_com = eig(body_->getBaseVel()), omega = eig(body_->getBaseOmega());
  const TyreParameters& tp = d_.tyre;
  std::array<double, 2> load_torque{0.0, 0.0};
  std::array<int, 2> side_wheels{0, 0};
  for (const Wheel& w : d_.wheels) ++side_wheels[w.side];

  // Pass 1: contact and forces from the present state.
  struct Pending {
    Eigen::Vector3d hub, point, normal, heading, lateral;
    TyreKinematics k;
    double arm = 0.0;
    double firm_load = 0.0;
    TyreForce firm, soil;
  };
  std::array<Pending, 8> pending;
  for (size_t i = 0; i < d_.wheels.size() && i < pending.size(); ++i) {
    WheelState& ws = wheels_[i];
    Pending& p = pending[i];
    p.hub = chassis * d_.wheels[i].hub_m;
    double penetration = 0.0;
    Eigen::Vector3d point, normal;
    const bool firm = firm_contact(static_cast<int>(i), chassis, point, normal, penetration);
    const SoftWheelContact* s = soft && soft[i].active ? &soft[i] : nullptr;
    // The soil's W with its viscous part at the hub's vertical speed, and
    // the carcass's: the tyre is in series with a soil much stiffer than
    // itself on a reload line (a rut), so the hub's motion passes through
    // its damper.
    const double damping = s ? s->vertical_damping_N_s_per_m + tp.radial_damping_N_s_per_m : 0.0;
    const double soil_load = s ? std::max(0.0, s->vertical_N - damping * (v_com + omega.cross(p.hub - com)).z()) : 0.0;
    ws.on_ground = firm || soil_load > 0.0;
    ws.soil_sheared = false;
    if (!ws.on_ground) {
      p.k = {};
      ws.normal_load_N = ws.soil_load_N = ws.longitudinal_force_N = ws.lateral_force_N = 0.0;
      continue;
    }
    if (!firm) {
      normal = Eigen::Vector3d::UnitZ();
      point = s->contact_point_m;
    }
    const Eigen::Vector3d v = v_com + omega.cross(point - com);
    if (firm)
      p.firm_load = std::max(0.0, tp.radial_stiffness_N_per_m * penetration - tp.radial_damping_N_s_per_m * v.dot(normal));
    p.heading = axle.cross(normal).normalized();
    p.lateral = normal.cross(p.heading);
    p.normal = normal;
    p.point = point;
    p.arm = tp.radius_m - penetration / 3.0;  // effective rolling radius
    p.k.contact_speed_x = v.dot(p.heading);
    p.k.contact_speed_y = v.dot(p.lateral);
    p.k.rolling_speed = side_speed_[d_.wheels[i].side] * p.arm;
    // Firm ground: Magic Formula on the tyre's radial load. Soil: the
    // Wong-Reece pull and Janosi's side force on the soil's load. Both from
    // the same patch deflection, so the sum changes continuously as the
    // load moves from one to the other.
    TyreKinematics firm_k = p.k;
    firm_k.normal_load_N = p.firm_load;
    p.firm = firm_tyre_force(tp, ws.deflection, firm_k);
    if (s) {
      TyreKinematics soil_k = p.k;
      soil_k.normal_load_N = soil_load;
      const SoilTyreForce sf =
          soil_tyre_force(tp, ws.deflection, s->shear, soil_k, s->contact_area_m2, s->drawbar_pull_N);
      p.soil = sf.force;
      ws.soil_sheared = sf.at_strength;
    }
    p.k.normal_load_N = p.firm_load + soil_load;
    ws.normal_load_N = p.k.normal_load_N;
    ws.soil_load_N = soil_load;
    ws.soil_contact_area_m2 = s ? s->contact_area_m2 : 0.0;
    ws.soil_contact_length_m = s ? s->shear.contact_length_m : 0.0;
    ws.longitudinal_force_N = p.firm.longitudinal_N + p.soil.longitudinal_N;
    ws.lateral_force_N = p.firm.lateral_N + p.soil.lateral_N;
    ws.contact_point_m = point;
    ws.slip_ratio = deflection_slip_ratio(tp, ws.deflection);
    ws.slip_angle_rad = deflection_slip_angle(tp, ws.deflection);
    // Rolling resistance on firm ground: a torque on the wheel against its
    // spin (smooth at 0). On soil it is the soil's own (compaction).
    const double spin = std::tanh(p.k.rolling_speed / 0.05);
    load_torque[d_.wheels[i].side] += p.arm * p.firm.longitudinal_N + tp.rolling_resistance * p.firm_load * p.arm * spin;
    // On soil the drive meets the shear's moment about the axle (Wong-Reece's
    // T; the normal stresses pass through the axle).
    if (s) load_torque[d_.wheels[i].side] += s->drive_torque_Nm;
  }

  // Drive: each side's wheel speed under its servo and the tyres' torque.
  // The most the engine can give at its present speed, less what the
  // implement takes (the pumps' anti-stall control reads the engine speed;
  // the governor then meets the load, lugging down if it must).
  const double engine_power = full_load_power_W(d_.engine, engine_speed_rad_s_) -
                              d_.engine.friction_torque_N_m * engine_speed_rad_s_;
  const double available = std::max(0.0, engine_power - implement_power_W_ / d_.implement_pump.efficiency);
  std::array<double, 2> motor_torque{0.0, 0.0};
  drive_power_W_ = 0.0;
  for (int side = 0; side < 2; ++side) {
    // Braked, the pumps go back to neutral: releasing the brake with a lever
    // forward starts from zero flow.
    const double lever = c.parking_brake ? 0.0 : (side == 0 ? c.drive_left : c.drive_right);
    pump_stroke_[side] = slew(pump_stroke_[side], lever, d_.drive.pump_stroke_time_s, dt_s);
    const double command = pump_stroke_[side];
    const DriveSideCommand cmd = drive_side_command(d_.drive, d_.engine, drive_radius_m_, engine_speed_rad_s_, command,
                                                    0.5 * available, side_speed_[side], c.parking_brake);
    motor_torque[side] = advance_drive_side(d_.drive, cmd, load_torque[side], dt_s, side_speed_[side]);
    // Only driving takes power from the engine; holding and braking do not.
    if (!cmd.brake) drive_power_W_ += std::max(0.0, motor_torque[side] * side_speed_[side]) / d_.drive.efficiency;
  }

  // Pass 2: forces on the chassis; deflections advance with the new wheel speeds.
  for (size_t i = 0; i < d_.wheels.size() && i < pending.size(); ++i) {
    WheelState& ws = wheels_[i];
    const Pending& p = pending[i];
    const int side = d_.wheels[i].side;
    // The motor's reaction on the chassis, shared by the side's wheels.
    body_->addBaseTorque(bt(Eigen::Vector3d(-axle * motor_torque[side] / side_wheels[side])));
    const WheelSideContact& wall = side_contacts_[i];
    if (wall.depth_m > 0.0) {
      const Eigen::Vector3d v = v_com + omega.cross(wall.point_m - com);
      const double push = std::max(0.0, tp.radial_stiffness_N_per_m * wall.depth_m - tp.radial_damping_N_s_per_m * v.dot(wall.normal));
      const Eigen::Vector3d f = push * wall.normal;
      body_->addBaseForce(bt(f));
      body_->addBaseTorque(bt(Eigen::Vector3d((wall.point_m - com).cross(f))));
    }
    if (ws.soil_load_N > 0.0) {
      const Eigen::Vector3d up = ws.soil_load_N * Eigen::Vector3d::UnitZ();
      body_->addBaseForce(bt(up));
      body_->addBaseTorque(bt(Eigen::Vector3d((p.hub - com).cross(up))));
    }
    if (!ws.on_ground) {
      ws.deflection = {};
      continue;
    }
    // The radial load and Fy act at the patch; Fx at the hub (its moment
    // about the axle is what turns the wheel, accounted for in the drive).
    const Eigen::Vector3d at_patch = p.firm_load * p.normal + ws.lateral_force_N * p.lateral;
    const Eigen::Vector3d at_hub = ws.longitudinal_force_N * p.heading;
    body_->addBaseForce(bt(Eigen::Vector3d(at_patch + at_hub)));
    body_->addBaseTorque(bt(Eigen::Vector3d((p.point - com).cross(at_patch) + (p.hub - com).cross(at_hub))));
    advance_deflection(tp, TyreKinematics{p.k.normal_load_N, p.k.contact_speed_x, p.k.contact_speed_y,
                                          side_speed_[side] * p.arm},
                       dt_s, ws.deflection);
  }
}

void Loader::post_step(double dt_s) {
  implement_power_W_ = 0.0;
  for (size_t i = 0; i < d_.cylinders.size(); ++i) {
    const Cylinder& cyl = d_.cylinders[i];
    const int j = cyl.joint;
    const CylinderKinematics k = cylinder_kinematics(cyl, d_.joints[j], body_->getJointPos(j));
    CylinderState& s = cylinder_state_[i];
    const double torque = motors_[j]->getAppliedImpulse(0) / dt_s;
    s.length_m = k.length_m;
    s.speed_m_per_s = k.moment_arm_m * body_->getJointVel(j);
    s.force_N = std::abs(k.moment_arm_m) > 1e-6 ? torque / k.moment_arm_m : 0.0;
    const double area = s.force_N >= 0.0 ? cyl.piston_area_m2() : cyl.annulus_area_m2();
    s.pressure_Pa = std::abs(s.force_N) / area;
    s.at_relief = s.pressure_Pa >= 0.999 * cyl.relief_pressure_Pa;
    implement_power_W_ += s.pressure_Pa * std::abs(cylinder_flow_[i]);
  }
}

}  // namespace skidsim::vehicle
