// The scene stream (SKIDSIM_SCENE, skidsim_lcm::scene_t; docs/rendering.md,
// "The scene stream"): a SceneFrame as a message, 25 a second, with every
// second state message. The ground and the loads go as changes against what was sent
// before (the ground in squares of kSceneTileCells, its flow record as what
// it grew by), so a view keeps them from message to message; everything
// else goes whole. A reader that has applied every message holds the
// writer's frame as sent (surfaces within kSceneSurfaceStepM of the world's,
// its flow record counted from the first message it applied), so a view
// draws the pixels the session's own recording draws.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <vector>

#include "skidsim_lcm/scene_t.hpp"
#include "visual/scene_frame.h"

namespace skidsim::visual {

inline constexpr const char* kSceneChannel = "SKIDSIM_SCENE";
inline constexpr int kSceneTileCells = 8;
// A square of a surface goes when one of its cells moved this much since it
// was last sent: half a millimetre, below what a frame shows at the
// sessions' cells; the automaton's creep, far smaller, would otherwise send
// most squares every message. A view's surfaces are within it of the
// world's, and the session's own recording, which draws the stream too,
// shows the same.
inline constexpr float kSceneSurfaceStepM = 0.0005f;
// The flow record's growth goes in units of 1024 quanta (about 1 um of
// soil; int32: the automaton's avalanches, back and forth, sent 0.25 m
// across a face in one message's 40 ms while truck loading, far below the
// 2 km an int32 holds; more would go in the next).
inline constexpr std::int64_t kSceneFlowUnitQuanta = 1024;
// The flow record's growth that sends a square on its own: 0.1 mm of soil
// across a face, a flow of 0.01 m/s over a message's 40 ms in a 5 cm cell
// (scene_snapshot's speeds), below what the eye follows; it goes, not lost,
// with the square's next change.
inline constexpr std::int64_t kSceneFlowStepQuanta = static_cast<std::int64_t>(1e-4 / terrain::kHeightQuantumM);

// Every square of the ground and the loads goes again at least once in this
// many messages (5 s at the stream's 25 a second), a few with each message
// besides those that changed: a view that joins a live session late, or
// loses a message to the network, holds the whole picture again within
// them, without a burst the size of the whole ground (432 kB while truck
// loading, beyond a host's default UDP receive buffer). It adds a fifth of
// the whole ground's size a second to the stream (docs/rendering.md).
inline constexpr int kSceneRefreshMessages = 125;

class SceneStreamWriter {
 public:
  // The message for `frame`: its ground's squares and its loads that differ
  // from those sent before (every one the first time), and the next of the
  // squares sent again in turn (kSceneRefreshMessages). Valid until the next call.
  const skidsim_lcm::scene_t& encode(const SceneFrame& frame);

 private:
  bool first_ = true;
  SceneFrame sent_;
  std::int64_t refresh_next_ = 0;  // the square sent again next, counting the ground's, then each load's
  skidsim_lcm::scene_t message_;
};

// A message that does not fit the stream so far (its sizes, a square off
// the grid, a change before any whole frame).
struct SceneStreamError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// Decodes a scene_t from bytes (a log's event, a network packet) after
// checking that every count in it fits the bytes there are, so that no
// count makes the decoder allocate more than the message holds; throws
// SceneStreamError otherwise.
void decode_scene(const std::uint8_t* data, std::size_t size, skidsim_lcm::scene_t& out);

class SceneStreamReader {
 public:
  // From the stream's first message (a log): a new ground or load must come
  // whole. Joining (a live view): from any message; a field's squares are
  // kept as they come, and the frame is ready once every cell has come.
  enum class Start { kFirstMessage, kJoining };
  explicit SceneStreamReader(Start start = Start::kFirstMessage) : joining_(start == Start::kJoining) {}
  // Applies one message; throws SceneStreamError naming what does not fit
  // (the frame is then as before): sizes and squares off their fields, a
  // new ground or load not sent whole (unless joining), numbers not
  // finite, a time before the frame's or more than kMaxGapS after it.
  static constexpr double kMaxGapS = 10.0;
  void apply(const skidsim_lcm::scene_t& message);
  // Whether the frame holds every cell of the ground and the loads.
  bool ready() const;
  const SceneFrame& frame() const { return frame_; }

 private:
  bool joining_;
  bool started_ = false;  // a message has been applied
  SceneFrame frame_;
  // The cells that have come (joining), the ground's and each load's.
  std::vector<std::uint8_t> ground_known_;
  std::vector<std::vector<std::uint8_t>> loads_known_;
  std::size_t ground_missing_ = 0;
  std::vector<std::size_t> load_missing_;
  bool ground_waiting_ = false;  // joining: a ground none of whose squares has come
};

}  // namespace skidsim::visual
