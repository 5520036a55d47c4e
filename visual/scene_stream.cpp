#include "visual/scene_stream.h"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <type_traits>

namespace skidsim::visual {
namespace {

// A pose as 12 numbers: the rotation row-major, then the translation.
template <class Out>
void put_pose(const Eigen::Isometry3d& p, Out& out) {
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) out[3 * r + c] = p.linear()(r, c);
  for (int r = 0; r < 3; ++r) out[9 + r] = p.translation()(r);
}

template <class In>
Eigen::Isometry3d get_pose(const In& in) {
  Eigen::Isometry3d p = Eigen::Isometry3d::Identity();
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) p.linear()(r, c) = in[3 * r + c];
  for (int r = 0; r < 3; ++r) p.translation()(r) = in[9 + r];
  return p;
}

void put_poses(const std::vector<Eigen::Isometry3d>& poses, std::int16_t& count, std::vector<std::vector<double>>& out) {
  count = static_cast<std::int16_t>(poses.size());
  out.resize(poses.size());
  for (std::size_t k = 0; k < poses.size(); ++k) {
    out[k].resize(12);
    put_pose(poses[k], out[k]);
  }
}

void get_poses(const std::vector<std::vector<double>>& in, std::vector<Eigen::Isometry3d>& poses) {
  poses.resize(in.size());
  for (std::size_t k = 0; k < in.size(); ++k) {
    if (in[k].size() != 12) throw SceneStreamError("scene: a pose with " + std::to_string(in[k].size()) + " numbers");
    poses[k] = get_pose(in[k]);
    if (!poses[k].matrix().allFinite()) throw SceneStreamError("scene: a pose that is not finite");
  }
}

// What a flow record grew by since it was last sent, in whole units, which
// then count as sent; the rest, and what an int32 cannot hold, goes later.
std::int32_t growth(std::int64_t now, std::int64_t& sent) {
  const std::int64_t units = std::clamp<std::int64_t>((now - sent) / kSceneFlowUnitQuanta, INT32_MIN, INT32_MAX);
  sent += units * kSceneFlowUnitQuanta;
  return static_cast<std::int32_t>(units);
}

// A height field's cells as the tiles carry them: the surface, and either
// the flow record (the ground) or which cells hold material (a load).
template <bool kConst>
struct CellsOf {
  template <class T>
  using Ptr = std::conditional_t<kConst, const T*, T*>;
  int nx = 0, ny = 0;
  Ptr<std::vector<float>> surface = nullptr;
  Ptr<std::vector<std::uint8_t>> shows = nullptr;                   // a load
  Ptr<std::vector<std::int64_t>> flow_x = nullptr, flow_y = nullptr;  // the ground, when recorded
  std::size_t at(int i, int j) const { return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i); }
};
using Cells = CellsOf<false>;
using ConstCells = CellsOf<true>;

int tiles_across(int n) { return (n + kSceneTileCells - 1) / kSceneTileCells; }
std::int64_t tiles_of(int nx, int ny) { return static_cast<std::int64_t>(tiles_across(nx)) * tiles_across(ny); }

// The squares a message sends again in turn: `count` of them from `first`,
// in the numbering over the ground's squares, then each load's, `total` in all.
struct Refresh {
  std::int64_t first = 0, count = 0, total = 1;
  bool due(std::int64_t square) const { return ((square - first) % total + total) % total < count; }
};

// Appends the squares of `now` where a cell differs from `sent` by a step
// worth sending (all of them when `whole`), and those the refresh has due
// (numbered from `square`, which moves past this field's), every cell of
// each exactly, and makes `sent` what was sent.
void append_changed_tiles(const ConstCells& now, const Cells& sent, bool whole, const Refresh& refresh, std::int64_t& square,
                          std::vector<skidsim_lcm::scene_tile_t>& out) {
  for (int j0 = 0; j0 < now.ny; j0 += kSceneTileCells)
    for (int i0 = 0; i0 < now.nx; i0 += kSceneTileCells) {
      const int ni = std::min(kSceneTileCells, now.nx - i0), nj = std::min(kSceneTileCells, now.ny - j0);
      const bool due = refresh.due(square++);  // numbered whether or not the field goes whole
      bool changed = whole || due;
      for (int j = j0; j < j0 + nj && !changed; ++j)
        for (int i = i0; i < i0 + ni && !changed; ++i) {
          const std::size_t c = now.at(i, j);
          changed = std::abs((*now.surface)[c] - (*sent.surface)[c]) >= kSceneSurfaceStepM ||
                    (now.shows && (*now.shows)[c] != (*sent.shows)[c]) ||
                    (now.flow_x && (std::abs((*now.flow_x)[c] - (*sent.flow_x)[c]) >= kSceneFlowStepQuanta ||
                                    std::abs((*now.flow_y)[c] - (*sent.flow_y)[c]) >= kSceneFlowStepQuanta));
        }
      if (!changed) continue;
      skidsim_lcm::scene_tile_t t;
      t.i0 = i0, t.j0 = j0, t.ni = ni, t.nj = nj, t.num_cells = ni * nj;
      t.num_flow = now.flow_x ? t.num_cells : 0;
      t.num_shows = now.shows ? t.num_cells : 0;
      t.surface_m.resize(static_cast<std::size_t>(t.num_cells));
      t.flow_dx.resize(static_cast<std::size_t>(t.num_flow)), t.flow_dy.resize(static_cast<std::size_t>(t.num_flow));
      t.shows.resize(static_cast<std::size_t>(t.num_shows));
      for (int j = j0; j < j0 + nj; ++j)
        for (int i = i0; i < i0 + ni; ++i) {
          const std::size_t c = now.at(i, j), k = static_cast<std::size_t>((j - j0) * ni + (i - i0));
          t.surface_m[k] = (*sent.surface)[c] = (*now.surface)[c];
          if (now.shows) t.shows[k] = static_cast<std::int8_t>((*sent.shows)[c] = (*now.shows)[c]);
          if (now.flow_x) {
            t.flow_dx[k] = growth((*now.flow_x)[c], (*sent.flow_x)[c]);
            t.flow_dy[k] = growth((*now.flow_y)[c], (*sent.flow_y)[c]);
          }
        }
      out.push_back(std::move(t));
    }
}

// Checks tiles against an nx x ny field: inside it, of their size, with the
// flow record (ground) or the cells holding material (load) as asked,
// surfaces finite; when `whole`, every cell exactly once.
void check_tiles(const std::vector<skidsim_lcm::scene_tile_t>& tiles, int nx, int ny, bool flow, bool shows, bool whole,
                 const std::string& what) {
  if (whole) {  // before the cells are counted one by one: as many as the field has
    long long cells = 0;
    for (const skidsim_lcm::scene_tile_t& t : tiles) cells += std::max(t.num_cells, 0);
    if (cells != static_cast<long long>(nx) * ny) throw SceneStreamError("scene: " + what + " is new, and needs every square");
  }
  std::vector<std::uint8_t> seen(whole ? static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny) : 0, 0);
  for (const skidsim_lcm::scene_tile_t& t : tiles) {
    const bool fits = t.ni > 0 && t.nj > 0 && t.ni <= kSceneTileCells && t.nj <= kSceneTileCells && t.i0 >= 0 && t.j0 >= 0 &&
                      t.i0 <= nx - t.ni && t.j0 <= ny - t.nj && t.num_cells == t.ni * t.nj &&
                      static_cast<int>(t.surface_m.size()) == t.num_cells && t.num_flow == (flow ? t.num_cells : 0) &&
                      static_cast<int>(t.flow_dx.size()) == t.num_flow && static_cast<int>(t.flow_dy.size()) == t.num_flow &&
                      t.num_shows == (shows ? t.num_cells : 0) && static_cast<int>(t.shows.size()) == t.num_shows;
    if (!fits)
      throw SceneStreamError("scene: " + what + ": a square at cell (" + std::to_string(t.i0) + ", " + std::to_string(t.j0) + "), " +
                             std::to_string(t.ni) + " x " + std::to_string(t.nj) + ", off the " + std::to_string(nx) + " x " +
                             std::to_string(ny) + " cells or not of its size");
    for (const float h : t.surface_m)
      if (!(std::abs(h) < 1e6f)) throw SceneStreamError("scene: " + what + ": a surface that is not a finite height");
    if (whole)
      for (int j = t.j0; j < t.j0 + t.nj; ++j)
        for (int i = t.i0; i < t.i0 + t.ni; ++i) {
          std::uint8_t& once = seen[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
          if (once) throw SceneStreamError("scene: " + what + ": cell (" + std::to_string(i) + ", " + std::to_string(j) + ") sent twice");
          once = 1;
        }
  }
  if (whole && std::find(seen.begin(), seen.end(), 0) != seen.end())
    throw SceneStreamError("scene: " + what + " is new, and needs every square");
}

// Counts the cells the tiles bring that had not come before (joining).
void mark_known(const std::vector<skidsim_lcm::scene_tile_t>& tiles, int nx, std::vector<std::uint8_t>& known, std::size_t& missing) {
  for (const skidsim_lcm::scene_tile_t& t : tiles)
    for (int j = t.j0; j < t.j0 + t.nj; ++j)
      for (int i = t.i0; i < t.i0 + t.ni; ++i) {
        std::uint8_t& k = known[static_cast<std::size_t>(j) * static_cast<std::size_t>(nx) + static_cast<std::size_t>(i)];
        if (!k) k = 1, --missing;
      }
}

void apply_tiles(const std::vector<skidsim_lcm::scene_tile_t>& tiles, const Cells& f) {
  for (const skidsim_lcm::scene_tile_t& t : tiles)
    for (int j = 0; j < t.nj; ++j)
      for (int i = 0; i < t.ni; ++i) {
        const std::size_t c = f.at(t.i0 + i, t.j0 + j), k = static_cast<std::size_t>(j * t.ni + i);
        (*f.surface)[c] = t.surface_m[k];
        if (f.shows) (*f.shows)[c] = t.shows[k] != 0;
        if (f.flow_x) (*f.flow_x)[c] += t.flow_dx[k] * kSceneFlowUnitQuanta, (*f.flow_y)[c] += t.flow_dy[k] * kSceneFlowUnitQuanta;
      }
}

bool sized(int nx, int ny, double cell_m) {
  return nx > 0 && ny > 0 && nx <= 100000 && ny <= 100000 && static_cast<long long>(nx) * ny <= 100000000LL && cell_m > 0.0 &&
         std::isfinite(cell_m);
}

// Walks a scene_t's encoding (LCM's: big-endian, a nested type without its
// hash) checking that each count is at least 0 and its elements fit the
// bytes left, before lcm-gen's decoder sizes anything by it.
class CountCheck {
 public:
  CountCheck(const std::uint8_t* data, std::size_t size) : data_(data), left_(size) {}
  bool skip(std::size_t bytes) {
    if (bytes > left_) return false;
    data_ += bytes, left_ -= bytes;
    return true;
  }
  // A count of `bytes` bytes (2 or 4), then that many elements of `each` bytes.
  bool count(std::size_t bytes, std::size_t each, long long* n = nullptr) {
    if (bytes > left_) return false;
    long long v = 0;
    for (std::size_t k = 0; k < bytes; ++k) v = v << 8 | data_[k];
    if (bytes == 2) v = static_cast<std::int16_t>(v);
    if (bytes == 4) v = static_cast<std::int32_t>(v);
    skip(bytes);
    if (v < 0 || (each > 0 && static_cast<unsigned long long>(v) > left_ / each)) return false;
    if (n) *n = v;
    return each == 0 || skip(static_cast<std::size_t>(v) * each);
  }
  bool tile() {
    long long cells = 0;
    // i0, j0, ni, nj; the cells' surfaces; the flow's growth; which hold material
    return skip(16) && count(4, 4, &cells) && count(4, 8) && count(4, 1);
  }
  bool tiles() {
    long long n = 0;
    if (!count(4, 0, &n) || static_cast<unsigned long long>(n) > left_ / kTileBytesAtLeast) return false;
    for (long long k = 0; k < n; ++k)
      if (!tile()) return false;
    return true;
  }
  // A tile's fixed part (i0, j0, ni, nj and three counts).
  static constexpr std::size_t kTileBytesAtLeast = 28;

 private:
  const std::uint8_t* data_;
  std::size_t left_;
};

bool counts_fit(const std::uint8_t* data, std::size_t size) {
  CountCheck c(data, size);
  // hash, step, time; links, trays, agents (12 doubles each)
  if (!(c.skip(24) && c.count(2, 96) && c.count(2, 96) && c.count(2, 96))) return false;
  // has_ground, nx, ny, cell, pose, ground_whole; its squares
  if (!(c.skip(1 + 4 + 4 + 8 + 96 + 1) && c.tiles())) return false;
  // has_bucket; the loads (pose, nx, ny, cell, their squares)
  long long loads = 0;
  if (!(c.skip(1) && c.count(2, 0, &loads))) return false;
  for (long long k = 0; k < loads; ++k)
    if (!(c.skip(96 + 4 + 4 + 8) && c.tiles())) return false;
  // the parcels: where and how fast (3 floats each), their quanta
  long long parcels = 0;
  return c.count(4, 0, &parcels) && static_cast<unsigned long long>(parcels) <= size / 32;
}

}  // namespace

void decode_scene(const std::uint8_t* data, std::size_t size, skidsim_lcm::scene_t& out) {
  if (size > static_cast<std::size_t>(INT32_MAX) || !counts_fit(data, size))
    throw SceneStreamError("scene: a message whose counts do not fit its " + std::to_string(size) + " bytes");
  try {
    if (out.decode(data, 0, static_cast<int>(size)) != static_cast<int>(size))
      throw SceneStreamError("scene: a message that does not decode (" + std::to_string(size) + " bytes)");
  } catch (const std::exception& e) {  // std::length_error, std::bad_alloc from lcm-gen's sizing
    throw SceneStreamError(std::string("scene: a message that does not decode: ") + e.what());
  }
}

const skidsim_lcm::scene_t& SceneStreamWriter::encode(const SceneFrame& f) {
  skidsim_lcm::scene_t& m = message_;
  m.step = f.step;
  m.sim_time_s = f.time_s;
  put_poses(f.links, m.num_links, m.link_pose);
  put_poses(f.trays, m.num_trays, m.tray_pose);
  put_poses(f.agents, m.num_agents, m.agent_pose);
  // The ground: a new grid (or the flow record turned on or off) goes whole,
  // its flow record's growth counted from zero.
  const bool whole = first_ || f.has_ground != sent_.has_ground || f.ground.nx != sent_.ground.nx ||
                     f.ground.ny != sent_.ground.ny || f.flow_x.size() != sent_.flow_x.size();
  if (whole) {
    sent_.has_ground = f.has_ground;
    sent_.ground = f.ground;
    sent_.flow_x.assign(f.flow_x.size(), 0);
    sent_.flow_y.assign(f.flow_y.size(), 0);
  }
  m.has_ground = f.has_ground;
  m.ground_nx = f.has_ground ? f.ground.nx : 0;
  m.ground_ny = f.has_ground ? f.ground.ny : 0;
  m.ground_cell_m = f.has_ground ? f.ground.cell_m : 0.0;
  put_pose(f.ground.pose, m.ground_pose);
  m.ground_whole = f.has_ground && whole;
  // The squares sent again with this message, in turn.
  Refresh refresh;
  refresh.total = f.has_ground ? tiles_of(f.ground.nx, f.ground.ny) : 0;
  for (const FrameField& load : f.loads) refresh.total += tiles_of(load.nx, load.ny);
  if (refresh.total > 0) {
    refresh.first = refresh_next_ % refresh.total;
    refresh.count = (refresh.total + kSceneRefreshMessages - 1) / kSceneRefreshMessages;
    refresh_next_ = (refresh.first + refresh.count) % refresh.total;
  } else {
    refresh.total = 1;
  }
  std::int64_t square = 0;
  m.tiles.clear();
  if (f.has_ground) {
    const bool flow = !f.flow_x.empty();
    append_changed_tiles({f.ground.nx, f.ground.ny, &f.ground.surface_m, nullptr, flow ? &f.flow_x : nullptr, flow ? &f.flow_y : nullptr},
                         {f.ground.nx, f.ground.ny, &sent_.ground.surface_m, nullptr, flow ? &sent_.flow_x : nullptr,
                          flow ? &sent_.flow_y : nullptr},
                         whole, refresh, square, m.tiles);
  }
  m.num_tiles = static_cast<std::int32_t>(m.tiles.size());
  // The loads: a new or resized one goes whole.
  m.has_bucket = f.has_bucket;
  m.num_loads = static_cast<std::int16_t>(f.loads.size());
  m.loads.resize(f.loads.size());
  if (sent_.loads.size() != f.loads.size()) sent_.loads.assign(f.loads.size(), FrameField{});
  for (std::size_t k = 0; k < f.loads.size(); ++k) {
    const FrameField& load = f.loads[k];
    FrameField& sent = sent_.loads[k];
    const bool new_load = first_ || sent.nx != load.nx || sent.ny != load.ny;
    if (new_load) sent = load;
    skidsim_lcm::scene_field_t& out = m.loads[k];
    put_pose(load.pose, out.pose);
    out.nx = load.nx, out.ny = load.ny, out.cell_m = load.cell_m;
    out.tiles.clear();
    append_changed_tiles({load.nx, load.ny, &load.surface_m, &load.shows, nullptr, nullptr},
                         {load.nx, load.ny, &sent.surface_m, &sent.shows, nullptr, nullptr}, new_load, refresh, square, out.tiles);
    out.num_tiles = static_cast<std::int32_t>(out.tiles.size());
  }
  m.num_parcels = static_cast<std::int32_t>(f.parcels.size());
  m.parcel_position_m.resize(f.parcels.size());
  m.parcel_velocity_m_s.resize(f.parcels.size());
  m.parcel_quanta.resize(f.parcels.size());
  for (std::size_t k = 0; k < f.parcels.size(); ++k) {
    const FrameParcel& p = f.parcels[k];
    // Single precision: a falling parcel drawn, and the dust it raises, need no more.
    m.parcel_position_m[k] = {static_cast<float>(p.position_m.x()), static_cast<float>(p.position_m.y()),
                              static_cast<float>(p.position_m.z())};
    m.parcel_velocity_m_s[k] = {static_cast<float>(p.velocity_m_s.x()), static_cast<float>(p.velocity_m_s.y()),
                                static_cast<float>(p.velocity_m_s.z())};
    m.parcel_quanta[k] = p.quanta;
  }
  first_ = false;
  return m;
}

bool SceneStreamReader::ready() const {
  if (!started_ || ground_waiting_ || ground_missing_ > 0) return false;
  for (const std::size_t missing : load_missing_)
    if (missing > 0) return false;
  return true;
}

void SceneStreamReader::apply(const skidsim_lcm::scene_t& m) {
  // Everything is checked before anything changes: a message that does not
  // fit leaves the frame as it was.
  if (!(std::isfinite(m.sim_time_s) && m.sim_time_s >= 0.0) ||
      (started_ && !(m.sim_time_s >= frame_.time_s && m.sim_time_s <= frame_.time_s + kMaxGapS)))
    throw SceneStreamError("scene: time " + std::to_string(m.sim_time_s) + " s after a frame at " + std::to_string(frame_.time_s) +
                           " s (times go forward, at most " + std::to_string(kMaxGapS) + " s at once)");
  const bool new_ground = !started_ || m.has_ground != frame_.has_ground || m.ground_nx != frame_.ground.nx ||
                          m.ground_ny != frame_.ground.ny;
  // A ground not held before starts afresh: from a whole one, or (joining)
  // from the squares that come; joining, a new ground whose message brings
  // none of its squares waits for one that does (which tells whether the
  // flow record comes with it).
  const bool take_ground = m.has_ground && !(joining_ && new_ground && !m.ground_whole && m.tiles.empty());
  const bool fresh_ground = take_ground && (new_ground || m.ground_whole);
  bool flow = false;
  if (m.has_ground) {
    if (!sized(m.ground_nx, m.ground_ny, m.ground_cell_m))
      throw SceneStreamError("scene: ground " + std::to_string(m.ground_nx) + " x " + std::to_string(m.ground_ny) +
                             " cells of " + std::to_string(m.ground_cell_m) + " m");
    if (!joining_ && new_ground && !m.ground_whole) throw SceneStreamError("scene: a new ground that is not sent whole");
    if (!get_pose(m.ground_pose).matrix().allFinite()) throw SceneStreamError("scene: the ground's pose is not finite");
    // A fresh ground brings the flow record or not; a change keeps it as it was.
    flow = fresh_ground ? !m.tiles.empty() && m.tiles.front().num_flow > 0 : !frame_.flow_x.empty();
    check_tiles(m.tiles, m.ground_nx, m.ground_ny, flow, false, m.ground_whole, "the ground");
  }
  const std::size_t loads = static_cast<std::size_t>(std::max<std::int16_t>(m.num_loads, 0));
  if (m.num_loads < 0 || m.loads.size() != loads || (m.has_bucket && loads == 0))
    throw SceneStreamError("scene: " + std::to_string(m.num_loads) + " loads");
  for (std::size_t k = 0; k < loads; ++k) {
    const skidsim_lcm::scene_field_t& l = m.loads[k];
    const std::string what = "load " + std::to_string(k);
    if (!sized(l.nx, l.ny, l.cell_m) || l.num_tiles != static_cast<int>(l.tiles.size()) || !get_pose(l.pose).matrix().allFinite())
      throw SceneStreamError("scene: " + what + ", " + std::to_string(l.nx) + " x " + std::to_string(l.ny) + " cells");
    const bool kept = started_ && k < frame_.loads.size() && frame_.loads[k].nx == l.nx && frame_.loads[k].ny == l.ny;
    check_tiles(l.tiles, l.nx, l.ny, false, true, !kept && !joining_, what);
  }
  const std::size_t parcels = static_cast<std::size_t>(std::max(m.num_parcels, 0));
  if (m.num_parcels < 0 || m.parcel_position_m.size() != parcels || m.parcel_velocity_m_s.size() != parcels ||
      m.parcel_quanta.size() != parcels)
    throw SceneStreamError("scene: " + std::to_string(m.num_parcels) + " parcels");
  for (std::size_t k = 0; k < parcels; ++k) {
    const auto& p = m.parcel_position_m[k];
    const auto& v = m.parcel_velocity_m_s[k];
    if (p.size() != 3 || v.size() != 3 || !std::isfinite(p[0] + p[1] + p[2] + v[0] + v[1] + v[2]) || m.parcel_quanta[k] <= 0)
      throw SceneStreamError("scene: parcel " + std::to_string(k) + " is not three finite numbers for where, three for how "
                             "fast and its quanta");
  }
  SceneFrame poses;
  get_poses(m.link_pose, poses.links);
  get_poses(m.tray_pose, poses.trays);
  get_poses(m.agent_pose, poses.agents);
  if (poses.links.empty()) throw SceneStreamError("scene: no links");

  // It fits: apply.
  frame_.step = m.step;
  frame_.time_s = m.sim_time_s;
  frame_.links.swap(poses.links);
  frame_.trays.swap(poses.trays);
  frame_.agents.swap(poses.agents);
  ground_waiting_ = m.has_ground && !take_ground;
  frame_.has_ground = take_ground;
  if (take_ground) {
    FrameField& g = frame_.ground;
    if (fresh_ground) {
      g.nx = m.ground_nx, g.ny = m.ground_ny;
      g.surface_m.assign(static_cast<std::size_t>(g.nx) * static_cast<std::size_t>(g.ny), 0.0f);
      frame_.flow_x.assign(flow ? g.surface_m.size() : 0, 0);
      frame_.flow_y.assign(flow ? g.surface_m.size() : 0, 0);
      if (joining_) ground_known_.assign(g.surface_m.size(), 0), ground_missing_ = g.surface_m.size();
    }
    g.cell_m = m.ground_cell_m;
    g.pose = get_pose(m.ground_pose);
    apply_tiles(m.tiles, {g.nx, g.ny, &g.surface_m, nullptr, flow ? &frame_.flow_x : nullptr, flow ? &frame_.flow_y : nullptr});
    if (joining_) mark_known(m.tiles, g.nx, ground_known_, ground_missing_);
  } else {
    frame_.ground = FrameField{};
    frame_.flow_x.clear(), frame_.flow_y.clear();
    ground_known_.clear(), ground_missing_ = 0;
  }
  frame_.has_bucket = m.has_bucket;
  frame_.loads.resize(loads);
  if (joining_) loads_known_.resize(loads), load_missing_.resize(loads, 0);
  for (std::size_t k = 0; k < loads; ++k) {
    const skidsim_lcm::scene_field_t& l = m.loads[k];
    FrameField& f = frame_.loads[k];
    if (f.nx != l.nx || f.ny != l.ny) {
      f.nx = l.nx, f.ny = l.ny;
      f.surface_m.assign(static_cast<std::size_t>(f.nx) * static_cast<std::size_t>(f.ny), 0.0f);
      f.shows.assign(f.surface_m.size(), 0);
      if (joining_) loads_known_[k].assign(f.surface_m.size(), 0), load_missing_[k] = f.surface_m.size();
    }
    f.pose = get_pose(l.pose);
    f.cell_m = l.cell_m;
    apply_tiles(l.tiles, {f.nx, f.ny, &f.surface_m, &f.shows, nullptr, nullptr});
    if (joining_) mark_known(l.tiles, f.nx, loads_known_[k], load_missing_[k]);
  }
  frame_.parcels.resize(parcels);
  for (std::size_t k = 0; k < parcels; ++k) {
    const auto& p = m.parcel_position_m[k];
    const auto& v = m.parcel_velocity_m_s[k];
    frame_.parcels[k] = {Eigen::Vector3f(p[0], p[1], p[2]).cast<double>(), Eigen::Vector3f(v[0], v[1], v[2]).cast<double>(),
                         m.parcel_quanta[k]};
  }
  started_ = true;
}

}  // namespace skidsim::visual
