#include "visual/scene_frame.h"

#include <algorithm>
#include <cmath>

namespace skidsim::visual {
namespace {

void capture_field(const terrain::GranularGrid& g, const Eigen::Isometry3d& frame, bool load, FrameField& f) {
  f.pose = frame * Eigen::Translation3d(g.spec().origin_m.x(), g.spec().origin_m.y(), 0.0);
  f.nx = g.nx();
  f.ny = g.ny();
  f.cell_m = g.cell_size_m();
  const auto n = static_cast<std::size_t>(f.nx) * static_cast<std::size_t>(f.ny);
  f.surface_m.resize(n);
  f.shows.resize(load ? n : 0);
  for (int j = 0; j < f.ny; ++j)
    for (int i = 0; i < f.nx; ++i) {
      const auto c = static_cast<std::size_t>(g.index(i, j));
      f.surface_m[c] = static_cast<float>(g.surface_m(i, j));
      if (load) f.shows[c] = g.material_quanta(i, j) > 0;
    }
}

}  // namespace

SceneLayout capture_layout(const engine::World& world) {
  SceneLayout l;
  const vehicle::LoaderDescription& d = world.loader().description();
  for (std::size_t k = 0; k < d.links.size(); ++k)
    for (const vehicle::VisualMesh& v : d.links[k].visuals)
      l.machine_parts.push_back({static_cast<int>(k), Eigen::Translation3d(v.pose.position_m) * v.pose.rotation});
  for (const vehicle::Wheel& w : d.wheels)
    for (const vehicle::VisualMesh& v : w.visuals)
      l.machine_parts.push_back({0, Eigen::Translation3d(w.hub_m) * (Eigen::Translation3d(v.pose.position_m) * v.pose.rotation)});
  for (int k = 0; k < world.tray_count(); ++k) {
    const terrain::ContainerShape& c = world.tray(k).shape();
    l.trays.push_back({c.length_m, c.width_m, std::max(c.side_height_back_m, c.side_height_front_m)});
  }
  for (const engine::AgentSpec& a : world.agent_specs())
    l.agent_tray.push_back(a.kind == engine::AgentKind::kTruck ? a.tray : -1);
  if (const terrain::GranularGrid* g = world.terrain()) {
    l.quantum_mass_kg = g->quantum_mass_kg();
    l.quantum_volume_m3 = g->quantum_volume_m3();
  }
  return l;
}

void capture_frame(const engine::World& world, SceneFrame& f) {
  f.step = world.steps();
  f.time_s = world.time_s();
  const vehicle::Loader& loader = world.loader();
  f.links.resize(loader.description().links.size());
  for (std::size_t k = 0; k < f.links.size(); ++k) f.links[k] = loader.link_pose(static_cast<int>(k));
  f.trays.resize(static_cast<std::size_t>(world.tray_count()));
  for (int k = 0; k < world.tray_count(); ++k) f.trays[static_cast<std::size_t>(k)] = world.tray(k).pose();
  f.agents.resize(world.agent_specs().size());
  for (std::size_t k = 0; k < f.agents.size(); ++k) f.agents[k] = world.agent_pose(static_cast<int>(k));
  const terrain::GranularGrid* g = world.terrain();
  f.has_ground = g != nullptr;
  if (g) {
    capture_field(*g, Eigen::Isometry3d::Identity(), false, f.ground);
    f.flow_x = g->flow_record_x();
    f.flow_y = g->flow_record_y();
  } else {
    f.ground = FrameField{};
    f.flow_x.clear(), f.flow_y.clear();
  }
  const terrain::BodyAutomaton* bucket = world.bucket_material();
  f.has_bucket = bucket != nullptr;
  f.loads.resize((bucket ? 1u : 0u) + static_cast<std::size_t>(world.tray_count()));
  std::size_t n = 0;
  if (bucket) capture_field(bucket->grid(), bucket->pose(), true, f.loads[n++]);
  for (int k = 0; k < world.tray_count(); ++k) capture_field(world.tray(k).grid(), world.tray(k).pose(), true, f.loads[n++]);
  f.parcels.clear();
  if (const terrain::MaterialExchange* x = world.material())
    for (const terrain::FallingParcel& p : x->parcels()) f.parcels.push_back({p.position_m, p.velocity_m_s, p.quanta});
}

double ground_height_m(const SceneFrame& f, const Eigen::Vector3d& at) {
  if (!f.has_ground) return 0.0;
  const Eigen::Vector3d local = f.ground.pose.inverse() * at;
  const int i = static_cast<int>(std::lround(local.x() / f.ground.cell_m));
  const int j = static_cast<int>(std::lround(local.y() / f.ground.cell_m));
  if (i < 0 || j < 0 || i >= f.ground.nx || j >= f.ground.ny) return 0.0;
  return f.ground.surface_m[static_cast<std::size_t>(j) * static_cast<std::size_t>(f.ground.nx) + static_cast<std::size_t>(i)];
}

}  // namespace skidsim::visual
