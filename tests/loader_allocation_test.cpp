// The 2 ms step allocates nothing once warm: counted through the global
// operator new and Bullet's own allocator hooks. A binary of its own, since
// it replaces operator new.
#include <gtest/gtest.h>
#include <LinearMath/btAlignedAllocator.h>

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <new>

#include "engine/demo_controls.h"
#include "engine/soil_site.h"
#include "io/soil_table.h"
#include "terrain/material_exchange.h"
#include "terrain/momentum_flow.h"
#include "tests/loader_support.h"

namespace {
std::atomic<long> g_allocations{0};

void* bullet_alloc(size_t size, int alignment) {
  ++g_allocations;
  return std::aligned_alloc(static_cast<size_t>(alignment), (size + alignment - 1) / alignment * alignment);
}
void* bullet_alloc_unaligned(size_t size) {
  ++g_allocations;
  return std::malloc(size);
}
void bullet_free(void* p) { std::free(p); }
}  // namespace

void* operator new(size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size ? size : 1)) return p;
  throw std::bad_alloc();
}
void* operator new[](size_t size) { return operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, size_t) noexcept { std::free(p); }
void operator delete[](void* p, size_t) noexcept { std::free(p); }

namespace skidsim::testing {
namespace {

struct BulletHooks {
  BulletHooks() {
    btAlignedAllocSetCustomAligned(bullet_alloc, bullet_free);
    btAlignedAllocSetCustom(bullet_alloc_unaligned, bullet_free);
  }
} hooks;


long allocations_in_steps(engine::World& w, long& step, int n) {
  const long before = g_allocations.load();
  for (int i = 0; i < n; ++i) w.step(engine::circle_work_cycle(step++));
  return g_allocations.load() - before;
}

TEST(LoaderAllocation, FirmGroundStepAllocatesNothingOnceWarm) {
  const long before = g_allocations.load();
  auto w = loader_on_ground();
  EXPECT_GT(g_allocations.load() - before, 0);  // the counter sees the world being built
  long step = 0;
  allocations_in_steps(*w, step, 6000);  // every motion and contact seen once
  EXPECT_EQ(allocations_in_steps(*w, step, 6000), 0);
}

TEST(LoaderAllocation, SandStepAllocatesNothingOnceWarm) {
  const io::SoilRecord sand = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
  auto grid = engine::flat_soil_grid(sand.flow, 10.0, Eigen::Vector2d(-10.0, -10.0), 20.0, 20.0, 0.5);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, -3.0, 0.5 + shipped_loader().tyre.radius_m);
  engine::World w(shipped_loader(), engine::FirmGround{}, pose, 0.3, 0.0);
  w.add_soil_site(std::move(grid), sand.terramechanics);
  // Driving a circle with the bucket curling and dumping above the sand.
  // (Bullet allocates when a new collision pair starts, e.g. the bucket
  // coming within 5 cm of the site's base, or near an obstacle: an event,
  // not a step. The soil's scratch grows with the largest contact so far.)
  long step = 0;
  const auto controls = [](long s) {
    vehicle::LoaderControls c = engine::circle_work_cycle(s);
    c.lift = 0.0;
    return c;
  };
  for (int i = 0; i < 12000; ++i) w.step(controls(step++));  // two laps of the circle
  const long before = g_allocations.load();
  for (int i = 0; i < 3000; ++i) w.step(controls(step++));
  const long n = g_allocations.load() - before;
  RecordProperty("allocations", std::to_string(n));
  EXPECT_EQ(n, 0);
}

// The same with the arm cycling down into the sand: the bucket's edge
// slices into it, its automaton sweeps, spills fall and land (thesis ch. 6).
void digging_allocates_nothing_once_warm(bool fast_flow) {
  const io::SoilRecord sand = io::load_soil_table(io::default_soil_table_path()).at("dry_sand");
  // A metre of sand: the bucket pressed down never reaches the hard base
  // (a new Bullet pair with the base allocates each time it is made).
  auto grid = engine::flat_soil_grid(sand.flow, 10.0, Eigen::Vector2d(-10.0, -10.0), 20.0, 20.0, 1.0);
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(0.0, -3.0, 1.0 + shipped_loader().tyre.radius_m);
  engine::World w(shipped_loader(), engine::FirmGround{}, pose, 0.03, 0.03);
  w.add_soil_site(std::move(grid), sand.terramechanics);
  if (fast_flow) w.enable_fast_flow(terrain::session_flow_parameters());  // as the sessions run it
  // Every 6 s: 3 s with the arm down and the bucket tipped into the sand
  // while driving the circle, then 3 s raising it, curling and dumping.
  const auto digging = [](long s) {
    vehicle::LoaderControls c = engine::circle_work_cycle(s);
    const long t = s % 3000;
    c.lift = t < 1500 ? -0.3 : 0.6;
    c.tilt = t < 1500 ? (t < 200 ? 0.5 : 0.0) : (t < 2200 ? -0.6 : 0.8);
    return c;
  };
  long step = 0;
  for (int i = 0; i < 12000; ++i) w.step(digging(step++));
  const long before = g_allocations.load();
  for (int i = 0; i < 3000; ++i) w.step(digging(step++));
  const long n = g_allocations.load() - before;
  ::testing::Test::RecordProperty("allocations", std::to_string(n));
  EXPECT_EQ(n, 0);
  EXPECT_GT(w.material()->stats().quanta_sliced, 0);
  EXPECT_GT(w.material()->stats().parcels_landed, 0);
  if (fast_flow) {
    EXPECT_GT(w.fast_flow()->substeps_run(), 0);  // the spills landed and flowed
  }
  std::printf("[ measured ] sliced %.0f kg, parcels %ld landed, in the bucket %.0f kg\n",
              w.material()->stats().quanta_sliced * w.material()->quantum_mass_kg(),
              static_cast<long>(w.material()->stats().parcels_landed), w.bucket_material()->material_mass_kg());
}

TEST(LoaderAllocation, DiggingStepAllocatesNothingOnceWarm) { digging_allocates_nothing_once_warm(false); }

// With fast flows on the site (terrain/momentum_flow.h): the spills that land
// flow with their momentum, and the step still allocates nothing.
TEST(LoaderAllocation, DiggingStepWithFastFlowsAllocatesNothingOnceWarm) { digging_allocates_nothing_once_warm(true); }

// A load landing with its impact (a soil with an impact sheet speed ratio,
// as dem_sand has; docs/fast_flows.md, "Landing"): the landings' pressure,
// its footprints and their shaping allocate nothing once the flow has seen
// one such landing.
TEST(LoaderAllocation, ALandingsImpactAllocatesNothingOnceWarm) {
  terrain::GridSpec spec;
  spec.nx = spec.ny = 61;
  spec.cell_size_m = 0.05;
  spec.origin_m = Eigen::Vector2d::Constant(-1.5);
  terrain::SoilFlowParameters soil = io::load_soil_table(io::default_soil_table_path()).at("dem_sand").flow;
  ASSERT_GT(soil.impact_sheet_speed_ratio, 0.0);
  terrain::GranularGrid g(spec, soil, 0.002, 100000);
  g.reserve_active_cells(static_cast<std::size_t>(spec.nx * spec.ny));  // as the World sizes its grids
  terrain::MomentumFlow flow(g, terrain::MomentumFlowParameters{}, 0.002);
  flow.reserve_cells(static_cast<std::size_t>(spec.nx * spec.ny));
  terrain::MaterialExchange ex(&g, 0.002);
  ex.set_ground_flow(&flow);
  // A column 0.5 m tall and 0.25 m in radius let go 1 m up, twice: the
  // second is counted.
  const auto drop_and_land = [&] {
    for (int j = 0; j < spec.ny; ++j)
      for (int i = 0; i < spec.nx; ++i) {
        const Eigen::Vector2d p = spec.origin_m + spec.cell_size_m * Eigen::Vector2d(i, j);
        if (p.norm() > 0.25) continue;
        for (int k = 0; k < 20; ++k)
          ex.release(Eigen::Vector3d(p.x(), p.y(), 1.0 + (k + 0.5) * 0.025), Eigen::Vector3d::Zero(),
                     std::llround(0.025 / terrain::kHeightQuantumM));
      }
    for (int s = 0; s < 3000 && (!ex.parcels().empty() || flow.moving_cells() > 0); ++s) {
      flow.step(g);
      g.step();
      ex.step();
    }
  };
  drop_and_land();
  const long pressed = flow.pressed_steps();
  const long before = g_allocations.load();
  drop_and_land();
  const long n = g_allocations.load() - before;
  ::testing::Test::RecordProperty("allocations", std::to_string(n));
  EXPECT_EQ(n, 0);
  EXPECT_GT(pressed, 0);
  EXPECT_GT(flow.pressed_steps(), pressed);  // the counted landing pressed on the layer
  EXPECT_TRUE(g.ledger().balanced());
}

}  // namespace
}  // namespace skidsim::testing
