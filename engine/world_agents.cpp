// The World's agents (engine/world.h, engine/agents.h): their Bullet bodies
// and the step that moves them.
#include <BulletCollision/BroadphaseCollision/btDispatcher.h>
#include <BulletCollision/CollisionDispatch/btCollisionObject.h>
#include <BulletCollision/CollisionShapes/btBoxShape.h>
#include <BulletCollision/CollisionShapes/btCapsuleShape.h>
#include <BulletCollision/NarrowPhaseCollision/btPersistentManifold.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "engine/world.h"
#include "vehicle/loader.h"

namespace skidsim::engine {
namespace {

constexpr int kAgentTagBase = 0x10000;  // btCollisionObject user index: agent k is kAgentTagBase + k
constexpr double kCabLengthM = kTruckCabLengthM, kCabHeightM = kTruckCabHeightM;

btTransform to_bt(const Eigen::Isometry3d& pose) {
  const Eigen::Quaterniond q(pose.linear());
  const Eigen::Vector3d t = pose.translation();
  return btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), btVector3(t.x(), t.y(), t.z()));
}

Eigen::Isometry3d agent_frame(const Eigen::Vector2d& xy, double z, double heading_rad) {
  Eigen::Isometry3d f = Eigen::Isometry3d::Identity();
  f.translation() = Eigen::Vector3d(xy.x(), xy.y(), z);
  f.linear() = Eigen::AngleAxisd(heading_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return f;
}

}  // namespace

double World::ground_height_at(const Eigen::Vector2d& xy) const {
  if (grid_) {
    const Eigen::Vector2i c = cell_under(xy.x(), xy.y());
    if (grid_->contains(c.x(), c.y())) return grid_->surface_m(c.x(), c.y());
  }
  return firm_ground_offset_m_ > -1e5 ? firm_ground_offset_m_ : 0.0;
}

int World::add_agent(const AgentSpec& spec_in) {
  AgentSpec spec = spec_in;
  const int k = static_cast<int>(agent_specs_.size());
  if (spec.route_m.empty()) throw std::invalid_argument("agent '" + spec.id + "': no route");
  std::vector<AgentBody> bodies;
  const auto add_body = [&](btCollisionShape* shape, const Eigen::Isometry3d& local, int group, int mask, int flags) {
    shapes_.emplace_back(shape);
    auto obj = std::make_unique<btCollisionObject>();
    obj->setUserIndex(kAgentTagBase + k);
    obj->setCollisionShape(shape);
    obj->setCollisionFlags(obj->getCollisionFlags() | flags);
    obj->setFriction(ground_friction_);
    world_->addCollisionObject(obj.get(), group, mask);
    bodies.push_back({obj.get(), local});
    statics_.push_back(std::move(obj));
  };
  Eigen::Isometry3d bed_in_agent = Eigen::Isometry3d::Identity();
  if (spec.kind == AgentKind::kPerson) {
    // Contact is seen, not resolved: the machine does not stop for a body.
    add_body(new btCapsuleShapeZ(kPersonRadiusM, kPersonHeightM - 2.0 * kPersonRadiusM),
             Eigen::Isometry3d(Eigen::Translation3d(0, 0, 0.5 * kPersonHeightM)), vehicle::kAgentCollisionGroup,
             vehicle::kMachineCollisionGroup, btCollisionObject::CF_KINEMATIC_OBJECT | btCollisionObject::CF_NO_CONTACT_RESPONSE);
  } else {
    if (spec.tray < 0 || spec.tray >= tray_count())
      throw std::invalid_argument("truck '" + spec.id + "': its bed is not a tray of this world");
    for (const AgentSpec& o : agent_specs_)
      if (o.kind == AgentKind::kTruck && o.tray == spec.tray)
        throw std::invalid_argument("truck '" + spec.id + "': its bed is carried by '" + o.id + "' already");
    // The agent's frame: the bed's centre on the ground, x along the bed
    // towards the cab. The tray's pose now is the truck docked.
    const terrain::BodyAutomaton& bed = tray(spec.tray);
    const Eigen::Isometry3d tray_pose = bed.pose();
    const double L = bed.shape().length_m, W = bed.shape().width_m;
    const Eigen::Vector3d centre = tray_pose * Eigen::Vector3d(0.5 * L, 0.5 * W, 0.0);
    const Eigen::Vector3d x_axis = tray_pose.linear().col(0);
    const double heading = std::atan2(x_axis.y(), x_axis.x());
    const double ground = ground_height_at(centre.head<2>());
    const Eigen::Isometry3d docked = agent_frame(centre.head<2>(), ground, heading);
    spec.dock_heading_rad = heading;
    bed_in_agent = docked.inverse() * tray_pose;
    if ((spec.route_m.back() - centre.head<2>()).norm() > 0.01) spec.route_m.push_back(centre.head<2>());
    // The bed's walls move with the truck, and count as the truck.
    for (AgentBody part : tray_parts_[static_cast<std::size_t>(spec.tray)].parts) {
      part.object->setCollisionFlags(part.object->getCollisionFlags() | btCollisionObject::CF_KINEMATIC_OBJECT);
      part.object->setUserIndex(kAgentTagBase + k);
      part.local = bed_in_agent * part.local;
      bodies.push_back(part);
    }
    const double floor_z = bed_in_agent.translation().z();
    const int solid_mask = vehicle::kMachineCollisionGroup | vehicle::kTyreProbeGroup;
    add_body(new btBoxShape(btVector3(0.5 * kCabLengthM, 0.5 * W, 0.5 * kCabHeightM)),
             Eigen::Isometry3d(Eigen::Translation3d(0.5 * L + 0.5 * kCabLengthM + 0.05, 0.0, 0.5 * kCabHeightM)),
             vehicle::kGroundCollisionGroup, solid_mask, btCollisionObject::CF_KINEMATIC_OBJECT);
    if (floor_z > 0.2)
      add_body(new btBoxShape(btVector3(0.45 * L, 0.4 * W, 0.5 * (floor_z - 0.15))),
               Eigen::Isometry3d(Eigen::Translation3d(0.0, 0.0, 0.5 * (floor_z - 0.15))), vehicle::kGroundCollisionGroup,
               solid_mask, btCollisionObject::CF_KINEMATIC_OBJECT);
  }
  agent_specs_.push_back(spec);
  agent_bodies_.push_back(std::move(bodies));
  truck_bed_in_agent_.push_back(bed_in_agent);
  agents_.push_back(start_agents({spec}).front());  // the others go on as they were
  bed_load_kg_.assign(agent_specs_.size(), 0.0);
  bed_frames_.resize(agent_specs_.size());
  agent_scratch_.reserve(agent_specs_.size());
  move_agents(false);  // into place, without stepping their plans
  return k;
}

Eigen::Isometry3d World::agent_pose(int k) const {
  const AgentState& s = agents_.at(static_cast<std::size_t>(k));
  // Not yet there, or gone: far below the site, out of every contact.
  const double z = on_site(s) ? ground_height_at(s.body.position_m) : -1e4;
  return agent_frame(s.body.position_m, z, s.heading_rad);
}

void World::move_agents(bool advance) {
  const double t = time_s();
  if (advance) {
    SiteView site;
    const Eigen::Isometry3d chassis = loader_->link_pose(0);
    site.loader_m = chassis.translation().head<2>();
    site.loader_velocity_m_s = loader_->chassis_velocity().head<2>();
    const int bucket = static_cast<int>(loader_->description().links.size()) - 1;
    site.loader_rear_m = (chassis * Eigen::Vector3d(-1.3, 0.0, 0.0)).head<2>();
    site.loader_front_m = (loader_->link_pose(bucket) * Eigen::Vector3d(0.5, 0.0, 0.0)).head<2>();
    for (std::size_t k = 0; k < agent_specs_.size(); ++k)
      bed_load_kg_[k] = agent_specs_[k].tray >= 0 ? tray(agent_specs_[k].tray).material_mass_kg() : 0.0;
    site.bed_load_kg = &bed_load_kg_;
    step_agents(agent_specs_, agents_, site, t, kStepSeconds, agent_scratch_);
  }
  for (std::size_t k = 0; k < agents_.size(); ++k) {
    const AgentState& s = agents_[k];
    const Eigen::Isometry3d frame = agent_pose(static_cast<int>(k));
    for (const AgentBody& b : agent_bodies_[k]) {
      const btTransform pose = to_bt(frame * b.local);
      b.object->setWorldTransform(pose);
      b.object->setInterpolationWorldTransform(pose);
    }
    const int tray_index = agent_specs_[k].tray;
    if (agent_specs_[k].kind == AgentKind::kTruck && tray_index >= 0) {  // the bed goes where the truck is
      const Eigen::Vector3d v(s.body.velocity_m_s.x(), s.body.velocity_m_s.y(), 0.0);
      tray(tray_index).set_pose(frame * truck_bed_in_agent_[k], v, Eigen::Vector3d::Zero());
      // The bed's frame accelerates with the truck's centre (the turn's
      // centripetal part comes with the velocity's change of direction).
      if (apparent_gravity_ && advance)
        tray(tray_index).set_frame_acceleration(update_frame_acceleration(bed_frames_[k], v, kStepSeconds));
    }
  }
}

void World::release_agent(int k) {
  AgentSpec& spec = agent_specs_.at(static_cast<std::size_t>(k));
  if (!spec.held) return;
  spec.held = false;
  spec.start_s = time_s();
}

void World::agents_touching_machine(std::vector<int>& out) const {
  out.clear();
  const int n = static_cast<int>(agent_specs_.size());
  btDispatcher* dispatcher = world_->getDispatcher();  // Bullet has no const access to its manifolds
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher->getInternalManifoldPointer()[m];
    const btCollisionObject* a = manifold->getBody0();
    const btCollisionObject* b = manifold->getBody1();
    const bool machine_a = btMultiBodyLinkCollider::upcast(a) != nullptr, machine_b = btMultiBodyLinkCollider::upcast(b) != nullptr;
    if (machine_a == machine_b) continue;
    const int agent = (machine_a ? b : a)->getUserIndex() - kAgentTagBase;
    if (agent < 0 || agent >= n) continue;
    bool touching = false;
    for (int c = 0; c < manifold->getNumContacts(); ++c) touching = touching || manifold->getContactPoint(c).getDistance() <= 0.0;
    if (touching && std::find(out.begin(), out.end(), agent) == out.end()) out.push_back(agent);
  }
}

}  // namespace skidsim::engine
