// Rendering (`skidsim bench --filter Render`): frames a second at 1280 x 720
// of the default exercise's scene (pile to zone, chase camera) on whatever
// backend `auto` finds (this machine: Mesa's llvmpipe, software), and the
// cost of updating the terrain mesh after a bucket pass (one region) against
// rebuilding it. `--filter View`: what a view (skidsim view) draws a second
// from a session's scene stream. Figures go in the README; nothing here
// asserts a time.
#include <benchmark/benchmark.h>

#include <filesystem>
#include <memory>
#include <vector>

#include "io/operator_script.h"
#include "session/session.h"
#include "visual/scene_snapshot.h"
#include "visual/scene_view.h"
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

// The scene stream of the pile-to-zone script's first 20 s (digging and
// dumping: parcels, dust, the ground changing), captured once.
struct KeepScene : session::SessionOutput {
  std::vector<skidsim_lcm::scene_t> messages;
  void scene(const skidsim_lcm::scene_t& m, double) override { messages.push_back(m); }
};

const std::vector<skidsim_lcm::scene_t>& pile_to_zone_stream() {
  static const std::vector<skidsim_lcm::scene_t> stream = [] {
    const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
    const io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
    session::SessionOptions options;
    options.scene_stream = true;
    options.limit_s = 20.0;
    session::Session s(ex, io::load_loader(ex.machine.loader), soils, options);
    session::ScriptOperator op(io::load_operator_script(source("scenarios/pile_to_zone.operator.xml")));
    const session::DecideControls decide = [&](const skidsim_lcm::state_t& st, long, double t) { return op.decide(st, t); };
    KeepScene out;
    while (s.tick(false, decide, out).empty()) {
    }
    return out.messages;
  }();
  return stream;
}

// A view drawing that stream at 25 frames a second of the session's time
// (the most it draws), chase camera: one iteration is one frame, the
// messages up to it applied (the ground's squares, the loads, the dust),
// the frame drawn and read back. Its frames a second against the 25 a
// realtime session sends is how far a live view keeps up on this machine.
void BM_ViewFromStream(benchmark::State& state) {
  const std::vector<skidsim_lcm::scene_t>& stream = pile_to_zone_stream();
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const io::Exercise ex = io::load_exercise(source("scenarios/pile_to_zone.xml"));
  auto world = session::build_session_world(ex, io::load_loader(ex.machine.loader), soils);
  auto context = render::make_offscreen_context("auto", static_cast<int>(state.range(0)), static_cast<int>(state.range(1)));
  render::Renderer renderer(*context);
  std::unique_ptr<visual::SceneView> view;
  std::size_t next = stream.size();
  std::vector<std::uint8_t> rgb;
  for (auto _ : state) {
    int due = 0;
    while (due == 0) {
      if (next == stream.size()) {  // from the stream's start again
        state.PauseTiming();
        view = std::make_unique<visual::SceneView>(ex, *world, "chase", 25.0);
        next = 0;
        state.ResumeTiming();
      }
      due = view->apply(stream[next++]);
    }
    renderer.render(view->scene(), view->camera());
    context->read_rgb(rgb);
  }
  state.SetLabel(std::string(render::backend_name(context->backend())) + ", " + context->renderer());
  state.counters["fps"] = benchmark::Counter(static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}
BENCHMARK(BM_ViewFromStream)->Args({640, 360})->Args({1280, 720})->Unit(benchmark::kMillisecond)->MinTime(3.0)->UseRealTime();

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
