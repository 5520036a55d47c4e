// A session's frames (issue 7's evidence): rendered from the world of a
// real session, they show the machine and the soil, and once the bucket has
// been filled, its load.
#include <gtest/gtest.h>

#include <set>

#include "session/operator_player.h"
#include "visual/scene_snapshot.h"
#include "session/session_world.h"
#include "io/loader_files.h"
#include "render/renderer.h"

namespace {

using namespace skidsim;

constexpr int kWidth = 480, kHeight = 270;

struct Frame {
  std::vector<std::uint8_t> rgb;
  int count(bool (*is)(int r, int g, int b)) const {
    int n = 0;
    for (std::size_t k = 0; k < rgb.size(); k += 3) n += is(rgb[k], rgb[k + 1], rgb[k + 2]);
    return n;
  }
};

// The machine's paint (0.86, 0.62, 0.08) lit: strongly yellow.
bool machine_yellow(int r, int g, int b) { return r > 120 && g > 80 && b < 40 && r > g && g > 2 * b; }
// Sand (0.76, 0.62, 0.40), lit or shaded: warm, blue well under red.
bool sand(int r, int g, int b) { return r > 60 && r > g && g > b && b > 0.35 * r && b < 0.8 * r; }

class SessionFrames : public ::testing::Test {
 protected:
  void SetUp() override {
    ex_ = io::load_exercise(std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.xml");
    const vehicle::LoaderDescription loader = io::load_loader(ex_.machine.loader);
    world_ = session::build_session_world(ex_, loader, io::load_soil_table(io::default_soil_table_path()));
    context_ = render::make_offscreen_context("auto", kWidth, kHeight);
    renderer_ = std::make_unique<render::Renderer>(*context_);
  }
  // Plays the exercise's operator script until `t_s`.
  void play_until(double t_s) {
    session::OperatorPlayer player(io::load_operator_script(std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.operator.xml"));
    vehicle::LoaderControls controls;
    while (world_->time_s() < t_s - 1e-9) {
      if (world_->steps() % 5 == 0) controls = player.step(session::machine_state(*world_, false));
      world_->step(controls);
    }
  }
  Frame render(const render::Scene& scene, const std::string& camera) {
    return {render::render_rgb(*context_, *renderer_, scene, visual::exercise_camera(camera, ex_, *world_))};
  }
  io::Exercise ex_;
  std::unique_ptr<engine::World> world_;
  std::unique_ptr<render::OffscreenContext> context_;
  std::unique_ptr<render::Renderer> renderer_;
};

TEST_F(SessionFrames, ShowTheMachineAndTheSoil) {
  const Frame f = render(visual::static_scene(ex_, *world_), "chase");
  std::set<std::uint32_t> colours;
  for (std::size_t k = 0; k < f.rgb.size(); k += 3)
    colours.insert(static_cast<std::uint32_t>(f.rgb[k]) << 16 | static_cast<std::uint32_t>(f.rgb[k + 1]) << 8 | f.rgb[k + 2]);
  const int machine = f.count(machine_yellow), soil = f.count(sand);
  std::printf("[ measured ] chase frame at the start: %zu colours, %d machine pixels, %d sand pixels of %d\n",
              colours.size(), machine, soil, kWidth * kHeight);
  EXPECT_GT(colours.size(), 500u);
  EXPECT_GT(machine, 1000) << "the machine fills a good part of the chase view";
  EXPECT_GT(soil, 10000) << "the soil site lies ahead of it";
}

// The four cameras: the fixed one where the exercise puts it (else beyond
// the site's corner), the others following the machine; no other name.
TEST_F(SessionFrames, CamerasFollowTheMachineOrStandWhereTheExerciseSays) {
  const render::Camera fixed_default = visual::exercise_camera("fixed", ex_, *world_);
  EXPECT_LT(fixed_default.eye_m.x(), 0.0);
  ex_.recording.fixed_eye_m = Eigen::Vector3d(2, 3, 6);
  ex_.recording.fixed_target_m = Eigen::Vector3d(8, 9, 0);
  const render::Camera fixed = visual::exercise_camera("fixed", ex_, *world_);
  EXPECT_EQ(fixed.eye_m, Eigen::Vector3d(2, 3, 6));
  EXPECT_EQ(fixed.target_m, Eigen::Vector3d(8, 9, 0));
  const Eigen::Vector3d at = world_->loader().link_pose(0).translation();
  for (const char* name : {"cab", "chase"}) EXPECT_LT((visual::exercise_camera(name, ex_, *world_).eye_m - at).norm(), 8.0) << name;
  EXPECT_THROW(visual::exercise_camera("drone", ex_, *world_), std::invalid_argument);
}

// After the script's first bucket fill (479 kg aboard at 6 s), the
// bucket's automaton is drawn: taking its field out of the scene changes
// sand-coloured pixels where the load is.
TEST_F(SessionFrames, ShowTheBucketsLoadAfterFilling) {
  play_until(6.0);
  ASSERT_NE(world_->bucket_material(), nullptr);
  const double load_kg = world_->bucket_material()->material_mass_kg();
  ASSERT_GT(load_kg, 300.0);
  for (const std::string camera : {"cab", "aerial"}) {  // the chase view has the cab in front of the bucket
    render::Scene scene = visual::static_scene(ex_, *world_);
    const Frame with_load = render(scene, camera);
    scene.fields.resize(1);  // the ground only
    const Frame without = render(scene, camera);
    // Sand where, without the load, the bucket or the sky shows (not merely
    // the ground under the load's shadow).
    int load_pixels = 0;
    for (std::size_t k = 0; k < with_load.rgb.size(); k += 3)
      load_pixels += sand(with_load.rgb[k], with_load.rgb[k + 1], with_load.rgb[k + 2]) &&
                     !sand(without.rgb[k], without.rgb[k + 1], without.rgb[k + 2]);
    std::printf("[ measured ] %s frame at 6 s, %.0f kg aboard: %d pixels of load\n", camera.c_str(), load_kg, load_pixels);
    EXPECT_GT(load_pixels, 100) << camera;  // measured 272 (cab) and 190 (aerial) at 480 x 270
  }
}

// The first dump (about 27-29 s into the script): snapshots at 10 frames a
// second see parcels falling from the bucket and dust rising where they
// land; the soil's flow record gives the sliding heap a moving texture.
TEST_F(SessionFrames, DumpingRaisesDustAndFallingSand) {
  world_->terrain()->record_flow(true);
  render::Scene scene = visual::static_scene(ex_, *world_);
  visual::SceneHistory history;
  std::size_t most_puffs = 0, most_parcels = 0;
  int frames_with_flow = 0;
  session::OperatorPlayer player(io::load_operator_script(std::string(SKIDSIM_SOURCE_DIR) + "/scenarios/pile_to_zone.operator.xml"));
  vehicle::LoaderControls controls;
  double next_frame_s = 0.0;
  while (world_->time_s() < 31.0) {
    if (world_->steps() % 5 == 0) controls = player.step(session::machine_state(*world_, false));
    world_->step(controls);
    if (world_->time_s() >= next_frame_s) {
      visual::update_scene(*world_, scene, &history);
      next_frame_s += 0.1;
      most_puffs = std::max(most_puffs, history.dust.puffs());
      most_parcels = std::max(most_parcels, world_->material()->parcels().size());
      EXPECT_EQ(scene.particles.size(), history.dust.puffs() + world_->material()->parcels().size()) << "every puff and parcel drawn";
      bool flow = false;
      for (const Eigen::Vector2f& v : scene.fields.front().flow_m_s) flow = flow || v.squaredNorm() > 0.0f;
      frames_with_flow += flow;
    }
  }
  std::printf("[ measured ] up to %zu dust puffs and %zu falling parcels in a frame; %d of 310 frames with sliding soil\n",
              most_puffs, most_parcels, frames_with_flow);
  EXPECT_GT(most_puffs, 20u);
  EXPECT_GT(most_parcels, 100u) << "the dump";
  EXPECT_GT(frames_with_flow, 10);
  // Drawn, the dust left at 31 s shows over the scene.
  ASSERT_GT(scene.particles.size(), 50u);
  const Frame dusty = render(scene, "aerial");
  scene.particles.clear();
  const Frame clear = render(scene, "aerial");
  int changed = 0;
  for (std::size_t k = 0; k < clear.rgb.size(); k += 3) changed += clear.rgb[k] != dusty.rgb[k];
  std::printf("[ measured ] %d pixels under the dust in the aerial view\n", changed);
  EXPECT_GT(changed, 500);
}

}  // namespace
