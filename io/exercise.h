// The exercise file: one XML file says everything a training
// session needs, and nothing it does not (a driving course on firm ground
// has no soil element, and no soil automaton is built). Plain data; the
// session runner builds the world from it. Reference: docs/exercises.md.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <limits>
#include <string>
#include <vector>

#include "terrain/flow_law.h"

namespace skidsim::io {

// A rectangle on the site, "x0 y0 x1 y1" (m, x0 < x1, y0 < y1).
using Region = Eigen::AlignedBox2d;

struct SoilPile {  // a cone of loose soil on the layer
  Eigen::Vector2d centre_m = Eigen::Vector2d::Zero();
  double radius_m = 1.0, height_m = 0.5;
};
struct SoilTrench {  // a straight trench cut into the layer
  Eigen::Vector2d from_m = Eigen::Vector2d::Zero(), to_m = Eigen::Vector2d::Zero();
  double width_m = 0.5, depth_m = 0.3;
};
struct SoilBank {  // a rectangular bank standing on the layer
  Region region;
  double height_m = 0.5;
};
struct SoilSlope {  // a ramp of soil on the layer: 0 at one side of its region, height_m at the other
  Region region;
  double height_m = 1.0;
  int rising_axis = 0;    // 0: along x, 1: along y
  bool rising_up = true;  // true: rises towards +axis
};
struct SoilSite {
  std::string id;
  Region region;
  double cell_m = 0.05;
  double depth_m = 0.0;   // the flat layer over the hard base
  std::string soil;       // an id of the soil table
  // How the site's loose soil slides: the automaton, or Li & Moshell's
  // slippage model (terrain/slippage_law.h; for cohesive soils).
  terrain::GroundModel model = terrain::GroundModel::kAutomaton;
  // Fast flows with momentum (terrain/momentum_flow.h): loads dumped or
  // spilled onto the site run out with the speed they land with.
  bool fast_flow = false;
  std::vector<SoilPile> piles;
  std::vector<SoilTrench> trenches;
  std::vector<SoilBank> banks;
  std::vector<SoilSlope> slopes;
};
struct Zone {
  std::string id;
  Region region;
};
struct BoxObstacle {
  std::string id;
  Eigen::Vector3d centre_m = Eigen::Vector3d::Zero();
  Eigen::Vector3d size_m = Eigen::Vector3d::Ones();
  double yaw_deg = 0.0;
};
struct TruckBed {  // an open container standing on the site
  std::string id;
  Eigen::Vector2d back_corner_m = Eigen::Vector2d::Zero();  // the floor's back corner
  double yaw_deg = 0.0;
  double length_m = 1.4, width_m = 2.4, floor_height_m = 0.9, wall_height_m = 0.3;
};
// A person or a dump truck on site (engine/agents.h): people walk their
// route (pausing at its points; round and round with loop) and keep out
// of a moving loader's way; a truck carries the bed of a <truck>, reverses
// along its route to the bed's place (appended as the route's end), waits
// there until the bed holds leave_at_kg, then drives off along its exit.
struct SiteAgent {
  enum class Kind { kPerson, kTruck } kind = Kind::kPerson;
  std::string id;
  std::vector<Eigen::Vector2d> route_m;
  bool loop = false;
  double pause_s = 0.0, start_s = 0.0, speed_m_s = 1.3, keep_clear_m = 6.0;
  std::string start_after;  // a task: the agent comes on site once it is done (a spawn event)
  const void* element = nullptr;  // (while reading: for messages)
  std::string bed;  // truck: the <truck> it carries
  double leave_at_kg = 0.0;
  std::vector<Eigen::Vector2d> exit_m;
};
struct MachineStart {
  std::string loader;  // parameter file (resolved against the exercise's folder)
  Eigen::Vector2d position_m = Eigen::Vector2d::Zero();
  double yaw_deg = 0.0;
  double lift_rad = 0.03, tilt_rad = 0.03;
};
struct OperatorSource {
  enum class Kind { kLcm, kScript } kind = Kind::kLcm;
  std::string lcm_url;  // empty: the default provider
  std::string channel = "SKIDSIM_CONTROL";
  double watchdog_s = 0.2;
  std::string script;  // for kScript (resolved against the exercise's folder)
};
// A task: what the trainee must do. Its parameters depend on its type.
struct Task {
  enum class Type { kDriveCourse, kMoveMaterial, kLoadTruck, kGrade, kBackfill, kClimb } type = Type::kDriveCourse;
  std::string id;
  int line = 0;               // in the exercise file, for messages
  double time_limit_s = 0.0;  // 0: the exercise's
  // drive_course: the gates, in order (each a region to pass through).
  std::vector<Region> gates;
  // move_material / backfill: from a soil site (or any) to a zone; load_truck:
  // into a truck bed. Mass to deliver.
  std::string from, to;
  double mass_kg = 0.0;
  // grade: a zone to level to a height within a tolerance.
  // Done when `coverage` of the zone's cells are within tolerance.
  double height_m = 0.0, tolerance_m = 0.05, coverage = 0.9;
  // climb: reach a zone (on a slope).
};
struct Event {
  enum class When { kAtTime, kEnterZone, kTaskDone } when = When::kAtTime;
  double at_s = 0.0;
  std::string subject;  // the zone or task
  std::string message;  // shown to the trainee (an event on the timeline)
};
struct Metric {
  std::string name;  // one of the scoring metrics of docs/exercises.md
  double weight = 1.0;
};
struct Scoring {
  std::vector<Metric> metrics;
  double pass_score = 0.0;
};
// The characters of an LCM channel's base name and of a live session's
// name: LCM subscribes to a channel as a regular expression, so none that
// means something there ('.' any character); '@' joins the two.
inline constexpr const char* kChannelNameCharacters = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_-";
inline bool channel_name_text(const std::string& s) { return s.find_first_not_of(kChannelNameCharacters) == std::string::npos; }

// Frames a second a recording or a view draws at most: the scene stream's
// rate (session::kStepsPerScene, 25 a second).
inline constexpr double kMaxRecordFps = 25.0;
// io::InputError unless 0.1 <= fps <= kMaxRecordFps, naming --fps.
void check_frame_rate(double fps);
// A frame's size in pixels, each way, from the exercise's <record> or an
// option: io::InputError naming `options` ("--width / --height") outside it.
inline constexpr int kMinFramePixels = 16, kMaxFramePixels = 8192;
void check_frame_size(int width, int height, const std::string& options);
struct Recording {
  double fps = 10.0;
  std::string camera = "chase";  // cab, chase, aerial, fixed
  int width = 1280, height = 720;
  // The fixed camera, where the exercise places it (a site camera on a
  // mast); unset (NaN): beyond the site's south-west corner, at the site.
  Eigen::Vector3d fixed_eye_m = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
  Eigen::Vector3d fixed_target_m = Eigen::Vector3d::Constant(std::numeric_limits<double>::quiet_NaN());
};

struct Exercise {
  std::string path;  // the file it was read from
  std::string name;
  int version = 1;
  double time_limit_s = 600.0;
  Eigen::Vector2d site_size_m = Eigen::Vector2d(20.0, 20.0);
  bool firm_ground = true;
  std::vector<SoilSite> soils;
  std::vector<Zone> zones;
  std::vector<BoxObstacle> boxes;
  std::vector<TruckBed> trucks;
  std::vector<SiteAgent> agents;
  MachineStart machine;
  OperatorSource operator_source;
  std::vector<Task> tasks;
  std::vector<Event> events;
  Scoring scoring;
  Recording recording;
};

// Task type names as written in the file ("move_material", ...).
const char* task_type_name(Task::Type type);
// The metrics an exercise may score (docs/exercises.md, "Elements").
const std::vector<std::string>& known_metrics();

// Reads and validates an exercise: unknown elements and attributes, values
// out of range, references to zones, tasks, soils or files that do not
// exist, regions off the site: io::InputError naming the file, line,
// element and what was expected. Soil ids are checked against
// `soil_table_path` (empty: the shipped table); file paths in the exercise
// are resolved against its folder.
Exercise load_exercise(const std::string& path, const std::string& soil_table_path = "");

}  // namespace skidsim::io
