// What a frame shows, as plain data (render/ knows nothing of the engine):
// triangle meshes placed in the world, height fields (the ground's soil and
// the material in the bucket and the beds), a camera and the sun. Built
// from a snapshot of the world by apps/ (scene_snapshot).
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <limits>
#include <vector>

namespace skidsim::render {

struct Mesh {
  std::vector<Eigen::Vector3f> positions_m, normals;
  std::vector<std::uint32_t> indices;  // triangles, counter-clockwise seen from outside
};

struct MeshInstance {
  int mesh = 0;  // into Scene::meshes
  Eigen::Affine3d pose = Eigen::Affine3d::Identity();  // mesh frame in the world (a box may be scaled)
  Eigen::Vector3f colour = Eigen::Vector3f(0.8f, 0.8f, 0.8f);  // linear RGB, 0..1
};

// A grid of surface heights: cell (i, j) at (i, j) * cell_m in the field's
// frame, height along its z.
struct HeightField {
  int nx = 0, ny = 0;
  double cell_m = 0.05;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // field frame (cell (0, 0) at its origin) in the world
  std::vector<float> height_m;  // j * nx + i
  // Cells that show (material in a bucket or bed); empty: every cell. A
  // quad is drawn where any of its corners shows.
  std::vector<std::uint8_t> shows;
  // A skirt: walls down from the field's four edges to this height (field
  // frame), so that a soil layer seen from its side is closed. NaN: none.
  float skirt_bottom_m = std::numeric_limits<float>::quiet_NaN();
  // Speed of the sliding surface layer at each cell (field frame, m/s);
  // empty: at rest. Drawn as sand whose texture moves with it (8.2).
  std::vector<Eigen::Vector2f> flow_m_s;
  Eigen::Vector3f colour = Eigen::Vector3f(0.76f, 0.62f, 0.40f);  // dry sand
};

// A soft, camera-facing disc of dust or falling sand (8.3), its shape one
// of the renderer's turbulence puffs.
struct Particle {
  Eigen::Vector3f position_m = Eigen::Vector3f::Zero();
  float radius_m = 0.1f;
  float opacity = 0.5f;  // 0..1, at the puff's densest
  float shape = 0.0f;    // 0..1: which puff
  Eigen::Vector3f colour = Eigen::Vector3f(0.80f, 0.70f, 0.55f);
};

struct Camera {
  Eigen::Vector3d eye_m = Eigen::Vector3d(-8, -8, 6), target_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  double fov_y_deg = 50.0, near_m = 0.1, far_m = 500.0;
};

struct Scene {
  double time_s = 0.0;  // simulated time: drives the flow texture's phases
  std::vector<Mesh> meshes;
  std::vector<MeshInstance> instances;
  std::vector<HeightField> fields;
  std::vector<Particle> particles;  // drawn last, blended, casting no shadow
  Eigen::Vector3d sun_direction = Eigen::Vector3d(-0.4, -0.3, -1.0);  // the way the light travels
  Eigen::Vector3f sky = Eigen::Vector3f(0.62f, 0.74f, 0.88f);
  // Where shadows are cast: the part of the world the sun's depth map covers.
  Eigen::AlignedBox3d shadow_bounds_m{Eigen::Vector3d(-20, -20, -2), Eigen::Vector3d(20, 20, 6)};
};

}  // namespace skidsim::render
