#include "engine/world.h"
#include "common/physical_constants.h"
#include "terrain/edge_penetration.h"

#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <BulletCollision/CollisionShapes/btHeightfieldTerrainShape.h>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace skidsim::engine {
namespace {

// Soil in the bucket and the truck beds always slides by the automaton: it
// is loosened, dumped soil, and the slippage model's cohesion belongs to
// the ground as it lies (a site selects that model for its own grid only).
terrain::SoilFlowParameters container_soil(terrain::SoilFlowParameters soil) {
  soil.model = terrain::GroundModel::kAutomaton;
  return soil;
}
btVector3 bt(const Eigen::Vector3d& v) { return btVector3(v.x(), v.y(), v.z()); }
constexpr int kObstacleTag = 0x0b57;  // btCollisionObject user index of an obstacle
}  // namespace

World::World(const vehicle::LoaderDescription& loader, const FirmGround& ground, const Eigen::Isometry3d& chassis_pose,
             double lift_rad, double tilt_rad)
    : config_(std::make_unique<btDefaultCollisionConfiguration>()),
      dispatcher_(std::make_unique<btCollisionDispatcher>(config_.get())),
      broadphase_(std::make_unique<btDbvtBroadphase>()),
      solver_(std::make_unique<btMultiBodyConstraintSolver>()),
      world_(std::make_unique<btMultiBodyDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(),
                                                        config_.get())) {
  world_->setGravity(btVector3(0, 0, -kGravity_m_s2));
  btContactSolverInfo& info = world_->getSolverInfo();
  info.m_numIterations = 50;
  ground_friction_ = ground.friction;
  if (ground.has_plane) {
    // Bullet's plane: normalized(n) . x = offset.
    firm_ground_normal_ = ground.plane_normal.normalized();
    firm_ground_offset_m_ = ground.plane_offset_m;
  }
  auto add_static = [&](btCollisionShape* shape, const btTransform& pose) { add_static_ground(shape, pose); };
  if (ground.has_plane) {
    btTransform t;
    t.setIdentity();
    add_static(new btStaticPlaneShape(bt(ground.plane_normal.normalized()), ground.plane_offset_m), t);
  }
  for (const StaticBox& b : ground.boxes) {
    const Eigen::Quaterniond q(b.pose.linear());
    add_static_ground(new btBoxShape(bt(b.half_extents_m)),
                      btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(Eigen::Vector3d(b.pose.translation()))),
                      true);
  }
  loader_ = std::make_unique<vehicle::Loader>(loader, *world_, chassis_pose, lift_rad, tilt_rad);
}

void World::add_static_ground(btCollisionShape* shape, const btTransform& pose, bool obstacle) {
  shapes_.emplace_back(shape);
  auto obj = std::make_unique<btCollisionObject>();
  obj->setUserIndex(obstacle ? kObstacleTag : 0);
  obj->setCollisionShape(shape);
  obj->setWorldTransform(pose);
  obj->setFriction(ground_friction_);
  obj->setRestitution(0.0);
  world_->addCollisionObject(obj.get(), vehicle::kGroundCollisionGroup,
                             vehicle::kMachineCollisionGroup | vehicle::kTyreProbeGroup);
  statics_.push_back(std::move(obj));
}

World::~World() {
  for (auto& r : resistances_) world_->removeMultiBodyConstraint(r.get());
  resistances_.clear();
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

void World::add_soil_site(std::unique_ptr<terrain::GranularGrid> grid, const terrain::SoilMechanics& soil) {
  if (grid_) throw std::logic_error("World::add_soil_site: this world already has its soil site");
  if (exchange_) throw std::logic_error("World::add_soil_site: add the soil site before enable_material or trays");
  if (!grid || grid->nx() < 2 || grid->ny() < 2)
    throw std::invalid_argument("World::add_soil_site: a soil site needs at least 2 x 2 cells");
  // Everything that can refuse this site first: a failure leaves the world
  // as it was.
  std::unique_ptr<terrain::BodyAutomaton> bucket = make_bucket_automaton(grid->soil(), grid->cell_size_m());
  grid_ = std::move(grid);
  soil_ = std::make_unique<terrain::SoilContactModel>(*grid_, soil);
  // A machine working a site keeps up to a few thousand cells moving: size
  // the sweep's lists once so that the step does not allocate.
  const size_t cells = static_cast<size_t>(grid_->nx()) * grid_->ny();
  grid_->reserve_active_cells(std::max<size_t>(16384, cells / 8));
  // The site's hard base is firm ground for Bullet: the tyres' probes and the
  // machine's boxes meet it as a rigid contact (stable at any stiffness), so
  // the terrain's own base spring is taken out of the reactions below.
  const terrain::GridSpec& spec = grid_->spec();
  base_heights_.resize(static_cast<size_t>(spec.nx) * spec.ny);
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i) {
      const double b = grid_->base_m(i, j);
      base_heights_[grid_->index(i, j)] = b;
      lo = std::min(lo, b);
      hi = std::max(hi, b);
    }
  btTransform pose;
  pose.setIdentity();
  const double centre_x = spec.origin_m.x() + 0.5 * spec.cell_size_m * (spec.nx - 1);
  const double centre_y = spec.origin_m.y() + 0.5 * spec.cell_size_m * (spec.ny - 1);
  if (lo == hi) {
    // A flat base is a box (its top the base, its sides the grid's): one
    // convex contact per collider instead of a pass over the triangles
    // under it.
    const double half_x = 0.5 * spec.cell_size_m * (spec.nx - 1), half_y = 0.5 * spec.cell_size_m * (spec.ny - 1);
    pose.setOrigin(btVector3(centre_x, centre_y, lo - 0.5));
    add_static_ground(new btBoxShape(btVector3(half_x, half_y, 0.5)), pose);
  } else {
    // Tight bounds: Bullet only pairs a collider (or a tyre's probe) with the
    // base when it comes within 5 cm of it: a pair costs a pass over the
    // triangles under it every step, and making one allocates, once.
    lo -= 0.05;
    hi += 0.05;
    auto* base = new btHeightfieldTerrainShape(spec.nx, spec.ny, base_heights_.data(), lo, hi, 2, false);
    base->setLocalScaling(btVector3(spec.cell_size_m, spec.cell_size_m, 1.0));
    // Bullet centres a heightfield on its bounds; vertex (i, j) is cell (i, j)'s centre.
    pose.setOrigin(btVector3(centre_x, centre_y, 0.5 * (lo + hi)));
    add_static_ground(base, pose);
  }
  const vehicle::LoaderDescription& d = loader_->description();
  soft_.assign(d.wheels.size(), {});
  wheel_contacts_.assign(d.wheels.size(), {});
  wheel_shapes_.assign(d.wheels.size(), {});
  link_boxes_.clear();
  const int bucket_link = static_cast<int>(d.links.size()) - 1;
  for (size_t l = 0; l < d.links.size(); ++l) {
    if (static_cast<int>(l) == bucket_link && d.bucket_interior.present) {
      // The bucket meets the soil with its plates: the floor plate slices
      // into the bucket (6.4), the back plate pushes.
      const vehicle::BucketInterior& in = d.bucket_interior;
      const double t = in.plate_thickness_m, back_t = std::max(t, grid_->cell_size_m());
      vehicle::CollisionBox floor, back;
      // Only the cutting edge's strip of floor meets the cut, and its bottom
      // rises behind the edge at the bucket's clearance angle towards the
      // heel: the edge cuts, the bottom rides the cut (pressing what the
      // edge left would lift the machine's front).
      const double edge_length = std::min(in.cutting_edge_length_m, in.length_m);
      const Eigen::Quaterniond clearance(Eigen::AngleAxisd(in.bottom_clearance_rad, Eigen::Vector3d::UnitY()));
      const Eigen::Vector3d edge = in.origin_m + Eigen::Vector3d(in.length_m, 0.5 * in.width_m, 0.0);
      floor.pose.rotation = clearance;
      floor.pose.position_m = edge - clearance * Eigen::Vector3d(0.5 * edge_length, 0.0, 0.5 * t);
      floor.half_extents_m = Eigen::Vector3d(0.5 * edge_length, 0.5 * in.width_m, 0.5 * t);
      back.pose.position_m = in.origin_m + Eigen::Vector3d(0.5 * back_t, 0.5 * in.width_m, 0.5 * in.back_height_m);
      back.half_extents_m = Eigen::Vector3d(0.5 * back_t, 0.5 * in.width_m, 0.5 * in.back_height_m);
      link_boxes_.push_back({bucket_link, floor, {}, true, true});
      link_boxes_.push_back({bucket_link, back, {}, false, true});
      continue;
    }
    for (const vehicle::CollisionBox& b : d.links[l].collision) link_boxes_.push_back({static_cast<int>(l), b, {}});
  }
  body_in_soil_.assign(d.wheels.size() + link_boxes_.size(), false);
  for (size_t w = 0; w < d.wheels.size(); ++w) {
    soil_->reserve_body(static_cast<int>(w), std::hypot(2.0 * d.tyre.radius_m, d.tyre.width_m));
    soil_->set_press_only(static_cast<int>(w), true);
  }
  for (size_t k = 0; k < link_boxes_.size(); ++k) {
    soil_->reserve_body(static_cast<int>(d.wheels.size() + k), 2.0 * link_boxes_[k].box.half_extents_m.norm());
    resistances_.push_back(std::make_unique<SoilResistance>(&loader_->multibody(), link_boxes_[k].link - 1));
    world_->addMultiBodyConstraint(resistances_.back().get());
  }
  material_soil_ = container_soil(grid_->soil());
  material_cell_m_ = grid_->cell_size_m();
  build_material(std::move(bucket));
}

void World::enable_material(const terrain::SoilFlowParameters& soil, double cell_size_m) {
  if (exchange_) throw std::logic_error("World::enable_material: material handling is already on");
  std::unique_ptr<terrain::BodyAutomaton> bucket = make_bucket_automaton(soil, cell_size_m);
  material_soil_ = container_soil(soil);
  material_cell_m_ = cell_size_m;
  build_material(std::move(bucket));
}

std::unique_ptr<terrain::BodyAutomaton> World::make_bucket_automaton(const terrain::SoilFlowParameters& soil,
                                                                     double cell_size_m) const {
  const vehicle::LoaderDescription& d = loader_->description();
  if (!d.bucket_interior.present) return nullptr;
  const vehicle::BucketInterior& in = d.bucket_interior;
  try {
    terrain::LoadSpreading spreading;
    spreading.eps = in.spreading_eps;
    spreading.block_height_cells = in.spreading_block_cells;
    terrain::validate(spreading);
    return std::make_unique<terrain::BodyAutomaton>(bucket_container(in), container_soil(soil), cell_size_m, kStepSeconds);
  } catch (const std::invalid_argument& e) {
    std::ostringstream msg;
    msg << d.parameters_path << ": <bucket> <interior>/<filling> cannot make the bucket's automaton at "
        << cell_size_m << " m cells: " << e.what();
    throw std::invalid_argument(msg.str());
  }
}

void World::enable_fast_flow(const terrain::MomentumFlowParameters& params) {
  if (!grid_ || !exchange_) throw std::logic_error("World::enable_fast_flow: add the soil site first");
  ground_flow_ = std::make_unique<terrain::MomentumFlow>(*grid_, params, kStepSeconds);
  // As the automaton's lists: sized once so that a busy step does not allocate.
  ground_flow_->reserve_cells(std::max<size_t>(16384, static_cast<size_t>(grid_->nx()) * grid_->ny() / 8));
  exchange_->set_ground_flow(ground_flow_.get());
  set_apparent_gravity(true);
}

void World::set_apparent_gravity(bool on) {
  apparent_gravity_ = bucket_.apparent_gravity = on;
  bucket_.frame = FrameAcceleration{};
  for (FrameAcceleration& f : bed_frames_) f = FrameAcceleration{};
  // Off again, the loads feel the world's gravity alone.
  if (bucket_.automaton) bucket_.automaton->set_frame_acceleration(Eigen::Vector3d::Zero());
  for (auto& t : trays_) t->set_frame_acceleration(Eigen::Vector3d::Zero());
}

void World::build_material(std::unique_ptr<terrain::BodyAutomaton> bucket) {
  exchange_ = std::make_unique<terrain::MaterialExchange>(grid_.get(), kStepSeconds);
  exchange_->set_firm_ground_plane(firm_ground_normal_, firm_ground_offset_m_);
  if (!bucket) return;
  const vehicle::LoaderDescription& d = loader_->description();
  const vehicle::BucketInterior& in = d.bucket_interior;
  bucket_.automaton = std::move(bucket);
  const size_t cells = static_cast<size_t>(bucket_.automaton->grid().nx()) * bucket_.automaton->grid().ny();
  bucket_.automaton->grid().reserve_active_cells(cells);
  // The load kernel's buffers, so that the first load does not allocate in a step.
  bucket_.loads_N.reserve(cells);
  bucket_.scratch.above.reserve(cells);
  bucket_.scratch.here.reserve(cells);
  bucket_.scratch.row.reserve(cells);
  bucket_.link = static_cast<int>(d.links.size()) - 1;
  bucket_.link_from_container = Eigen::Isometry3d::Identity();
  bucket_.link_from_container.translation() = in.origin_m;
  bucket_.spreading.eps = in.spreading_eps;
  bucket_.spreading.block_height_cells = in.spreading_block_cells;
  bucket_.exchange_index = exchange_->add_body(bucket_.automaton.get());
  terrain::CuttingEdge edge;
  edge.capacity_m3 = in.heaped_volume_m3;
  edge.filling_angle_drop_deg = in.filling_angle_drop_deg;
  exchange_->set_cutting_edge(bucket_.exchange_index, edge);
  material_on_bucket();
}

int World::add_tray(const TraySpec& tray) {
  if (!exchange_) throw std::logic_error("World::add_tray: add a soil site or call enable_material first");
  const double d = material_cell_m_;
  auto automaton = std::make_unique<terrain::BodyAutomaton>(tray.shape, material_soil_, d, kStepSeconds);
  automaton->grid().reserve_active_cells(static_cast<size_t>(automaton->grid().nx()) * automaton->grid().ny());
  automaton->set_pose(tray.pose, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero());
  // Floor and walls are rigid for the machine (it can hit the truck).
  const terrain::ContainerShape& s = tray.shape;
  const double L = s.length_m, W = s.width_m, side = std::max(s.side_height_back_m, s.side_height_front_m);
  struct Part {
    Eigen::Vector3d centre, half;
  } parts[] = {{{0.5 * L, 0.5 * W, -0.5 * tray.floor_thickness_m}, {0.5 * L, 0.5 * W, 0.5 * tray.floor_thickness_m}},
               {{0.5 * d, 0.5 * W, 0.5 * s.back_height_m}, {0.5 * d, 0.5 * W, 0.5 * s.back_height_m}},
               {{L - 0.5 * d, 0.5 * W, 0.5 * s.front_height_m}, {0.5 * d, 0.5 * W, 0.5 * s.front_height_m}},
               {{0.5 * L, 0.5 * d, 0.5 * side}, {0.5 * L, 0.5 * d, 0.5 * side}},
               {{0.5 * L, W - 0.5 * d, 0.5 * side}, {0.5 * L, 0.5 * d, 0.5 * side}}};
  const Eigen::Quaterniond q(tray.pose.linear());
  TrayParts kept;
  for (const Part& p : parts) {
    if (p.half.z() <= 0.0) continue;
    add_static_ground(new btBoxShape(bt(p.half)),
                      btTransform(btQuaternion(q.x(), q.y(), q.z(), q.w()), bt(Eigen::Vector3d(tray.pose * p.centre))),
                      true);
    kept.parts.push_back({statics_.back().get(), Eigen::Isometry3d(Eigen::Translation3d(p.centre))});  // a truck may move it
  }
  tray_parts_.push_back(std::move(kept));
  exchange_->add_body(automaton.get());
  trays_.push_back(std::move(automaton));
  return static_cast<int>(trays_.size()) - 1;
}

bool World::machine_touches_obstacle() const {
  btDispatcher* dispatcher = world_->getDispatcher();  // Bullet has no const access to its manifolds
  for (int m = 0; m < dispatcher->getNumManifolds(); ++m) {
    const btPersistentManifold* manifold = dispatcher->getInternalManifoldPointer()[m];
    const btCollisionObject* a = manifold->getBody0();
    const btCollisionObject* b = manifold->getBody1();
    const bool obstacle = a->getUserIndex() == kObstacleTag || b->getUserIndex() == kObstacleTag;
    const bool machine = btMultiBodyLinkCollider::upcast(a) != nullptr || btMultiBodyLinkCollider::upcast(b) != nullptr;
    if (!obstacle || !machine) continue;
    for (int k = 0; k < manifold->getNumContacts(); ++k)
      if (manifold->getContactPoint(k).getDistance() <= 0.0) return true;
  }
  return false;
}

double World::bucket_fill_fraction() const {
  const double struck_m3 = loader_->description().bucket_volume_m3;
  if (!bucket_.automaton || !(struck_m3 > 0.0)) return 1.0;
  return std::min(1.0, bucket_.automaton->grid().total_volume_m3() / struck_m3);
}

void World::material_on_bucket() {
  if (!bucket_.automaton) return;
  Eigen::Vector3d v, w;
  loader_->link_velocity(bucket_.link, v, w);
  const Eigen::Isometry3d pose = loader_->link_pose(bucket_.link);
  // A machine gone non-finite is an event (watch_stability), not a throw:
  // the load keeps its last pose.
  if (!pose.matrix().allFinite() || !v.allFinite() || !w.allFinite()) return;
  pose_bucket_material(bucket_, pose, loader_->link_centre_of_mass(bucket_.link), v, w, kStepSeconds);
}

void World::slicing_edge_shares(const Eigen::Isometry3d& pose, const Eigen::Vector2d& forward,
                                const terrain::BodyReaction& r, double share[4]) {
  // The edge meets what its tip bears on, and the load already in must make
  // room for what comes in: the larger of the edge's share of the wedge and
  // the fill (struck full pushes like a blade). The tip: in the earthmoving
  // soils, the bearing capacity of its blunt face (terrain/edge_penetration.h)
  // at the soil standing over it one cell ahead, cell by cell across its
  // width, never more than the blade's wedge; in the thesis's, a fixed share
  // of the wedge (Zelenin's thin edge against bulldozing).
  const vehicle::BucketInterior& in = loader_->description().bucket_interior;
  const double cell = grid_->cell_size_m();
  const Eigen::Vector3d a = pose * (in.origin_m + Eigen::Vector3d(in.length_m, 0.0, 0.0));
  const Eigen::Vector3d b = pose * (in.origin_m + Eigen::Vector3d(in.length_m, in.width_m, 0.0));
  const double speed = forward.norm();
  const Eigen::Vector2d ahead = speed > 0.0 ? Eigen::Vector2d(forward * (cell / speed)) : Eigen::Vector2d::Zero();
  const int strips = std::max(1, static_cast<int>(std::ceil(in.width_m / cell)));
  double edge_N = 0.0;
  int bearing_strips = 0, thesis_strips = 0;
  for (int k = 0; k < strips; ++k) {
    const Eigen::Vector3d p = a + (b - a) * ((k + 0.5) / strips);
    const Eigen::Vector2i c = cell_under(p.x() + ahead.x(), p.y() + ahead.y());
    if (!grid_->contains(c.x(), c.y())) continue;
    const int n = grid_->index(c.x(), c.y());
    terrain::EdgeInSoil edge;
    edge.thickness_m = in.cutting_edge_thickness_m;
    edge.width_m = in.width_m / strips;
    edge.overburden_m = grid_->surface_at(n) - p.z();
    if (!(edge.overburden_m > 0.0)) continue;
    if (soil_->soil_at_cell(n).cutting != terrain::CuttingModel::kEarthmoving) {
      ++thesis_strips;
      continue;
    }
    ++bearing_strips;
    edge_N += terrain::edge_penetration(soil_->cutting_soil_at_cell(n), edge).force_N;
  }
  if (bearing_strips > thesis_strips) edge_penetration_N_ = edge_N;
  const double fill = bucket_fill_fraction();
  for (int f = 0; f < terrain::kFaceCount; ++f) {
    if (!terrain::face_ahead(f, forward.x(), forward.y(), speed)) continue;
    double edge_share = in.edge_resistance;
    if (bearing_strips > thesis_strips) {
      // The edge's force along this face's axis, against the wedge's bound.
      const double along = std::abs(f < 2 ? forward.x() : forward.y()) / speed;
      const double bound = r.wedge[static_cast<size_t>(f)].bound_N;
      edge_share = bound > 0.0 ? std::min(1.0, edge_N * along / bound) : 0.0;
    }
    share[f] = std::max(edge_share, fill);
  }
}

Eigen::Vector2i World::cell_under(double x_m, double y_m) const {
  // Clamped in double to one cell beyond the grid either side: a point far
  // off it must not overflow an int, and callers can still tell it is off.
  const terrain::GridSpec& spec = grid_->spec();
  const auto index = [&](double coordinate, double origin, int n) {
    return static_cast<int>(std::clamp(std::floor((coordinate - origin) / spec.cell_size_m + 0.5), -1.0, static_cast<double>(n)));
  };
  return {index(x_m, spec.origin_m.x(), spec.nx), index(y_m, spec.origin_m.y(), spec.ny)};
}

double World::highest_soil_under(const Eigen::AlignedBox3d& box) const {
  const Eigen::Vector2i lo = cell_under(box.min().x(), box.min().y()), hi = cell_under(box.max().x(), box.max().y());
  const int i0 = std::max(0, lo.x()), i1 = std::min(grid_->nx() - 1, hi.x());
  const int j0 = std::max(0, lo.y()), j1 = std::min(grid_->ny() - 1, hi.y());
  double highest = -std::numeric_limits<double>::infinity();
  for (int j = j0; j <= j1; ++j)
    for (int i = i0; i <= i1; ++i) highest = std::max(highest, grid_->surface_m(i, j));
  return highest;
}

terrain::BodyReaction World::soil_on_body(int body_id, const terrain::BodyGeometry& shape,
                                          const terrain::BodyMotion& motion, double highest_soil_m,
                                          bool wedge_bounds) {
  // Only what a scene needs: a body clear of the soil under it (the chassis
  // over sand, a raised bucket, a wheel on firm ground) costs one scan of
  // the surface, no contact map.
  const bool touches = shape.world_bounds().min().z() < highest_soil_m + grid_->cell_size_m();
  if (!touches) {
    if (body_in_soil_[body_id]) soil_->release(body_id);
    body_in_soil_[body_id] = false;
    return {};
  }
  body_in_soil_[body_id] = true;
  // Wheels take no wedge limits (their traction and rolling resistance are
  // the tyre model's): not computing them saves a tenth of the step on sand.
  return soil_->interact(body_id, shape, motion, wedge_bounds);
}

// Step 3 of the 2 ms step: the machine's parts meet the soil through their
// contact maps. Wheels pass the soil's reaction to the tyre model (which
// adds Janosi-Hanamoto traction); boxes take it directly.
void World::soil_on_machine() {
  const vehicle::LoaderDescription& d = loader_->description();
  const Eigen::Isometry3d chassis = loader_->link_pose(0);
  const Eigen::Quaterniond rotation(chassis.linear());
  Eigen::Vector3d v_com, omega;
  loader_->link_velocity(0, v_com, omega);
  const Eigen::Vector3d com = loader_->link_centre_of_mass(0);
  for (size_t w = 0; w < d.wheels.size(); ++w) {
    terrain::Cylinder& shape = wheel_shapes_[w];
    shape.centre_m = chassis * d.wheels[w].hub_m;
    shape.orientation = rotation;
    shape.radius_m = d.tyre.radius_m;
    shape.half_width_m = 0.5 * d.tyre.width_m;
    shape.clip_above_m = std::numeric_limits<double>::infinity();
    const double highest = highest_soil_under(shape.world_bounds());
    shape.clip_above_m = highest;  // the contact map looks no higher than the soil
    terrain::BodyMotion motion;
    motion.reference_point_m = shape.centre_m;
    motion.linear_velocity_m_s = v_com + omega.cross(shape.centre_m - com);
    motion.angular_velocity_rad_s = omega;
    // The soil's force by Wong-Reece from the soil ahead (before the
    // contact map presses this step's rut), at the patch's slip.
    terrain::WheelOnGrid wheel;
    wheel.hub_m = shape.centre_m;
    const Eigen::Vector3d heading = rotation * Eigen::Vector3d::UnitX();
    wheel.heading = heading.head<2>().norm() > 1e-6 ? Eigen::Vector2d(heading.head<2>().normalized())
                                                    : Eigen::Vector2d::UnitX();
    wheel.shape = {d.tyre.radius_m, d.tyre.width_m, d.tyre.ground_pressure_limit_Pa()};
    const double slip = vehicle::deflection_slip_ratio(d.tyre, loader_->wheels()[w].deflection);
    const terrain::WheelGridForces f =
        terrain::wheel_on_grid(*grid_, *soil_, static_cast<int>(w), wheel, slip, wheel_contacts_[w]);
    const terrain::BodyReaction r = soil_on_body(static_cast<int>(w), shape, motion, highest, false);
    terrain::advance_wheel_contact(motion.linear_velocity_m_s.head<2>().dot(wheel.heading) * kStepSeconds,
                                   motion.linear_velocity_m_s.head<2>().norm() * kStepSeconds, f.contact_length_m,
                                   wheel_contacts_[w]);
    vehicle::SoftWheelContact& s = soft_[w];
    s = {};
    if (!f.in_soil || r.contact_cells == 0) {
      terrain::forget_soil_share(wheel_contacts_[w]);
      continue;
    }
    const terrain::SoilMechanics& soil = soil_->soil_at_cell(f.cell);
    // A wheel rolling onto the soil from firm ground (or off it) carries on
    // the soil the share of its footprint that lies on soil, followed over
    // travel (terrain/wheel_contact.h).
    const double share = terrain::follow_soil_share(terrain::soil_share_under(*grid_, wheel, f.contact_length_m),
                                                    wheel_contacts_[w]);
    s.active = true;
    s.vertical_N = share * f.vertical_N;
    s.drawbar_pull_N = share * f.forward_N;
    s.drive_torque_Nm = share * f.drive_torque_Nm;
    s.contact_area_m2 = share * f.contact_length_m * d.tyre.width_m;
    s.vertical_damping_N_s_per_m = 1000.0 * soil.damping_kPa_s_per_m * s.contact_area_m2;
    s.contact_point_m = shape.centre_m - d.tyre.radius_m * Eigen::Vector3d::UnitZ();
    s.shear.cohesion_Pa = 1000.0 * soil.cohesion_kPa;
    s.shear.friction_angle_rad = deg_to_rad(soil.friction_angle_deg);
    s.shear.shear_modulus_K_m = soil.shear_modulus_K_m;
    s.shear.contact_length_m = f.contact_length_m;
  }
  edge_penetration_N_ = 0.0;
  face_forces_ = {};
  for (size_t k = 0; k < link_boxes_.size(); ++k) {
    LinkBox& lb = link_boxes_[k];
    const Eigen::Isometry3d pose = loader_->link_pose(lb.link);
    lb.shape.centre_m = pose * lb.box.pose.position_m;
    lb.shape.orientation = Eigen::Quaterniond(pose.linear()) * lb.box.pose.rotation;
    lb.shape.half_extents_m = lb.box.half_extents_m;
    Eigen::Vector3d v, w;
    loader_->link_velocity(lb.link, v, w);
    terrain::BodyMotion motion;
    motion.reference_point_m = lb.shape.centre_m;
    motion.linear_velocity_m_s = v + w.cross(lb.shape.centre_m - loader_->link_centre_of_mass(lb.link));
    motion.angular_velocity_rad_s = w;
    const int id = static_cast<int>(d.wheels.size() + k);
    const bool slicing = lb.cutting && exchange_->mouth_open(bucket_.exchange_index);
    const Eigen::Vector2d forward = (lb.shape.orientation * Eigen::Vector3d::UnitX()).head<2>();  // towards the edge
    if (lb.cutting) soil_->set_slicing(id, slicing, forward);
    // The soil ahead of the bucket meets the back plate's inner face (the
    // load's own face in front of it): its rake follows the curl.
    if (lb.tool_face) soil_->set_tool_face(id, pose.linear() * Eigen::Vector3d::UnitX());
    const terrain::BodyReaction r =
        soil_on_body(id, lb.shape, motion, highest_soil_under(lb.shape.world_bounds()), true);
    if (lb.cutting && body_in_soil_[static_cast<size_t>(id)])
      for (const terrain::SoilContactModel::SlicedCell& c : soil_->sliced(id))
        exchange_->add_sliced(bucket_.exchange_index, static_cast<int>(c.cell), c.quanta);
    SoilResistance& resistance = *resistances_[k];
    // The earthmoving soils' force on a face is inclined at the soil-tool
    // friction angle to its normal: its vertical part goes with the
    // horizontal reaction the wedges gave last step (one step behind, as
    // the solver gives that reaction only after the step).
    Eigen::Vector3d vertical_N[4], vertical_at_m[4];
    double reaction_N = 0.0;
    const int verticals = resistance.vertical_forces(kStepSeconds, vertical_N, vertical_at_m, &reaction_N);
    resistance.clear();
    if (r.contact_cells == 0) continue;
    loader_->add_wrench(lb.link, r.force_N - r.base_force_N, r.torque_Nm - r.base_torque_Nm, lb.shape.centre_m);
    for (int i = 0; i < verticals; ++i) {
      loader_->add_force(lb.link, vertical_N[i], vertical_at_m[i]);
      face_forces_.vertical_down_N -= vertical_N[i].z();
    }
    if (verticals > 0) face_forces_.horizontal_N += reaction_N;
    // The wedges and shear hold the link up to their bounds (a Bullet
    // constraint). A slicing edge meets no fracture wedge (6.4); what
    // resists it moving forward is the cutting itself and the load it
    // drives into the bucket, which the material already there must make
    // room for: the wedge limit ahead scaled by slicing_edge_shares (the
    // edge's part when empty, 1 struck full, pushing like a blade). Other
    // ways it is a blade.
    double wedge_scale[4] = {1.0, 1.0, 1.0, 1.0};
    if (slicing) slicing_edge_shares(pose, forward, r, wedge_scale);
    resistance.set(r, wedge_scale, motion.velocity_at(r.shear_point_m).head<2>(), kStepSeconds);
  }
}

void World::step(const vehicle::LoaderControls& controls) {
  for (const LinkLoad& l : loads_) loader_->add_force(l.link, l.force_N, loader_->link_pose(l.link) * l.point_in_link_m);
  if (bucket_.automaton) {
    // (6.5) The material's base loads press on the bucket (posed at the end
    // of the last step).
    update_bucket_load(bucket_, kGravity_m_s2);
    bucket_load_force_N_ = Eigen::Vector3d(0.0, 0.0, -bucket_.weight_N);
    // With the apparent gravity the load presses with m (g - a), its
    // inertia too (d'Alembert): braking, it pushes the machine on. The
    // acceleration is the filtered one the load feels, so that the coupled
    // step does not rock; its integral over a stop is the velocity's change,
    // so the load still hands over its whole momentum (tested).
    if (bucket_.apparent_gravity) bucket_load_force_N_ -= bucket_.weight_N / kGravity_m_s2 * bucket_.frame.filtered_m_s2;
    if (bucket_.weight_N > 0.0) loader_->add_force(bucket_.link, bucket_load_force_N_, bucket_.load_point_world_m());
  }
  if (grid_) soil_on_machine();
  if (!agents_.empty()) move_agents(true);
  loader_->pre_step(controls, kStepSeconds, grid_ ? soft_.data() : nullptr);
  // maxSubSteps = 0: exactly one internal step of kStepSeconds, no interpolation.
  world_->stepSimulation(kStepSeconds, 0, kStepSeconds);
  loader_->post_step(kStepSeconds);
  if (ground_flow_) ground_flow_->step(*grid_);  // fast flows with momentum
  if (grid_) grid_->step();  // avalanche sweep over the active cells
  if (exchange_) {
    if (bucket_.automaton) {
      material_on_bucket();  // the bucket's new pose: slopes in the world (6.2)
      bucket_.automaton->grid().step();
    }
    for (auto& t : trays_) t->grid().step();
    exchange_->step();
  }
  ++steps_;
  watch_stability();
}

void World::watch_stability() {
  const vehicle::Loader& l = *loader_;
  // The rear wheels unloaded: under a hundredth of the machine's weight.
  constexpr double kRearUnloadedShareOfWeight = 0.01;
  constexpr double kTippedOverTilt_rad = 0.25 * kPi;  // the chassis' z axis 45 deg from vertical
  const double rear_load = l.axle_loads().rear_N;
  const double weight = kGravity_m_s2 * l.description().total_mass_kg();
  if (events_.rear_wheels_unloaded_s < 0.0 && rear_load < kRearUnloadedShareOfWeight * weight)
    events_.rear_wheels_unloaded_s = time_s();
  const Eigen::Isometry3d chassis = l.link_pose(0);
  if (events_.tipped_over_s < 0.0 && chassis.linear()(2, 2) < std::cos(kTippedOverTilt_rad))
    events_.tipped_over_s = time_s();
  if (!chassis.matrix().allFinite() || !l.chassis_velocity().allFinite()) events_.finite = false;
}

}  // namespace skidsim::engine
