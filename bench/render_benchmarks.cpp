// Rendering (`skidsim bench --filter Render`): frames a second at 1280 x 720
// of the default exercise's scene (pile to zone, chase camera) on whatever
// backend `auto` finds (this machine: Mesa's llvmpipe, software), and the
// cost of updating the terrain mesh after a bucket pass (one region) against
// rebuilding it. Figures go in the README; nothing here asserts a time.
#include <benchmark/benchmark.h>

#include <filesystem>

#include "visual/scene_snapshot.h"
#include "session/session_world.h"
#include "io/loader_files.h"
#include "render/renderer.h"
#include "render/terrain_mesh.h"

namespace {

using namespace skidsim;

std::string source(const std::string& relative) {
  return (std::filesystem::path(io::default_loader_path()).parent_path().parent_path().parent_path() / relative)
      .string();
}

// Frames of the pile-to-zone scene from the chase camera, `dust_puffs`
// puffs of 0.2-0.9 m around the machine. One iteration: one frame (shadow
// pass, colour pass, read back), timed by the wall clock: llvmpipe
// rasterises on threads of its own.
void render_frames(benchmark::State& state, int dust_puffs) {
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
  const vehicle::LoaderDescription loader = io::load_loader(ex.machine.loader);
  auto world = session::build_session_world(ex, loader, soils);
  render::Scene scene = visual::static_scene(ex, *world);
  const Eigen::Vector3f at = world->loader().link_pose(0).translation().cast<float>();
  for (int k = 0; k < dust_puffs; ++k)
    scene.particles.push_back({at + Eigen::Vector3f(1.5f + 0.004f * static_cast<float>(k % 97), 0.01f * static_cast<float>(k % 131) - 0.6f,
                                                    0.002f * static_cast<float>(k % 211)),
                               0.2f + 0.7f * static_cast<float>(k % 50) / 50.0f, 0.3f, static_cast<float>(k % 4) / 4.0f,
                               Eigen::Vector3f(0.8f, 0.7f, 0.55f)});
  const render::Camera camera = visual::exercise_camera("chase", ex, *world);
  auto context = render::make_offscreen_context("auto", static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  render::Renderer renderer(*context);
  std::vector<std::uint8_t> rgb;
  for (auto _ : state) {
    renderer.render(scene, camera);
    context->read_rgb(rgb);
  }
  state.SetLabel(std::string(render::backend_name(context->backend())) + ", " + context->renderer());
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

void BM_RenderFrame(benchmark::State& state) { render_frames(state, 0); }
// With a dump's dust: 600 puffs, the most a frame of the pile-to-zone
// script holds.
void BM_RenderFrameWithDust(benchmark::State& state) { render_frames(state, 600); }
BENCHMARK(BM_RenderFrameWithDust)->Args({1280, 720})->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

BENCHMARK(BM_RenderFrame)->Args({1280, 720})->Args({640, 360})->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();

// The soil of pile to zone (240 x 240 cells of 5 cm): after a bucket pass
// changed a 1.7 m x 1 m patch, update that region (arg 1) or rebuild the
// whole mesh (arg 0).
void BM_TerrainMeshAfterBucketPass(benchmark::State& state) {
  render::HeightField f;
  f.nx = f.ny = 240;
  f.cell_m = 0.05;
  f.height_m.assign(240 * 240, 0.05f);
  render::Mesh mesh;
  render::build_terrain_mesh(f, mesh);
  int pass = 0;
  for (auto _ : state) {
    ++pass;
    for (int j = 100; j < 134; ++j)
      for (int i = 80; i < 100; ++i) f.height_m[static_cast<std::size_t>(j * 240 + i)] = 0.05f + 0.01f * static_cast<float>((i + j + pass) % 7);
    if (state.range(0) == 1) {
      render::update_terrain_mesh(f, 80, 100, 100, 134, mesh);
    } else {
      render::build_terrain_mesh(f, mesh);
    }
    benchmark::DoNotOptimize(mesh.positions_m.data());
  }
}
BENCHMARK(BM_TerrainMeshAfterBucketPass)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);

}  // namespace
