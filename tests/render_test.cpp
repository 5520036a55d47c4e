// Off-screen rendering: a fixed scene (a sand cone on a height field, a box,
// its shadow) rendered on EGL and on OSMesa matches a stored reference
// image, and the terrain mesh's diagonals and incremental update.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <set>
#include <string>

#include "io/png_image.h"
#include "render/noise.h"
#include "render/primitives.h"
#include "render/particles_pass.h"
#include "render/renderer.h"
#include "render/terrain_mesh.h"

namespace {

using namespace skidsim;

const std::string kReference = std::string(SKIDSIM_SOURCE_DIR) + "/tests/data/render_reference.png";
constexpr int kWidth = 320, kHeight = 240;


// A 6 m x 6 m field of 10 cm cells holding a 1 m cone, and a box beside it.
render::Scene fixed_scene() {
  render::Scene s;
  render::HeightField f;
  f.nx = f.ny = 61;
  f.cell_m = 0.1;
  f.height_m.resize(61 * 61);
  for (int j = 0; j < 61; ++j)
    for (int i = 0; i < 61; ++i)
      f.height_m[static_cast<std::size_t>(j * 61 + i)] =
          static_cast<float>(std::max(0.0, 1.0 - std::hypot(0.1 * i - 3.0, 0.1 * j - 3.0) / 1.8));
  s.fields.push_back(f);
  s.meshes.push_back(render::unit_cube());
  Eigen::Affine3d box = Eigen::Affine3d::Identity();
  box.translate(Eigen::Vector3d(4.8, 1.5, 0.5));
  box.scale(Eigen::Vector3d(0.8, 0.8, 1.0));
  s.instances.push_back({0, box, Eigen::Vector3f(0.9f, 0.4f, 0.1f)});
  s.shadow_bounds_m = Eigen::AlignedBox3d(Eigen::Vector3d(-1, -1, -0.5), Eigen::Vector3d(7, 7, 2));
  return s;
}

render::Camera fixed_camera() {
  render::Camera c;
  c.eye_m = Eigen::Vector3d(-3.0, -4.0, 4.0);
  c.target_m = Eigen::Vector3d(3.0, 3.0, 0.3);
  return c;
}

io::RgbImage render_on(const std::string& backend) {
  auto context = render::make_offscreen_context(backend, kWidth, kHeight);
  render::Renderer renderer(*context);
  io::RgbImage image;
  image.width = kWidth;
  image.height = kHeight;
  image.rgb = render::render_rgb(*context, renderer, fixed_scene(), fixed_camera());
  return image;
}

double psnr_db(const io::RgbImage& a, const io::RgbImage& b) {
  double se = 0.0;
  for (std::size_t k = 0; k < a.rgb.size(); ++k) {
    const double d = static_cast<double>(a.rgb[k]) - static_cast<double>(b.rgb[k]);
    se += d * d;
  }
  const double mse = se / static_cast<double>(a.rgb.size());
  return mse == 0.0 ? 99.0 : 10.0 * std::log10(255.0 * 255.0 / mse);
}

class RenderBackend : public ::testing::TestWithParam<const char*> {};

// The reference was rendered by this renderer on Mesa's llvmpipe; a GPU
// rasterises edges and shadows a little differently, hence PSNR, not
// equality: 30 dB is a few grey levels on average, and a missing cone, box
// or shadow drops it under 20.
TEST_P(RenderBackend, FixedSceneMatchesTheReferenceImage) {
  const io::RgbImage image = render_on(GetParam());
  if (std::getenv("SKIDSIM_UPDATE_REFERENCE")) io::write_png_rgb8(kReference, image);
  const io::RgbImage reference = io::read_png_rgb8(kReference);
  ASSERT_EQ(reference.width, kWidth);
  ASSERT_EQ(reference.height, kHeight);
  const double psnr = psnr_db(image, reference);
  std::printf("[ measured ] %s against the reference: PSNR %.1f dB\n", GetParam(), psnr);
  EXPECT_GT(psnr, 30.0);
  // Not blank: sky, sand, box and shadow make many colours.
  std::set<std::uint32_t> colours;
  for (std::size_t k = 0; k < image.rgb.size(); k += 3)
    colours.insert(static_cast<std::uint32_t>(image.rgb[k]) << 16 | static_cast<std::uint32_t>(image.rgb[k + 1]) << 8 | image.rgb[k + 2]);
  EXPECT_GT(colours.size(), 200u);
}

INSTANTIATE_TEST_SUITE_P(Backends, RenderBackend, ::testing::Values("egl", "osmesa"));

TEST(RenderBackends, EglAndOsmesaDrawTheSameFrame) {
  const double psnr = psnr_db(render_on("egl"), render_on("osmesa"));
  std::printf("[ measured ] EGL against OSMesa: PSNR %.1f dB\n", psnr);
  EXPECT_GT(psnr, 40.0);
}

TEST(RenderBackends, UnknownBackendIsRefused) {
  EXPECT_THROW(render::make_offscreen_context("vulkan", 64, 64), std::invalid_argument);
  EXPECT_THROW(render::make_offscreen_context("egl", 0, 64), std::invalid_argument);
}

// 8.1.2: a crest along a quad's diagonal is split along that diagonal, so
// the mesh keeps the crest instead of sawing it.
TEST(TerrainMesh, QuadsSplitAlongADiagonalCrest) {
  EXPECT_TRUE(render::split_along_main_diagonal(1.0f, 0.2f, 0.5f, 1.0f));   // crest (0,0)-(1,1)
  EXPECT_FALSE(render::split_along_main_diagonal(0.3f, 1.0f, 1.0f, 0.0f));  // crest (1,0)-(0,1)
  render::HeightField f;
  f.nx = f.ny = 8;
  f.cell_m = 0.1;
  f.height_m.resize(64);
  for (int j = 0; j < 8; ++j)
    for (int i = 0; i < 8; ++i) f.height_m[static_cast<std::size_t>(j * 8 + i)] = 1.0f - 0.2f * static_cast<float>(std::abs(i - j));
  render::Mesh m;
  render::build_terrain_mesh(f, m);
  ASSERT_EQ(m.indices.size(), 7u * 7u * 6u);
  for (int k = 0; k < 7; ++k) {  // quads on the crest (i == j): split along it
    const std::size_t q = static_cast<std::size_t>(k * 7 + k) * 6;
    EXPECT_EQ(m.indices[q + 2], static_cast<std::uint32_t>((k + 1) * 8 + k + 1));
  }
}

// Updating a changed region gives the mesh a full rebuild gives: plain,
// with a mask of shown cells (a bucket's material), with a skirt.
TEST(TerrainMesh, RegionUpdateEqualsARebuild) {
  for (const int variant : {0, 1, 2}) {
    const bool masked = variant == 1;
    render::HeightField f;
    f.nx = 20;
    f.ny = 15;
    f.cell_m = 0.05;
    f.height_m.assign(300, 0.2f);
    if (masked)
      for (int c = 0; c < 300; ++c) f.shows.push_back(c % 20 > 2 && c / 20 > 1 ? 1 : 0);
    if (variant == 2) f.skirt_bottom_m = -0.3f;
    render::Mesh updated;
    render::build_terrain_mesh(f, updated);
    EXPECT_EQ(updated.positions_m.size(), variant == 2 ? 300u + 4u * 35u : 300u);
    const int i0 = variant == 2 ? 0 : 3;  // the skirt's edge changes too
    for (int j = 5; j < 9; ++j)
      for (int i = i0; i < 10; ++i) f.height_m[static_cast<std::size_t>(j * 20 + i)] = 0.2f + 0.03f * static_cast<float>((i * 7 + j * 3) % 5);
    EXPECT_TRUE(render::update_terrain_mesh(f, i0, 5, 10, 9, updated)) << masked;
    render::Mesh rebuilt;
    render::build_terrain_mesh(f, rebuilt);
    EXPECT_EQ(updated.indices, rebuilt.indices) << masked;
    for (std::size_t v = 0; v < rebuilt.positions_m.size(); ++v) {
      EXPECT_EQ(updated.positions_m[v], rebuilt.positions_m[v]) << v;
      EXPECT_EQ(updated.normals[v], rebuilt.normals[v]) << v;
    }
  }
}

// The renderer keeps each field's mesh and updates the rows that changed:
// a frame after a change matches, pixel for pixel, the frame a fresh
// renderer draws of the changed scene.
TEST(RenderBackends, IncrementalTerrainUpdateDrawsWhatARebuildDraws) {
  auto context = render::make_offscreen_context("osmesa", kWidth, kHeight);
  render::Scene scene = fixed_scene();
  scene.fields[0].skirt_bottom_m = -0.3f;  // the edge's skirt is updated too
  for (int j = 0; j < 61; ++j)
    for (int i = 0; i < 61; ++i) scene.fields[0].height_m[static_cast<std::size_t>(j * 61 + i)] += 0.2f;
  std::vector<std::uint8_t> updated, rebuilt;
  {
    render::Renderer renderer(*context);
    (void)render::render_rgb(*context, renderer, scene, fixed_camera());
    for (int j = 10; j < 25; ++j)  // a trench across the cone's flank, out through the field's edge
      for (int i = 0; i < 40; ++i) scene.fields[0].height_m[static_cast<std::size_t>(j * 61 + i)] *= 0.3f;
    updated = render::render_rgb(*context, renderer, scene, fixed_camera());
  }
  {
    render::Renderer renderer(*context);
    rebuilt = render::render_rgb(*context, renderer, scene, fixed_camera());
  }
  EXPECT_EQ(updated, rebuilt);
  const std::vector<std::uint8_t> before = render_on("osmesa").rgb;
  int changed_pixels = 0;
  for (std::size_t k = 0; k < before.size(); k += 3)
    changed_pixels += before[k] != updated[k] || before[k + 1] != updated[k + 1] || before[k + 2] != updated[k + 2];
  EXPECT_GT(changed_pixels, 1000) << "the trench shows";
}

// Sliding sand (8.2): where the surface flows, the sand's texture moves
// from frame to frame; sand at rest stays exactly as it was.
TEST(RenderBackends, FlowingSandMovesItsTextureAndRestingSandDoesNot) {
  auto context = render::make_offscreen_context("osmesa", kWidth, kHeight);
  const auto changed_pixels = [&](bool flowing) {
    render::Renderer renderer(*context);
    render::Scene scene = fixed_scene();
    render::HeightField& f = scene.fields[0];
    f.flow_m_s.assign(61 * 61, Eigen::Vector2f::Zero());
    if (flowing)  // the cone's west flank slides west at 0.8 m/s
      for (int j = 0; j < 61; ++j)
        for (int i = 0; i < 30; ++i)
          if (f.height_m[static_cast<std::size_t>(j * 61 + i)] > 0.05f) f.flow_m_s[static_cast<std::size_t>(j * 61 + i)] = {-0.8f, 0.0f};
    std::vector<std::vector<std::uint8_t>> frames;
    for (const double t : {1.0, 1.1, 1.2}) {
      scene.time_s = t;
      frames.push_back(render::render_rgb(*context, renderer, scene, fixed_camera()));
    }
    int changed = 0;
    for (std::size_t k = 0; k < frames[1].size(); k += 3)
      changed += frames[1][k] != frames[2][k] || frames[1][k + 1] != frames[2][k + 1] || frames[1][k + 2] != frames[2][k + 2];
    return changed;
  };
  const int flowing = changed_pixels(true), resting = changed_pixels(false);
  std::printf("[ measured ] pixels changed between frames 0.1 s apart: %d with the flank flowing, %d at rest\n", flowing, resting);
  EXPECT_GT(flowing, 500);
  EXPECT_EQ(resting, 0);
}

// Particles (8.3): dust puffs drawn blended over the scene, shaped by
// turbulence; none, none drawn.
TEST(RenderBackends, DustPuffsAreDrawnOverTheScene) {
  auto context = render::make_offscreen_context("osmesa", kWidth, kHeight);
  render::Renderer renderer(*context);
  render::Scene scene = fixed_scene();
  const std::vector<std::uint8_t> clear = render::render_rgb(*context, renderer, scene, fixed_camera());
  for (int k = 0; k < 40; ++k)
    scene.particles.push_back({Eigen::Vector3f(1.5f + 0.05f * k, 1.5f, 0.3f + 0.02f * k), 0.4f, 0.5f, k / 40.0f,
                               Eigen::Vector3f(0.8f, 0.7f, 0.55f)});
  const std::vector<std::uint8_t> dusty = render::render_rgb(*context, renderer, scene, fixed_camera());
  int changed = 0;
  for (std::size_t k = 0; k < clear.size(); k += 3) changed += clear[k] != dusty[k];
  std::printf("[ measured ] pixels under 40 dust puffs: %d\n", changed);
  EXPECT_GT(changed, 1000);  // measured 1714 at 320 x 240
  scene.particles.clear();
  EXPECT_EQ(render::render_rgb(*context, renderer, scene, fixed_camera()), clear);
}

// Seed 001's noise: deterministic for a seed, zero on the lattice, within
// about -1..1; turbulence non-negative; the puffs fade to nothing at the rim.
TEST(SolidNoise, LatticeZerosRangeAndDeterminism) {
  const render::SolidNoise a(3), b(3), c(4);
  double lo = 0.0, hi = 0.0;
  bool differs = false;
  for (int k = 0; k < 4000; ++k) {
    const Eigen::Vector3d p(0.137 * k, -0.071 * k, 0.013 * (k * k % 97));
    const double n = a.noise(p);
    EXPECT_EQ(n, b.noise(p));
    differs = differs || n != c.noise(p);
    lo = std::min(lo, n);
    hi = std::max(hi, n);
    EXPECT_GE(a.turbulence(p, 4), 0.0);
  }
  EXPECT_TRUE(differs);
  EXPECT_LT(hi, 1.6);
  EXPECT_GT(lo, -1.6);
  EXPECT_GT(hi - lo, 1.0) << "not flat";
  EXPECT_NEAR(a.noise(Eigen::Vector3d(3, -2, 7)), 0.0, 1e-12);
  const std::vector<unsigned char> atlas = render::ParticlesPass::make_puff_atlas();
  const int side = render::ParticlesPass::kPuffs * render::ParticlesPass::kPuffPixels;
  EXPECT_EQ(atlas[0], 0);                                      // corner: outside the disc
  EXPECT_GT(atlas[static_cast<std::size_t>(32 * side + 32)], 60);  // the first puff's middle
}

}  // namespace
