#include "engine/world.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <btBulletDynamicsCommon.h>

#include <cmath>

namespace skidsim::engine {
namespace {
btVector3 bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
}  // namespace

World::World(const vehicle::LoaderDescription& loader, const FirmGround& ground, const Eigen::Isometry3d& chassis_pose,
             double lift_rad, double tilt_rad)
    : config_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(config_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btMultiBodyConstraintSolver>()),
      world_(std::make_unique<btMultiBodyDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                        config_.get())) {
  world_->setGravity(btVector3(0, 0, -9.81));
  btContactSolverInfo& info = world_->getSolverInfo();
  info.m_numIterations = 50;
  auto add_static = [&](btCollisionShape* shape, const btTransform& pose) {
    shapes_.emplace_back(shape);
    auto obj = std::make_unique<btCollisionObject>();
    obj->setCollisionShape(shape);
    obj->setWorldTransform(pose);
    obj->setFriction(ground.friction);
    obj->setRestitution(0.0);
    world_->addCollisionObject(obj.get(), vehicle::kGroundCollisionGroup,
                               vehicle::kMachineCollisionGroup | vehicle::kTyreRayGroup);
    statics_.push_back(std::move(obj));
  };
  if (ground.has_plane) {
    btTransform t;
    t.setIdentity();
    add_static(new btStaticPlaneShape(bt(ground.plane_normal.normalized()), ground.plane_offset_m), t);
  }
  for (const StaticBox& b : ground.boxes) {
    const Eigen::Quaterniond q(b.pose.linear());
    add_static(new btBoxShape(bt(b.half_extents_m)),
               btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(Eigen::Vector3d(b.pose.translation()))));
  }
  loader_ = std::make_unique<vehicle::Loader>(loader, *world_, chassis_pose, lift_rad, tilt_rad);
}

World::~World() {
  loader_.reset();
  for (auto& obj : statics_) world_->removeCollisionObject(obj.get());
}

void World::set_link_load(int link, const Eigen::Vector3d& force_N, const Eigen::Vector3d& point_in_link_m) {
  for (LinkLoad& l : loads_)
    if (l.link == link) {
      l.force_N = force_N;
      l.point_in_link_m = point_in_link_m;
      return;
    }
  loads_.push_back({link, force_N, point_in_link_m});
}

void World::step(const vehicle::LoaderControls& controls) {
  for (const LinkLoad& l : loads_) loader_->add_force(l.link, l.force_N, loader_->link_pose(l.link) * l.point_in_link_m);
  loader_->pre_step(controls, kStepSeconds);
  // maxSubSteps = 0: exactly one internal step of kStepSeconds, no interpolation.
  world_->stepSimulation(kStepSeconds, 0, kStepSeconds);
  loader_->post_step(kStepSeconds);
  ++steps_;
  watch_stability();
}

void World::watch_stability() {
  const vehicle::Loader& l = *loader_;
  double rear_load = 0.0;
  for (size_t i = 0; i < l.wheels().size(); ++i)
    if (l.description().wheels[i].hub_m.x() < 0.0) rear_load += l.wheels()[i].normal_load_N;
  const double weight = 9.81 * l.description().total_mass_kg();
  if (events_.rear_wheels_unloaded_s < 0.0 && rear_load < 0.01 * weight) events_.rear_wheels_unloaded_s = time_s();
  const Eigen::Isometry3d chassis = l.link_pose(0);
  if (events_.tipped_over_s < 0.0 && chassis.linear()(2, 2) < std::cos(0.25 * 3.14159265358979323846))
    events_.tipped_over_s = time_s();
  if (!chassis.matrix().allFinite() || !l.chassis_velocity().allFinite()) events_.finite = false;
}

}  // namespace skidsim::engine
