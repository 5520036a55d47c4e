// The scene stream (visual/scene_stream.h): a session's frames, sent as
// changes, arrive whole and exact; what does not fit is refused.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "io/loader_files.h"
#include "io/soil_table.h"
#include "session/session.h"

namespace skidsim::session {
namespace {

const std::string kSource = SKIDSIM_SOURCE_DIR;

bool same_pose(const Eigen::Isometry3d& a, const Eigen::Isometry3d& b) { return a.matrix() == b.matrix(); }

bool same_poses(const std::vector<Eigen::Isometry3d>& a, const std::vector<Eigen::Isometry3d>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t k = 0; k < a.size(); ++k)
    if (!same_pose(a[k], b[k])) return false;
  return true;
}

// The largest surface difference seen (m).
double g_surface_off_m = 0.0;

bool same_field(const visual::FrameField& a, const visual::FrameField& b) {
  if (!(same_pose(a.pose, b.pose) && a.nx == b.nx && a.ny == b.ny && a.cell_m == b.cell_m && a.shows == b.shows &&
        a.surface_m.size() == b.surface_m.size()))
    return false;
  for (std::size_t c = 0; c < a.surface_m.size(); ++c) {
    const double off = std::abs(static_cast<double>(a.surface_m[c]) - b.surface_m[c]);
    g_surface_off_m = std::max(g_surface_off_m, off);
    if (!(off < visual::kSceneSurfaceStepM)) return false;
  }
  return true;
}

bool near_flow(const std::vector<std::int64_t>& a, const std::vector<std::int64_t>& b) {
  if (a.size() != b.size()) return false;
  for (std::size_t c = 0; c < a.size(); ++c)
    if (!(std::abs(a[c] - b[c]) < visual::kSceneFlowStepQuanta + visual::kSceneFlowUnitQuanta)) return false;
  return true;
}

// Whether the reader's frame is the captured one: poses and loads' cells
// exactly, parcels in single precision, surfaces and the flow record within
// the stream's steps.
// (A view that joined late counts the flow record from when it joined.)
std::string difference(const visual::SceneFrame& a, const visual::SceneFrame& b, bool flow_record = true) {
  if (a.step != b.step || a.time_s != b.time_s) return "step";
  if (!same_poses(a.links, b.links)) return "links";
  if (!same_poses(a.trays, b.trays)) return "trays";
  if (!same_poses(a.agents, b.agents)) return "agents";
  if (a.has_ground != b.has_ground || !same_field(a.ground, b.ground)) return "ground";
  if (flow_record && (!near_flow(a.flow_x, b.flow_x) || !near_flow(a.flow_y, b.flow_y))) return "flow record";
  if (a.flow_x.size() != b.flow_x.size()) return "flow record's size";
  if (a.has_bucket != b.has_bucket || a.loads.size() != b.loads.size()) return "loads";
  for (std::size_t k = 0; k < a.loads.size(); ++k)
    if (!same_field(a.loads[k], b.loads[k])) return "load " + std::to_string(k);
  if (a.parcels.size() != b.parcels.size()) return "parcels";
  for (std::size_t k = 0; k < a.parcels.size(); ++k)
    if (a.parcels[k].position_m != b.parcels[k].position_m.cast<float>().cast<double>() ||
        a.parcels[k].velocity_m_s != b.parcels[k].velocity_m_s.cast<float>().cast<double>() || a.parcels[k].quanta != b.parcels[k].quanta)
      return "parcel " + std::to_string(k);
  return "";
}

// A view joining the stream late (a live view started after the session):
// from message kJoinAt on, as a reader that never saw the first.
constexpr int kJoinAt = 250;

struct Captured : SessionOutput {
  const engine::World* world = nullptr;
  visual::SceneStreamReader reader;
  visual::SceneStreamReader joiner{visual::SceneStreamReader::Start::kJoining};
  int joiner_ready_after = -1, joiner_mismatches = 0;
  std::string joiner_first_mismatch;
  visual::SceneFrame frame;
  int messages = 0, mismatches = 0, with_parcels = 0, with_load = 0;
  std::size_t bytes = 0, tiles = 0, first_bytes = 0, load_bytes = 0, parcels = 0, poses = 0;
  std::string first_mismatch;
  void scene(const skidsim_lcm::scene_t& m, double) override {
    // Through the wire format: encoded, decoded, applied.
    std::vector<std::uint8_t> buffer(static_cast<std::size_t>(m.getEncodedSize()));
    ASSERT_EQ(m.encode(buffer.data(), 0, static_cast<int>(buffer.size())), static_cast<int>(buffer.size()));
    skidsim_lcm::scene_t decoded;
    visual::decode_scene(buffer.data(), buffer.size(), decoded);
    reader.apply(decoded);
    visual::capture_frame(*world, frame);
    const std::string d = difference(reader.frame(), frame);
    if (!d.empty() && mismatches++ == 0) first_mismatch = d + " at " + std::to_string(m.sim_time_s) + " s";
    if (messages >= kJoinAt) {
      joiner.apply(decoded);
      if (joiner.ready() && joiner_ready_after < 0) joiner_ready_after = messages - kJoinAt + 1;
      const std::string dj = joiner.ready() ? difference(joiner.frame(), frame, false) : "";
      if (!dj.empty() && joiner_mismatches++ == 0) joiner_first_mismatch = dj + " at " + std::to_string(m.sim_time_s) + " s";
    }
    if (messages == 0) first_bytes = buffer.size();
    ++messages;
    bytes += buffer.size();
    tiles += static_cast<std::size_t>(m.num_tiles);
    for (const skidsim_lcm::scene_field_t& l : m.loads)
      for (const skidsim_lcm::scene_tile_t& t : l.tiles) load_bytes += 5u * static_cast<std::size_t>(t.num_cells);
    with_parcels += m.num_parcels > 0;
    parcels += static_cast<std::size_t>(m.num_parcels);
    poses += static_cast<std::size_t>(m.num_links + m.num_trays + m.num_agents);
    with_load += !m.loads.empty() && m.loads.front().num_tiles > 0;
  }
};

// The truck-loading script digs, carries and dumps: the ground changes,
// the bucket fills and empties, parcels fall, a truck comes and goes.
TEST(SceneStream, ASessionsFramesArriveExactlyThroughTheStream) {
  const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
  const io::Exercise ex = io::load_exercise(kSource + "/scenarios/truck_loading.xml");
  SessionOptions options;
  options.scene_stream = true;
  options.limit_s = 60.0;
  Session session(ex, io::load_loader(ex.machine.loader), soils, options);
  ScriptOperator op(io::load_operator_script(kSource + "/scenarios/truck_loading.operator.xml"));
  Captured out;
  out.world = &session.world();
  const DecideControls decide = [&](const skidsim_lcm::state_t& st, long, double t) { return op.decide(st, t); };
  while (session.tick(false, decide, out).empty()) {
  }
  std::printf("[ measured ] %d scene messages over %.1f s: %.1f kB a second (the first %.1f kB, every ground square), "
              "%.1f ground squares a message; the loads %.1f kB a second; %d with falling parcels, %d with a changed bucket load; "
              "surfaces at most %.2f mm off the world's; %.1f poses and %.1f parcels a message\n",
              out.messages, session.world().time_s(), 1e-3 * out.bytes / session.world().time_s(), 1e-3 * out.first_bytes,
              static_cast<double>(out.tiles) / out.messages, 1e-3 * out.load_bytes / session.world().time_s(), out.with_parcels,
              out.with_load, 1e3 * g_surface_off_m, static_cast<double>(out.poses) / out.messages,
              static_cast<double>(out.parcels) / out.messages);
  EXPECT_EQ(out.mismatches, 0) << "first: " << out.first_mismatch;
  EXPECT_GE(out.messages, static_cast<int>(25 * 59));
  EXPECT_GT(out.with_parcels, 0);
  EXPECT_GT(out.with_load, 0);
  ASSERT_TRUE(out.reader.ready());
  EXPECT_FALSE(out.reader.frame().flow_x.empty()) << "the flow record travels for the sand's texture and dust";
  // Joining late: the whole picture within one refresh cycle, exact from then on.
  std::printf("[ measured ] a view joining at message %d holds the whole picture after %d messages\n", kJoinAt,
              out.joiner_ready_after);
  EXPECT_GT(out.joiner_ready_after, 0);
  EXPECT_LE(out.joiner_ready_after, visual::kSceneRefreshMessages);
  EXPECT_EQ(out.joiner_mismatches, 0) << "first: " << out.joiner_first_mismatch;
}

// Messages that do not fit are refused naming what, and the frame stays.
// An exercise's world at its start, as a frame, and a writer for it.
struct StillSite {
  explicit StillSite(const std::string& exercise) {
    const io::SoilTable soils = io::load_soil_table(io::default_soil_table_path());
    const io::Exercise ex = io::load_exercise(kSource + "/scenarios/" + exercise);
    SessionOptions options;
    options.scene_stream = true;
    Session session(ex, io::load_loader(ex.machine.loader), soils, options);
    visual::capture_frame(session.world(), frame);
  }
  visual::SceneFrame frame;
  visual::SceneStreamWriter writer;
};

TEST(SceneStream, AMessageThatDoesNotFitIsRefusedAndChangesNothing) {
  StillSite site("pile_to_zone.xml");
  visual::SceneFrame& frame = site.frame;
  visual::SceneStreamWriter& writer = site.writer;
  const skidsim_lcm::scene_t first = writer.encode(frame);
  visual::SceneStreamReader reader;
  // A change before any whole frame: the ground must come whole first.
  skidsim_lcm::scene_t partial = first;
  partial.tiles.resize(1);
  partial.num_tiles = 1;
  EXPECT_THROW(reader.apply(partial), visual::SceneStreamError);
  EXPECT_FALSE(reader.ready());
  reader.apply(first);
  ASSERT_TRUE(reader.ready());
  const visual::SceneFrame before = reader.frame();
  struct Bad {
    const char* what;
    void (*spoil)(skidsim_lcm::scene_t&);
  };
  const Bad bad[] = {
      {"a square off the grid", [](skidsim_lcm::scene_t& m) { m.tiles.front().i0 = m.ground_nx; }},
      {"a square of the wrong size", [](skidsim_lcm::scene_t& m) { m.tiles.front().num_cells += 1; }},
      {"a load's square off its cells", [](skidsim_lcm::scene_t& m) { m.loads.front().tiles.front().j0 = m.loads.front().ny; }},
      {"a load's tiles miscounted", [](skidsim_lcm::scene_t& m) { m.loads.front().num_tiles += 1; }},
      {"parcels miscounted", [](skidsim_lcm::scene_t& m) { m.num_parcels = 3; }},
      {"a pose not finite", [](skidsim_lcm::scene_t& m) { m.link_pose.front()[9] = std::nan(""); }},
      {"no links", [](skidsim_lcm::scene_t& m) { m.link_pose.clear(), m.num_links = 0; }},
      {"a ground of no size", [](skidsim_lcm::scene_t& m) { m.ground_nx = 0; }},
      {"a square past the largest int", [](skidsim_lcm::scene_t& m) { m.tiles.front().i0 = 2147483640; }},
      {"a surface not finite", [](skidsim_lcm::scene_t& m) { m.tiles.front().surface_m.front() = std::nanf(""); }},
      {"a square sent twice in a whole ground", [](skidsim_lcm::scene_t& m) { m.tiles.back() = m.tiles.front(); }},
      {"time going back", [](skidsim_lcm::scene_t& m) { m.sim_time_s = -0.02; }},
      {"time leaping ahead", [](skidsim_lcm::scene_t& m) { m.sim_time_s = 1e12; }},
      {"a load's pose not finite", [](skidsim_lcm::scene_t& m) { m.loads.front().pose[9] = std::nan(""); }},
  };
  // Bytes whose counts overstate them: refused before anything is sized.
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(first.getEncodedSize()));
  ASSERT_EQ(first.encode(bytes.data(), 0, static_cast<int>(bytes.size())), static_cast<int>(bytes.size()));
  skidsim_lcm::scene_t decoded;
  visual::decode_scene(bytes.data(), bytes.size(), decoded);
  EXPECT_EQ(decoded.num_tiles, first.num_tiles);
  std::vector<std::uint8_t> cut(bytes.begin(), bytes.begin() + static_cast<long>(bytes.size() / 2));
  EXPECT_THROW(visual::decode_scene(cut.data(), cut.size(), decoded), visual::SceneStreamError);
  std::vector<std::uint8_t> huge = bytes;
  const std::size_t tiles_at = 8 + 8 + 8 + 2 + 96 * first.link_pose.size() + 2 + 96 * first.tray_pose.size() + 2 +
                               96 * first.agent_pose.size() + 1 + 4 + 4 + 8 + 96 + 1;
  for (std::size_t k = 0; k < 4; ++k) huge[tiles_at + k] = k == 0 ? 0x7f : 0xff;  // num_tiles 2^31 - 1
  EXPECT_THROW(visual::decode_scene(huge.data(), huge.size(), decoded), visual::SceneStreamError);
  for (std::size_t k = 0; k < 4; ++k) huge[tiles_at + k] = 0xff;  // num_tiles -1
  EXPECT_THROW(visual::decode_scene(huge.data(), huge.size(), decoded), visual::SceneStreamError);
  for (const Bad& b : bad) {
    skidsim_lcm::scene_t m = first;
    m.step += 10, m.sim_time_s += 0.02;
    b.spoil(m);
    EXPECT_THROW(reader.apply(m), visual::SceneStreamError) << b.what;
    EXPECT_EQ(difference(reader.frame(), before), "") << b.what << ": the frame changed";
  }
}

// Joining (a live view started late): squares kept as they come, the frame
// ready once every cell of the ground and the loads has come: within one
// refresh of the stream, the squares of a still world going again in turn.
TEST(SceneStream, AJoiningReaderIsReadyOnceEveryCellHasCome) {
  StillSite site("truck_loading.xml");
  const visual::SceneFrame& frame = site.frame;
  visual::SceneStreamWriter& writer = site.writer;
  (void)writer.encode(frame);  // the first, whole: missed
  visual::SceneStreamReader joiner(visual::SceneStreamReader::Start::kJoining);
  // A message with none of the ground's squares leaves it waiting.
  skidsim_lcm::scene_t bare = writer.encode(frame);
  bare.tiles.clear(), bare.num_tiles = 0;
  joiner.apply(bare);
  EXPECT_FALSE(joiner.ready());
  int messages = 1;
  while (!joiner.ready() && messages < 10 * visual::kSceneRefreshMessages) {
    skidsim_lcm::scene_t m = writer.encode(frame);
    m.sim_time_s = 0.04 * ++messages;
    if (messages == 3) {
      // A square whose flow record disagrees with the ground's is refused,
      // the frame as it was.
      skidsim_lcm::scene_t odd = m;
      ASSERT_FALSE(odd.tiles.empty());
      odd.tiles.front().num_flow = 0, odd.tiles.front().flow_dx.clear(), odd.tiles.front().flow_dy.clear();
      EXPECT_THROW(joiner.apply(odd), visual::SceneStreamError);
    }
    joiner.apply(m);
  }
  std::printf("[ measured ] a joining reader of a still truck-loading site was ready after %d messages\n", messages);
  EXPECT_LE(messages, visual::kSceneRefreshMessages + 1);
  ASSERT_TRUE(joiner.ready());
  EXPECT_EQ(joiner.frame().ground.surface_m, frame.ground.surface_m);
  ASSERT_EQ(joiner.frame().loads.size(), frame.loads.size());
  for (std::size_t k = 0; k < frame.loads.size(); ++k) EXPECT_EQ(joiner.frame().loads[k].shows, frame.loads[k].shows);
}

}  // namespace

}  // namespace skidsim::session
