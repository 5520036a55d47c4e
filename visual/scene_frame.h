// What a frame shows that changes while a session runs, as plain data: the
// machine's links, the beds and the people and trucks, the soil's surface
// and its flow record, the loads in the bucket and the beds, the falling
// parcels. Captured from the world in-process (capture_frame), or rebuilt
// from the scene stream by a view (visual/scene_stream.h, docs/rendering.md,
// "The scene stream"): the same data in both, so the same pixels. What does
// not change (the meshes, the beds' and agents' sizes) is the layout, taken
// from the world as the exercise builds it.
#pragma once

#include <Eigen/Geometry>

#include <cstdint>
#include <vector>

#include "engine/world.h"

namespace skidsim::visual {

// A grid's height field: the ground, or a body's load in its frame.
struct FrameField {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();  // cell (0, 0)'s centre in the world
  int nx = 0, ny = 0;
  double cell_m = 0.05;
  std::vector<float> surface_m;  // j * nx + i, in the field's frame
  std::vector<std::uint8_t> shows;  // a body's load: the cells holding material (empty for the ground)
};

struct FrameParcel {
  Eigen::Vector3d position_m = Eigen::Vector3d::Zero(), velocity_m_s = Eigen::Vector3d::Zero();
  std::int64_t quanta = 0;
};

struct SceneFrame {
  long step = 0;
  double time_s = 0.0;
  std::vector<Eigen::Isometry3d> links;   // the loader's links (Loader::link_pose), in its description's order
  std::vector<Eigen::Isometry3d> trays;   // each bed's frame
  std::vector<Eigen::Isometry3d> agents;  // each person's and truck's pose
  bool has_ground = false;
  FrameField ground;
  // The ground's flow record (GranularGrid::flow_record_x / _y: quanta sent
  // across each cell's faces since the start); empty when not recorded.
  std::vector<std::int64_t> flow_x, flow_y;
  bool has_bucket = false;
  std::vector<FrameField> loads;  // the bucket's (when has_bucket), then each bed's
  std::vector<FrameParcel> parcels;
};

// What a frame needs that does not change: the sizes of the beds and the
// trucks' cabs and which agent is a truck, the soil's quantum.
struct SceneLayout {
  // Each of the machine's meshes, in static_scene's order: the link it
  // rides on and its pose on that link (a wheel's on the chassis).
  struct MachinePart {
    int link = 0;
    Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  };
  std::vector<MachinePart> machine_parts;
  struct Tray {
    double length_m = 0.0, width_m = 0.0, wall_height_m = 0.0;
  };
  std::vector<Tray> trays;
  std::vector<int> agent_tray;  // per agent: a truck's bed (-1: a person)
  double quantum_mass_kg = 0.0, quantum_volume_m3 = 0.0;
};

SceneLayout capture_layout(const engine::World& world);
// Into `frame`, reusing its buffers.
void capture_frame(const engine::World& world, SceneFrame& frame);

// Height of the ground (soil surface, else the firm yard at 0) below a point.
double ground_height_m(const SceneFrame& frame, const Eigen::Vector3d& at);

}  // namespace skidsim::visual
