#include "visual/scene_snapshot.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "render/primitives.h"

namespace skidsim::visual {
namespace {

const Eigen::Vector3f kMachineYellow(0.86f, 0.62f, 0.08f);
const Eigen::Vector3f kBucketGrey(0.25f, 0.25f, 0.27f);
const Eigen::Vector3f kTyreBlack(0.06f, 0.06f, 0.06f);

// A visual mesh, flat-shaded: each triangle its own three vertices.
render::Mesh flat_mesh(const vehicle::VisualMesh& v) {
  render::Mesh m;
  for (const auto& t : v.triangles) {
    const Eigen::Vector3f a = v.vertices_m[t[0]], b = v.vertices_m[t[1]], c = v.vertices_m[t[2]];
    Eigen::Vector3f n = (b - a).cross(c - a);
    n = n.norm() > 0.0f ? n.normalized() : Eigen::Vector3f::UnitZ();
    for (const Eigen::Vector3f& p : {a, b, c}) {
      m.indices.push_back(static_cast<std::uint32_t>(m.positions_m.size()));
      m.positions_m.push_back(p);
      m.normals.push_back(n);
    }
  }
  return m;
}


Eigen::Affine3d box_pose(const Eigen::Isometry3d& frame, const Eigen::Vector3d& centre, const Eigen::Vector3d& size) {
  Eigen::Affine3d a = Eigen::Affine3d::Identity();
  a = frame * Eigen::Translation3d(centre);
  a.scale(size);
  return a;
}

// The machine's meshes, in static_scene's order (capture_layout's
// machine_parts): each link's visuals, then each wheel's.
template <class F>
void for_each_machine_mesh(const vehicle::LoaderDescription& d, F&& f) {
  for (std::size_t k = 0; k < d.links.size(); ++k)
    for (const vehicle::VisualMesh& v : d.links[k].visuals) f(v, k + 1 == d.links.size() && k > 0 ? kBucketGrey : kMachineYellow);
  for (const vehicle::Wheel& w : d.wheels)
    for (const vehicle::VisualMesh& v : w.visuals) f(v, kTyreBlack);
}

// The parts that move with the world but are not the machine, in a fixed
// order static_scene and update_scene share: each tray's bed (floor, four
// walls, and the block under it when it stands up), then each agent (a
// person: body and head; a truck: its cab). `f(pose, colour)` for each.
template <class F>
void for_each_site_part(const SceneLayout& layout, const SceneFrame& frame, F&& f) {
  const Eigen::Vector3f bed(0.55f, 0.12f, 0.10f);
  for (std::size_t k = 0; k < layout.trays.size(); ++k) {
    const Eigen::Isometry3d& tray = frame.trays[k];
    const double L = layout.trays[k].length_m, W = layout.trays[k].width_m, H = layout.trays[k].wall_height_m, w = 0.05;
    const double floor_z = tray.translation().z();
    f(box_pose(tray, {0.5 * L, 0.5 * W, -0.05}, {L, W, 0.1}), bed);
    f(box_pose(tray, {0.5 * w, 0.5 * W, 0.5 * H}, {w, W, H}), bed);
    f(box_pose(tray, {L - 0.5 * w, 0.5 * W, 0.5 * H}, {w, W, H}), bed);
    f(box_pose(tray, {0.5 * L, 0.5 * w, 0.5 * H}, {L, w, H}), bed);
    f(box_pose(tray, {0.5 * L, W - 0.5 * w, 0.5 * H}, {L, w, H}), bed);
    // What carries the bed: a dark block under it (always emitted, flat
    // when the bed stands on the ground, so the order never changes).
    const double block = std::max(floor_z - 0.1, 0.001);
    f(box_pose(tray, {0.5 * L, 0.5 * W, -0.1 - 0.5 * block}, {L * 0.9, W * 0.8, block}), Eigen::Vector3f(0.15f, 0.15f, 0.17f));
  }
  for (std::size_t k = 0; k < layout.agent_tray.size(); ++k) {
    const Eigen::Isometry3d& frame_k = frame.agents[k];
    if (const int t = layout.agent_tray[k]; t >= 0) {
      const double L = layout.trays[static_cast<std::size_t>(t)].length_m, W = layout.trays[static_cast<std::size_t>(t)].width_m;
      f(box_pose(frame_k, {0.5 * L + 0.05 + 0.5 * engine::kTruckCabLengthM, 0.0, 0.5 * engine::kTruckCabHeightM},
                 {engine::kTruckCabLengthM, W, engine::kTruckCabHeightM}),
        Eigen::Vector3f(0.85f, 0.85f, 0.82f));
      continue;
    }
    // A person in a high-visibility vest with a hard hat; out of sight
    // (far below) when not on site.
    const double h = engine::kPersonHeightM;
    f(box_pose(frame_k, {0.0, 0.0, 0.42 * h}, {0.3, 0.46, 0.84 * h}), Eigen::Vector3f(1.0f, 0.45f, 0.05f));
    f(box_pose(frame_k, {0.0, 0.0, 0.92 * h}, {0.22, 0.2, 0.16 * h}), Eigen::Vector3f(0.95f, 0.85f, 0.2f));  // hard hat
  }
}

render::HeightField field_of(const FrameField& g) {
  render::HeightField f;
  f.nx = g.nx;
  f.ny = g.ny;
  f.cell_m = g.cell_m;
  f.pose = g.pose;
  f.height_m = g.surface_m;
  f.shows = g.shows;
  return f;
}

}  // namespace


render::Scene static_scene(const io::Exercise& ex, const engine::World& world) {
  render::Scene s;
  const SceneLayout layout = capture_layout(world);
  SceneFrame frame;
  capture_frame(world, frame);
  // The machine first (update_scene walks the same order), posed by update_scene.
  for_each_machine_mesh(world.loader().description(), [&](const vehicle::VisualMesh& v, const Eigen::Vector3f& colour) {
    s.meshes.push_back(flat_mesh(v));
    s.instances.push_back({static_cast<int>(s.meshes.size()) - 1, Eigen::Affine3d::Identity(), colour});
  });
  s.meshes.push_back(render::unit_cube());
  const int cube = static_cast<int>(s.meshes.size()) - 1;
  for_each_site_part(layout, frame, [&](const Eigen::Affine3d& pose, const Eigen::Vector3f& colour) {
    s.instances.push_back({cube, pose, colour});
  });
  const Eigen::Vector2d size = ex.site_size_m;
  if (ex.firm_ground) {
    // The yard, 10 m beyond the site on every side. Around soil it is a
    // frame, not a slab under it: a rut worn down to the base would show
    // the slab's top through the sand.
    const Eigen::Vector3f yard(0.42f, 0.40f, 0.36f);
    const auto slab = [&](double x0, double y0, double x1, double y1) {
      s.instances.push_back({cube, box_pose(Eigen::Isometry3d::Identity(), {0.5 * (x0 + x1), 0.5 * (y0 + y1), -0.05}, {x1 - x0, y1 - y0, 0.1}), yard});
    };
    constexpr double kMargin = 10.0;
    const double x_lo = -kMargin, y_lo = -kMargin, x_hi = size.x() + kMargin, y_hi = size.y() + kMargin;
    if (const terrain::GranularGrid* g = world.terrain()) {
      // The hole: the soil's mesh, cell (0, 0) to cell (nx - 1, ny - 1).
      const double x0 = g->spec().origin_m.x(), y0 = g->spec().origin_m.y();
      const double x1 = x0 + (g->nx() - 1) * g->cell_size_m(), y1 = y0 + (g->ny() - 1) * g->cell_size_m();
      slab(x_lo, y_lo, x0, y_hi);
      slab(x1, y_lo, x_hi, y_hi);
      slab(x0, y_lo, x1, y0);
      slab(x0, y1, x1, y_hi);
    } else {
      slab(x_lo, y_lo, x_hi, y_hi);
    }
  }
  for (const io::BoxObstacle& b : ex.boxes) {
    const Eigen::Isometry3d yaw(Eigen::AngleAxisd(b.yaw_deg * kPi / 180.0, Eigen::Vector3d::UnitZ()));
    Eigen::Affine3d pose = Eigen::Translation3d(b.centre_m) * Eigen::Affine3d(yaw.linear());
    pose.scale(b.size_m);
    s.instances.push_back({cube, pose, Eigen::Vector3f(0.95f, 0.35f, 0.05f)});
  }
  s.shadow_bounds_m = Eigen::AlignedBox3d(Eigen::Vector3d(-2, -2, -1), Eigen::Vector3d(size.x() + 2, size.y() + 2, 5));
  update_scene(layout, frame, s);
  return s;
}

void update_scene(const engine::World& world, render::Scene& s, SceneHistory* history) {
  SceneFrame local;
  SceneFrame& frame = history ? history->frame : local;
  capture_frame(world, frame);
  update_scene(capture_layout(world), frame, s, history);
}

void update_scene(const SceneLayout& layout, const SceneFrame& frame, render::Scene& s, SceneHistory* history) {
  s.time_s = frame.time_s;
  std::size_t k = 0;
  for (const SceneLayout::MachinePart& part : layout.machine_parts)
    s.instances[k++].pose = Eigen::Affine3d(frame.links[static_cast<std::size_t>(part.link)] * part.offset);
  for_each_site_part(layout, frame, [&](const Eigen::Affine3d& pose, const Eigen::Vector3f&) { s.instances[k++].pose = pose; });
  s.fields.clear();
  if (frame.has_ground) {
    s.fields.push_back(field_of(frame.ground));
    s.fields.back().skirt_bottom_m = -0.3f;  // below the yard: the layer's sides closed
  }
  for (const FrameField& load : frame.loads) s.fields.push_back(field_of(load));
  s.particles.clear();
  if (history == nullptr) {
    DustSystem().append_particles(layout, frame, s.particles);  // the falling parcels alone
    return;
  }
  const double dt = history->time_s >= 0.0 ? frame.time_s - history->time_s : 0.0;
  const std::vector<Eigen::Vector2f>* flow = nullptr;
  if (frame.has_ground && !frame.flow_x.empty()) {
    const std::vector<std::int64_t>&x = frame.flow_x, &y = frame.flow_y;
    if (history->flow_x.size() != x.size() || !(dt > 0.0)) {
      history->flow_x = x;
      history->flow_y = y;
    } else {
      std::vector<Eigen::Vector2f>& v = s.fields.front().flow_m_s;
      v.assign(x.size(), Eigen::Vector2f::Zero());
      const double scale = terrain::kHeightQuantumM * frame.ground.cell_m / (kFlowingLayerM * dt);
      for (std::size_t c = 0; c < x.size(); ++c) {
        if (x[c] == history->flow_x[c] && y[c] == history->flow_y[c]) continue;
        Eigen::Vector2f u(static_cast<float>(static_cast<double>(x[c] - history->flow_x[c]) * scale),
                          static_cast<float>(static_cast<double>(y[c] - history->flow_y[c]) * scale));
        if (u.norm() > 3.0f) u *= 3.0f / u.norm();  // what the eye can follow
        v[c] = u;
      }
      history->flow_x = x;
      history->flow_y = y;
      flow = &v;
    }
  }
  history->dust.advance(layout, frame, flow, dt);
  history->time_s = frame.time_s;
  history->dust.append_particles(layout, frame, s.particles);
}

render::Camera exercise_camera(const std::string& name, const io::Exercise& ex, const engine::World& world) {
  return exercise_camera(name, ex, world.loader().link_pose(0));
}

render::Camera exercise_camera(const std::string& name, const io::Exercise& ex, const Eigen::Isometry3d& chassis) {
  const Eigen::Vector3d x = chassis.linear().col(0);
  const Eigen::Vector3d ahead = Eigen::Vector3d(x.x(), x.y(), 0.0).normalized();
  const Eigen::Vector3d at = chassis.translation();
  render::Camera c;
  if (name == "chase") {  // behind, above and to the left: the bucket shows past the cab
    const Eigen::Vector3d left(-ahead.y(), ahead.x(), 0.0);
    c.eye_m = at - 5.5 * ahead + 3.0 * left + Eigen::Vector3d(0, 0, 3.8);
    c.target_m = at + 1.5 * ahead + Eigen::Vector3d(0, 0, 0.4);
  } else if (name == "cab") {  // the operator's seat, looking out over the bucket
    c.eye_m = chassis * Eigen::Vector3d(-0.15, 0.0, 1.25);
    c.target_m = chassis * Eigen::Vector3d(4.0, 0.0, 0.2);
    c.fov_y_deg = 70.0;
    c.near_m = 0.05;
  } else if (name == "aerial") {  // straight down on the whole site
    const Eigen::Vector2d mid = 0.5 * ex.site_size_m;
    c.target_m = Eigen::Vector3d(mid.x(), mid.y(), 0.0);
    c.eye_m = c.target_m + Eigen::Vector3d(0, -0.2 * ex.site_size_m.maxCoeff(), 1.1 * ex.site_size_m.maxCoeff());
  } else if (name == "fixed" && ex.recording.fixed_eye_m.allFinite()) {  // where the exercise put it
    c.eye_m = ex.recording.fixed_eye_m;
    c.target_m = ex.recording.fixed_target_m;
  } else if (name == "fixed") {  // from beyond the site's corner, at the site
    const Eigen::Vector2d mid = 0.5 * ex.site_size_m;
    c.target_m = Eigen::Vector3d(mid.x(), mid.y(), 0.0);
    c.eye_m = Eigen::Vector3d(-0.15 * ex.site_size_m.x(), -0.15 * ex.site_size_m.y(), 0.45 * ex.site_size_m.maxCoeff());
  } else {
    throw std::invalid_argument("camera '" + name + "': expected cab, chase, aerial or fixed");
  }
  return c;
}

}  // namespace skidsim::visual
