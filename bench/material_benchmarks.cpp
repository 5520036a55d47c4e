// Material on moving bodies (thesis ch. 6), run by `skidsim bench`: the cost
// of one 2 ms step of bucket-ground exchange while a bucket fills. Figures
// go in the README; nothing here asserts a time.
#include <benchmark/benchmark.h>

#include <cmath>
#include <memory>

#include "common/physical_constants.h"
#include "engine/bucket_material.h"
#include "terrain/body_automaton.h"
#include "terrain/body_shapes.h"
#include "terrain/granular_grid.h"
#include "terrain/load_spreading.h"
#include "terrain/material_exchange.h"
#include "terrain/soil_contact.h"

namespace {

using namespace skidsim::terrain;

constexpr double kDt = 0.002;
constexpr double kDepth = 0.15;  // m of sand the bucket fills from
constexpr double kSpeed = 0.5;  // m/s, the bucket's advance

// A 1.70 m bucket (the shipped loader's interior) driven level through
// 0.15 m of sand, its 0.25 m cutting plate 5 mm over the hard base, slicing
// into its automaton: every part of a filling step but the multibody.
struct FillingScene {
  std::unique_ptr<GranularGrid> ground;
  std::unique_ptr<SoilContactModel> soil;
  skidsim::engine::BucketMaterial material;  // owns the bucket's automaton
  BodyAutomaton* bucket = nullptr;
  std::unique_ptr<MaterialExchange> exchange;
  OrientedBox plate;
  double front_x = 0.5;

  explicit FillingScene(double cell_m) {
    GridSpec spec;
    spec.cell_size_m = cell_m;
    spec.nx = static_cast<int>(std::lround(4.0 / cell_m));
    spec.ny = static_cast<int>(std::lround(2.4 / cell_m));
    ground = std::make_unique<GranularGrid>(spec, SoilFlowParameters{}, kDt);
    for (int j = 0; j < spec.ny; ++j)
      for (int i = 0; i < spec.nx; ++i) ground->set_material_m(i, j, kDepth);
    ground->reserve_active_cells(static_cast<std::size_t>(spec.nx) * spec.ny);
    soil = std::make_unique<SoilContactModel>(*ground, SoilMechanics{});
    soil->set_slicing(0, true);
    material.automaton = std::make_unique<BodyAutomaton>(ContainerShape{}, SoilFlowParameters{}, cell_m, kDt);
    bucket = material.automaton.get();
    bucket->grid().reserve_active_cells(static_cast<std::size_t>(bucket->grid().nx()) * bucket->grid().ny());
    exchange = std::make_unique<MaterialExchange>(ground.get(), kDt);
    exchange->set_cutting_edge(exchange->add_body(bucket), CuttingEdge{});
    plate.half_extents_m = Eigen::Vector3d(0.125, 0.85, 0.02);
    pose(0.0);
  }

  void pose(double advance_m) {
    front_x = 0.5 + advance_m;
    Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
    p.translation() = Eigen::Vector3d(front_x - bucket->shape().length_m, 1.2 - 0.85, 0.045);
    bucket->set_pose(p, Eigen::Vector3d(kSpeed, 0, 0), Eigen::Vector3d::Zero());
    plate.centre_m = Eigen::Vector3d(front_x - 0.125, 1.2, 0.025);
  }

  // One 2 ms step: the plate's contact map and slices and the ground's
  // sweep (the soil's side), then the bucket's sweep, the exchange and the
  // load on the bucket (the material's side), each timed or not.
  void soil_side(double advance_m) {
    pose(advance_m);
    BodyMotion motion;
    motion.reference_point_m = plate.centre_m;
    motion.linear_velocity_m_s = Eigen::Vector3d(kSpeed, 0, 0);
    soil->set_slicing(0, exchange->mouth_open(0));
    soil->interact(0, plate, motion, false);
    for (const SoilContactModel::SlicedCell& c : soil->sliced(0))
      exchange->add_sliced(0, static_cast<int>(c.cell), c.quanta);
    ground->step();
  }
  void material_side() {
    bucket->grid().step();
    exchange->step();
    skidsim::engine::update_bucket_load(material, kGravity_m_s2);  // as the engine does
  }
};

// A bucket filling from 0.15 m of sand at 0.5 m/s; the scene starts afresh
// (untimed) every 1.5 m, before the bucket is full. Whole: the step of
// everything but the multibody. Material: only the bucket's automaton, the
// exchange and the load (the ground's sweep and the edge's contact map,
// which any body pushing soil costs, untimed).
void bucket_filling(benchmark::State& state, bool material_only) {
  const double cell_m = static_cast<double>(state.range(0)) / 1000.0;  // range in mm
  auto scene = std::make_unique<FillingScene>(cell_m);
  long n = 0;
  double kg_per_m = 0.0;
  for (auto _ : state) {
    if (n == 1500) {
      state.PauseTiming();
      kg_per_m = scene->bucket->material_mass_kg() / (kSpeed * kDt * n);
      scene = std::make_unique<FillingScene>(cell_m);
      n = 0;
      state.ResumeTiming();
    }
    if (material_only) state.PauseTiming();
    scene->soil_side(kSpeed * kDt * static_cast<double>(++n));
    if (material_only) state.ResumeTiming();
    scene->material_side();
  }
  state.counters["cell_mm"] = 1000.0 * cell_m;
  state.counters["bucket_cells"] = static_cast<double>(scene->bucket->grid().nx()) * scene->bucket->grid().ny();
  if (kg_per_m > 0.0) state.counters["filled_kg_per_m"] = kg_per_m;
}
void BM_BucketFillingStep(benchmark::State& state) { bucket_filling(state, false); }
void BM_BucketMaterialStep(benchmark::State& state) { bucket_filling(state, true); }
BENCHMARK(BM_BucketFillingStep)->Arg(50)->Arg(25)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BucketMaterialStep)->Arg(50)->Arg(25)->Unit(benchmark::kMicrosecond);

}  // namespace
