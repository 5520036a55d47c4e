// The world of one session and its fixed 2 ms step (docs/architecture.md, "The
// 2 ms step"): controls -> hydraulics and drive -> tyre and terrain forces ->
// Bullet step -> read back. Firm ground and static obstacles are Bullet
// rigid bodies; the loader is a Featherstone multibody.
#pragma once

#include <Eigen/Geometry>

#include <memory>
#include <vector>

#include "engine/agents.h"
#include "engine/bucket_material.h"
#include "engine/frame_acceleration.h"
#include "engine/soil_resistance.h"
#include "terrain/body_shapes.h"
#include "terrain/granular_grid.h"
#include "terrain/material_exchange.h"
#include "terrain/soil_contact.h"
#include "terrain/wheel_contact.h"
#include "vehicle/loader.h"

class btBroadphaseInterface;
class btCollisionDispatcher;
class btDefaultCollisionConfiguration;
class btMultiBodyConstraintSolver;
class btMultiBodyDynamicsWorld;
class btCollisionObject;
class btCollisionShape;
class btTransform;

namespace skidsim::engine {

constexpr double kStepSeconds = 0.002;  // 500 steps per second (thesis)

struct StaticBox {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // centre, world
  Eigen::Vector3d half_extents_m = Eigen::Vector3d::Constant(0.5);
};

// An open container standing on site (a truck bed, a hopper): static, with
// Bullet boxes for its floor and walls, and an automaton for what it holds.
struct TraySpec {
  // The container frame in the world: origin at the floor's back corner, x
  // along its length, y across, z up (terrain::ContainerShape).
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  terrain::ContainerShape shape;
  double floor_thickness_m = 0.1;
};

// Firm ground: a plane n . x = offset (omit with has_plane = false) and boxes.
struct FirmGround {
  bool has_plane = true;
  Eigen::Vector3d plane_normal = Eigen::Vector3d::UnitZ();
  double plane_offset_m = 0.0;
  std::vector<StaticBox> boxes;
  double friction = 0.8;  // Bullet contact friction (body, bucket on ground)
};

class World {
 public:
  World(const vehicle::LoaderDescription& loader, const FirmGround& ground, const Eigen::Isometry3d& chassis_pose,
        double lift_rad = 0.0, double tilt_rad = 0.0);
  ~World();
  World(const World&) = delete;
  World& operator=(const World&) = delete;

  // One 2 ms step with these controls.
  void step(const vehicle::LoaderControls& controls);
  double time_s() const { return static_cast<double>(steps_) * kStepSeconds; }
  long steps() const { return steps_; }
  vehicle::Loader& loader() { return *loader_; }
  const vehicle::Loader& loader() const { return *loader_; }
  // Soft soil: the granular automaton of a site and the soil's mechanics.
  // Wheels (rigid cylinders of the tyre's size) and the links' collision
  // boxes (chassis belly, bucket) whose footprint meets the grid get the
  // soil's reaction; the terrain sweeps once per step. The grid's hard base
  // becomes rigid ground (a Bullet heightfield) under the site. The base is
  // read once, here. One site per world (throws on a second, or on a grid
  // under 2 x 2 cells).
  void add_soil_site(std::unique_ptr<terrain::GranularGrid> grid, const terrain::SoilMechanics& soil);
  terrain::GranularGrid* terrain() { return grid_.get(); }
  const terrain::GranularGrid* terrain() const { return grid_.get(); }
  terrain::SoilContactModel* soil_contact() { return soil_.get(); }
  // Fast flows on the site (terrain/momentum_flow.h): what lands on the
  // ground from a body (a dump, a spill over the lip, a bed's edge) joins a
  // flowing layer with its momentum and runs out until friction stops it,
  // beside the automaton's slow avalanches. After add_soil_site; throws
  // std::invalid_argument where the site's tallest fall breaks the flow's
  // stability bound.
  // Also turns on the apparent gravity below.
  void enable_fast_flow(const terrain::MomentumFlowParameters& params);
  const terrain::MomentumFlow* fast_flow() const { return ground_flow_.get(); }
  // The loads on moving bodies (the bucket's, a truck bed's) feel their
  // frames' acceleration, low-passed (engine/frame_acceleration.h): braking
  // hard with a heaped bucket throws the heap over the lip, a truck pulling
  // away shifts its load back.
  void set_apparent_gravity(bool on);
  // The force the bucket's load put on the bucket in the last step (N,
  // world): its weight, and with the apparent gravity its inertia.
  const Eigen::Vector3d& bucket_load_force_N() const { return bucket_load_force_N_; }

  // Material on moving bodies (thesis ch. 6): the bucket carries an
  // automaton (when its parameters describe its interior), trays hold
  // material, and the exchange moves it between them and the ground. A soil
  // site turns this on with its own soil and cell size; a scene without
  // one calls enable_material first (material reaching the ground then
  // rests on the firm ground plane). Trays come after either.
  void enable_material(const terrain::SoilFlowParameters& soil, double cell_size_m);
  int add_tray(const TraySpec& tray);
  terrain::BodyAutomaton* bucket_material() { return bucket_.automaton.get(); }
  // Whether a part of the machine (chassis, arm, bucket) is in contact with
  // an obstacle (a box, a truck bed) after the last step: Bullet's contact
  // manifolds, read between steps.
  bool machine_touches_obstacle() const;
  const terrain::BodyAutomaton* bucket_material() const { return bucket_.automaton.get(); }
  terrain::BodyAutomaton& tray(int k) { return *trays_.at(static_cast<size_t>(k)); }
  const terrain::BodyAutomaton& tray(int k) const { return *trays_.at(static_cast<size_t>(k)); }
  int tray_count() const { return static_cast<int>(trays_.size()); }
  terrain::MaterialExchange* material() { return exchange_.get(); }
  const terrain::MaterialExchange* material() const { return exchange_.get(); }
  // The load the bucket's material puts on it this step (N, its weight) and
  // a point on its (vertical) line of action.
  double bucket_load_N() const { return bucket_.weight_N; }
  Eigen::Vector3d bucket_load_point_m() const { return bucket_.load_point_world_m(); }
  // What the bucket's slicing edge bore on this step in an earthmoving soil
  // (N, terrain/edge_penetration.h; 0 when not slicing into one).
  double edge_penetration_N() const { return edge_penetration_N_; }
  // The vertical part of the earthmoving soils' force on the machine's
  // pushing faces applied this step (positive down), and the horizontal
  // reactions it goes with (SoilResistance::vertical_forces).
  struct FaceForces {
    double vertical_down_N = 0.0, horizontal_N = 0.0;
  };
  const FaceForces& face_forces() const { return face_forces_; }

  // Stability events, first time seen (-1: not yet): the rear wheels lose
  // all load (the machine is tipping forward), the chassis leans past 45 deg.
  struct Events {
    double rear_wheels_unloaded_s = -1.0;
    double tipped_over_s = -1.0;
    bool finite = true;  // every state value stayed finite
  };
  const Events& events() const { return events_; }
  // People and vehicles on site (engine/agents.h), moved by their plans
  // every step before Bullet's. A person is a capsule the machine passes
  // through: the contact is detected, not resolved (the session scores it).
  // A truck is its bed (a tray of this world, posed at the loading spot:
  // the tray then moves with the truck, its material with it) with a cab in
  // front and a chassis under it, solid to the machine; its route ends at
  // the bed's centre there, appended if not given. Throws
  // std::invalid_argument for a route that is empty or a truck without a
  // tray. Returns the agent's index.
  int add_agent(const AgentSpec& spec);
  const std::vector<AgentSpec>& agent_specs() const { return agent_specs_; }
  const std::vector<AgentState>& agents() const { return agents_; }
  // An agent's frame: its centre on the ground, x its heading (far below
  // the site when it is not on it).
  Eigen::Isometry3d agent_pose(int k) const;
  // Lets a held agent (AgentSpec::held) come on site from the next step.
  void release_agent(int k);
  // The agents a part of the machine touches after the last step.
  void agents_touching_machine(std::vector<int>& out) const;

  // A constant external force on a link, re-applied every step (payload).
  void set_link_load(int link, const Eigen::Vector3d& force_N, const Eigen::Vector3d& point_in_link_m);

 private:
  void watch_stability();
  // `obstacle`: a box or a truck bed's part the machine can collide with (not
  // the ground plane or a site's base); counted by machine_touches_obstacle.
  void add_static_ground(btCollisionShape* shape, const btTransform& pose, bool obstacle = false);
  void soil_on_machine();
  // The bucket's automaton at this soil and cell size (null when the
  // loader's bucket has no interior); throws std::invalid_argument naming
  // the parameter file when it cannot be made.
  std::unique_ptr<terrain::BodyAutomaton> make_bucket_automaton(const terrain::SoilFlowParameters& soil,
                                                                double cell_size_m) const;
  void build_material(std::unique_ptr<terrain::BodyAutomaton> bucket);
  void material_on_bucket();  // poses the bucket's automaton from the link
  double bucket_fill_fraction() const;  // its material over the struck volume, at most 1
  double edge_penetration_N_ = 0.0;     // this step's, for edge_penetration_N()
  FaceForces face_forces_;              // this step's, for face_forces()
  // The share of the forward wedge (+x, -x, +y, -y) the slicing edge of a
  // bucket posed at `pose`, moving along `forward`, meets (docs/material.md).
  void slicing_edge_shares(const Eigen::Isometry3d& pose, const Eigen::Vector2d& forward,
                           const terrain::BodyReaction& r, double share[4]);
  // One body against the soil: its reaction, or a release when it left the grid.
  terrain::BodyReaction soil_on_body(int body_id, const terrain::BodyGeometry& shape, const terrain::BodyMotion& motion,
                                     double highest_soil_m, bool wedge_bounds);
  // The grid cell under a world point: -1 or n beyond the grid's sides.
  Eigen::Vector2i cell_under(double x_m, double y_m) const;
  // The highest soil surface under a world box (-inf off the grid).
  double highest_soil_under(const Eigen::AlignedBox3d& box) const;

  std::unique_ptr<btDefaultCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btMultiBodyConstraintSolver> solver_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;
  std::vector<std::unique_ptr<btCollisionShape>> shapes_;
  std::vector<std::unique_ptr<btCollisionObject>> statics_;
  std::unique_ptr<vehicle::Loader> loader_;
  struct LinkLoad {
    int link;
    Eigen::Vector3d force_N, point_in_link_m;
  };
  std::vector<LinkLoad> loads_;
  long steps_ = 0;
  Events events_;
  std::unique_ptr<terrain::GranularGrid> grid_;
  std::unique_ptr<terrain::SoilContactModel> soil_;
  std::vector<vehicle::SoftWheelContact> soft_;
  std::vector<terrain::WheelContactState> wheel_contacts_;
  std::vector<terrain::Cylinder> wheel_shapes_;
  struct LinkBox {
    int link;
    vehicle::CollisionBox box;
    terrain::OrientedBox shape;
    bool cutting = false;  // the bucket's floor plate: slices into the bucket (6.4)
    bool tool_face = false;  // the bucket's plates: push soil with the back plate's inner face
  };
  std::vector<LinkBox> link_boxes_;
  std::vector<std::unique_ptr<SoilResistance>> resistances_;  // one per link box
  std::vector<bool> body_in_soil_;  // wheels, then link boxes
  std::vector<double> base_heights_;  // the soil site's hard base, Bullet's heightfield data
  double ground_friction_ = 0.8;
  Eigen::Vector3d firm_ground_normal_ = Eigen::Vector3d::UnitZ();  // where spilled material rests off the site
  double firm_ground_offset_m_ = -1e6;                               // (no plane: far below)
  terrain::SoilFlowParameters material_soil_;  // trays' soil and cells: the site's, or enable_material's
  double material_cell_m_ = 0.05;
  BucketMaterial bucket_;
  std::vector<std::unique_ptr<terrain::BodyAutomaton>> trays_;
  std::unique_ptr<terrain::MaterialExchange> exchange_;
  std::unique_ptr<terrain::MomentumFlow> ground_flow_;
  // Agents: specs, states, and their Bullet bodies.
  struct AgentBody {
    btCollisionObject* object;  // owned by statics_
    Eigen::Isometry3d local;    // in the agent's frame (ground point, x its heading)
  };
  struct TrayParts {
    std::vector<AgentBody> parts;  // floor and walls, in the tray's frame
  };
  std::vector<TrayParts> tray_parts_;
  std::vector<AgentSpec> agent_specs_;
  std::vector<AgentState> agents_;
  std::vector<std::vector<AgentBody>> agent_bodies_;
  std::vector<Eigen::Isometry3d> truck_bed_in_agent_;  // per agent: its tray's frame in the agent's (trucks)
  std::vector<double> bed_load_kg_;
  bool apparent_gravity_ = false;
  Eigen::Vector3d bucket_load_force_N_ = Eigen::Vector3d::Zero();
  std::vector<FrameAcceleration> bed_frames_;  // per agent: its bed's frame (trucks)
  std::vector<SteeringAgent> agent_scratch_;
  void move_agents(bool advance);  // advance: step the plans first
  double ground_height_at(const Eigen::Vector2d& xy) const;
};

}  // namespace skidsim::engine
