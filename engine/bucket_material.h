// The load the bucket carries (thesis 6.4, 6.5): an automaton fixed to the
// bucket link, posed from the link every step, whose base loads (the
// load-spreading kernel) press on the bucket and so on the arm and the
// cylinders.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <memory>
#include <vector>

#include "engine/frame_acceleration.h"
#include "terrain/body_automaton.h"
#include "terrain/load_spreading.h"
#include "vehicle/loader_description.h"

namespace skidsim::engine {

// The container a bucket interior describes (terrain's shape from the
// loader's parameters).
terrain::ContainerShape bucket_container(const vehicle::BucketInterior& interior);

struct BucketMaterial {
  std::unique_ptr<terrain::BodyAutomaton> automaton;
  int exchange_index = -1;  // in the world's MaterialExchange
  int link = -1;
  Eigen::Isometry3d link_from_container = Eigen::Isometry3d::Identity();
  terrain::LoadSpreading spreading;
  // The base loads' resultant, recomputed when the grid changes: the
  // weight (N) and a point on its line of action, in the container frame.
  double weight_N = 0.0;
  Eigen::Vector3d load_point_container_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d load_point_world_m() const { return automaton->pose() * load_point_container_m; }
  std::uint64_t loads_revision = ~std::uint64_t{0};
  int steps_since_spread = 1 << 20;  // since the kernel last ran
  bool spread_stale = true;          // the material moved since
  std::vector<double> loads_N;
  terrain::LoadSpreadingScratch scratch;
  // The apparent gravity of the bucket's accelerating frame (fast flows).
  bool apparent_gravity = false;
  FrameAcceleration frame;
};

// Poses the automaton from the bucket link's pose and velocity (the link's
// centre of mass `com_m` moving at `v_com`, turning at `omega`).
void pose_bucket_material(BucketMaterial& b, const Eigen::Isometry3d& link_pose, const Eigen::Vector3d& com_m,
                          const Eigen::Vector3d& v_com, const Eigen::Vector3d& omega, double step_s);

// Refreshes the load resultant when the material changed (6.5: the base
// loads sum to the weight). The weight is always the material's own; the
// kernel that places it runs at most every kSpreadEverySteps steps while
// material moves (a load shifting within 10 ms; it is a tenth of a filling
// step's cost).
constexpr int kSpreadEverySteps = 5;
void update_bucket_load(BucketMaterial& b, double gravity_m_s2);

}  // namespace skidsim::engine
