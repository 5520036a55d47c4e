// skidsim: one command, with subcommands. Thin: parse, wire, report.
#include <CLI/CLI.hpp>
#include <tinyxml2.h>
#include <nlohmann/json.hpp>
#include <benchmark/benchmark.h>

#include <cmath>
#include <sstream>
#include <exception>
#include <iostream>
#include <string>
#include <vector>

#include "jobs/dig_job.h"
#include "jobs/pour_job.h"
#include "jobs/push_job.h"
#include "apps/operator_job.h"
#include "apps/render_job.h"
#include "apps/review_job.h"
#include "apps/view_job.h"
#include "station/station.h"
#include "apps/batch_job.h"
#include "report/perf_report.h"
#include "apps/run_job.h"
#include "session/session_tasks.h"
#include "session/session_world.h"
#include "io/operator_script.h"
#include "jobs/interrupt.h"
#include "io/atomic_file.h"
#include "io/exercise.h"
#include "io/loader_files.h"
#include "io/soil_table.h"
#include "io/xml_reader.h"
#include "vehicle/loader_figures.h"

namespace {

int run_bench(bool json, const std::string& filter, double min_time_s, const std::string& out_file) {
  std::vector<std::string> args = {"skidsim-bench"};
  if (json) args.push_back("--benchmark_format=json");
  if (!filter.empty()) args.push_back("--benchmark_filter=" + filter);
  if (min_time_s > 0) args.push_back("--benchmark_min_time=" + std::to_string(min_time_s));
  if (!out_file.empty()) {
    args.push_back("--benchmark_out=" + out_file);
    args.push_back("--benchmark_out_format=json");
  }
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  int argc = static_cast<int>(argv.size());
  benchmark::Initialize(&argc, argv.data());
  const std::size_t ran = benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (ran == 0) {
    std::cerr << "skidsim bench: no benchmark matches '" << filter << "'\n";
    return 2;
  }
  return 0;
}

// Every number on the command line is a finite decimal in its range where it
// enters (CLI11's own Range and PositiveNumber let NaN through, and its
// parser takes hex and inf).
CLI::Validator number_in(double lo, double hi) {
  std::ostringstream range;
  range << "[" << lo << ", " << hi << "]";
  return CLI::Validator(
      [lo, hi, r = range.str()](std::string& text) -> std::string {
        const char* p = text.c_str();
        double v = 0.0;
        if (!skidsim::io::parse_decimal_number(p, v) || *p != '\0') return "'" + text + "' is not a finite decimal number";
        if (!(v >= lo && v <= hi)) return "'" + text + "' is not within " + r;
        return "";
      },
      "NUMBER in " + range.str());
}

// A frame's width and height options, each checked against the frame's
// range (io::kMinFramePixels to io::kMaxFramePixels).
void add_frame_size(CLI::App& cmd, const std::string& width_name, const std::string& height_name, int& width, int& height,
                    const std::string& help) {
  const CLI::Validator pixels = number_in(skidsim::io::kMinFramePixels, skidsim::io::kMaxFramePixels);
  cmd.add_option(width_name, width, help)->check(pixels);
  cmd.add_option(height_name, height, help)->check(pixels);
}

// Options every job has: its run directory and its soil.
void add_job_options(CLI::App* cmd, std::string& out_dir, std::string& soil_id, std::string& soil_table) {
  cmd->add_option("--out", out_dir, "Run directory to write")->capture_default_str();
  cmd->add_option("--soil", soil_id, "Soil id from the soil table")->capture_default_str();
  cmd->add_option("--soil-table", soil_table, "Soil table XML (default: assets/soils.xml)");
}

// Reads a loader (parameters, URDF, meshes), validates it, and prints the
// figures its description implies (vehicle/loader_figures.h).
int check_loader(const std::string& path, bool json) {
  const skidsim::vehicle::LoaderDescription d = skidsim::io::load_loader(path);
  const skidsim::vehicle::LoaderFigures f = skidsim::vehicle::loader_figures(d);
  // A figure someone may act on is a number: one that is not finite, or a
  // mass, cycle time, speed or force that is not positive, means the files
  // describe no working machine, whatever passed on the way in. Cycle times
  // name their cylinder's line.
  auto cylinder_line = [&](int joint) {
    for (const auto& c : d.cylinders)
      if (c.joint == joint) return c.line;
    return 0;
  };
  const struct {
    const char* name;
    double value;
    bool positive;
    int line;
  } figures[] = {{"mass_kg", f.mass_kg, true, 0},
                 {"static_tipping_load_kg", f.static_tipping_load_kg, false, 0},
                 {"rated_operating_capacity_kg", f.rated_operating_capacity_kg, false, 0},
                 {"hinge_pin_height_m", f.hinge_pin_height_m, false, 0},
                 {"arm_travel_deg", f.arm_travel_deg, true, 0},
                 {"lift_time_s", f.lift_time_s, true, cylinder_line(0)},
                 {"lower_time_s", f.lower_time_s, true, cylinder_line(0)},
                 {"dump_time_s", f.dump_time_s, true, cylinder_line(1)},
                 {"curl_time_s", f.curl_time_s, true, cylinder_line(1)},
                 {"top_speed_km_h", f.top_speed_km_h, true, 0},
                 {"push_force_kN", f.push_force_kN, true, 0}};
  for (const auto& figure : figures)
    if (!std::isfinite(figure.value) || (figure.positive && !(figure.value > 0.0)))
      throw skidsim::io::InputError(path + (figure.line > 0 ? ":" + std::to_string(figure.line) : std::string()) +
                                    ": the loader's " + figure.name + " comes out as " + std::to_string(figure.value) +
                                    (figure.positive ? " (must be finite and positive)" : " (must be finite)"));
  nlohmann::json j;
  j["parameters"] = d.parameters_path;
  j["urdf"] = d.urdf_path;
  j["links"] = d.links.size();
  j["wheels"] = d.wheels.size();
  j["mass_kg"] = f.mass_kg;
  j["static_tipping_load_kg"] = f.static_tipping_load_kg;
  j["rated_operating_capacity_kg"] = f.rated_operating_capacity_kg;
  j["hinge_pin_height_m"] = f.hinge_pin_height_m;
  j["arm_travel_deg"] = f.arm_travel_deg;
  j["lift_time_s"] = f.lift_time_s;
  j["lower_time_s"] = f.lower_time_s;
  j["dump_time_s"] = f.dump_time_s;
  j["curl_time_s"] = f.curl_time_s;
  j["top_speed_km_h"] = f.top_speed_km_h;
  j["push_force_kN"] = f.push_force_kN;
  if (json) {
    std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    return 0;
  }
  std::cout << "loader " << path << ": valid\n";
  for (const auto& [key, value] : j.items())
    if (key != "parameters") std::cout << "  " << key << ": " << value << "\n";
  return 0;
}

// Reads an exercise (and the loader it names), validates both, and prints
// what the session would build, without running it.
int check_exercise(const std::string& path, bool json) {
  const skidsim::io::Exercise e = skidsim::io::load_exercise(path);
  const skidsim::vehicle::LoaderDescription loader = skidsim::io::load_loader(e.machine.loader);
  if (e.operator_source.kind == skidsim::io::OperatorSource::Kind::kScript)
    skidsim::io::load_operator_script(e.operator_source.script);
  // What the session would build, built once (refusals name the file).
  const auto world =
      skidsim::session::build_session_world(e, loader, skidsim::io::load_soil_table(skidsim::io::default_soil_table_path()));
  skidsim::session::check_tasks(e, *world);
  nlohmann::json j;
  j["exercise"] = e.name;
  j["file"] = path;
  j["time_limit_s"] = e.time_limit_s;
  j["site_m"] = {e.site_size_m.x(), e.site_size_m.y()};
  j["firm_ground"] = e.firm_ground;
  nlohmann::json soils = nlohmann::json::array();
  for (const auto& s : e.soils) {
    const Eigen::Vector2d cells = s.region.sizes() / s.cell_m;
    soils.push_back({{"id", s.id}, {"soil", s.soil}, {"cell_m", s.cell_m},
                     {"cells", static_cast<long>(std::lround(cells.x())) * std::lround(cells.y())},
                     {"piles", s.piles.size()}, {"trenches", s.trenches.size()}, {"banks", s.banks.size()}});
  }
  j["soil_sites"] = soils;
  j["zones"] = e.zones.size();
  j["boxes"] = e.boxes.size();
  j["trucks"] = e.trucks.size();
  j["loader"] = e.machine.loader;
  j["operator"] = e.operator_source.kind == skidsim::io::OperatorSource::Kind::kLcm
                      ? "lcm channel " + e.operator_source.channel
                      : "script " + e.operator_source.script;
  nlohmann::json tasks = nlohmann::json::array();
  for (const auto& t : e.tasks) tasks.push_back(std::string(skidsim::io::task_type_name(t.type)) + " " + t.id);
  j["tasks"] = tasks;
  j["events"] = e.events.size();
  j["metrics"] = e.scoring.metrics.size();
  if (json) {
    std::cout << j.dump(2, ' ', false, nlohmann::json::error_handler_t::replace) << "\n";
    return 0;
  }
  std::cout << "exercise " << path << ": valid\n";
  for (const auto& [key, value] : j.items())
    if (key != "file") std::cout << "  " << key << ": " << value << "\n";
  return 0;
}

// The root element says which kind of file it is.
int check_file(const std::string& path, bool json) {
  tinyxml2::XMLDocument doc;
  skidsim::io::load_xml(doc, path);
  const tinyxml2::XMLElement* root = doc.RootElement();
  const std::string kind = root ? root->Name() : "";
  if (kind == "exercise") return check_exercise(path, json);
  if (kind == "loader_parameters") return check_loader(path, json);
  skidsim::io::fail_at(path, root, "expected an <exercise> or a <loader_parameters> file");
}

int list_soils(const std::string& path) {
  const auto table = skidsim::io::load_soil_table(path);
  std::cout << "soils in " << path << ":\n";
  for (const auto& [id, rec] : table) {
    std::cout << "  " << id << ": " << rec.description << " (density " << rec.flow.bulk_density_kg_m3
              << " kg/m^3, repose " << rec.flow.repose_angle_deg << " deg, stop " << rec.flow.stop_angle_deg
              << " deg; slippage model: c " << rec.flow.slip_cohesion_Pa / 1000.0 << " kPa, phi "
              << rec.flow.slip_friction_deg() << " deg)\n";
  }
  return 0;
}

// Every command's options and the values they fill.
struct Commands {
  skidsim::jobs::PourJob pour{};
  skidsim::jobs::PushJob push{};
  skidsim::jobs::DigJob dig{};
  skidsim::apps::RunJob run{};
  skidsim::apps::RenderJob render_job{};
  skidsim::apps::ReviewJob review_job{};
  skidsim::apps::ViewJob view_job{};
  skidsim::apps::BatchJob batch_job{};
  skidsim::apps::OperatorJob operator_job{};
  skidsim::station::StationOptions station_job{};
  bool bench_json = false;
  double bench_min_time = 0.0;
  skidsim::report::PerfReportJob report_job{};
  std::string loader_path = skidsim::io::default_loader_path();
  std::string check_path{};
  bool check_json = false;
  std::string soil_table = skidsim::io::default_soil_table_path();
  std::string bench_filter;
  std::string bench_out;
  CLI::App* pour_cmd = nullptr;
  CLI::App* push_cmd = nullptr;
  CLI::App* dig_cmd = nullptr;
  CLI::App* run_cmd = nullptr;
  CLI::App* render_cmd = nullptr;
  CLI::App* review_cmd = nullptr;
  CLI::App* view_cmd = nullptr;
  CLI::App* batch_cmd = nullptr;
  CLI::App* operator_cmd = nullptr;
  CLI::App* station_cmd = nullptr;
  CLI::App* bench_cmd = nullptr;
  CLI::App* report_cmd = nullptr;
  CLI::App* check_cmd = nullptr;
  CLI::App* soils_cmd = nullptr;
};

// The batch jobs: pour, push, dig.
void add_job_commands(CLI::App& app, Commands& c) {

  c.pour_cmd = app.add_subcommand(
      "pour", "Pour sand from a hopper onto a site, let it settle, and write a run directory\n"
              "(summary.json, final terrain as 16-bit PNG height maps with JSON metadata)");
  add_job_options(c.pour_cmd, c.pour.out_dir, c.pour.soil_id, c.pour.soil_table_path);
  c.pour_cmd->add_option("--site-m", c.pour.site_size_m, "Side of the square site, m")->capture_default_str()->check(number_in(1e-6, 1e12));
  c.pour_cmd->add_option("--cell-m", c.pour.cell_size_m, "Cell size, m")->capture_default_str()->check(number_in(1e-6, 1e12));
  c.pour_cmd->add_option("--layer-m", c.pour.layer_depth_m, "Initial flat layer of soil, m")->capture_default_str()->check(number_in(0.0, 1000.0));
  c.pour_cmd->add_option("--rate-kg-s", c.pour.pour_rate_kg_per_s, "Hopper flow, kg/s")->capture_default_str()->check(number_in(0.0, 1e12));
  c.pour_cmd->add_option("--pour-s", c.pour.pour_duration_s, "Pouring time, s")->capture_default_str()->check(number_in(0.0, 86400.0));
  c.pour_cmd->add_option("--hopper-m", c.pour.hopper_radius_m, "Hopper outlet radius, m")->capture_default_str()->check(number_in(0.0, 1000.0));
  c.pour_cmd->add_option("--settle-s", c.pour.max_settle_s, "Longest settling time after the pour, s")->capture_default_str()->check(number_in(0.0, 86400.0));
  c.pour_cmd->add_option("--material-map", c.pour.material_map_path,
                       "Initial material depth: a height map's JSON (quantity \"material\"), e.g. a previous run's "
                       "terrain_material.json; sets the grid")
      ->check(CLI::ExistingFile);
  c.pour_cmd->add_option("--base-map", c.pour.base_map_path,
                       "Hard base relief: a height map's JSON (quantity \"base\"); sets the grid")
      ->check(CLI::ExistingFile);
  c.pour_cmd->add_flag("--open-edges", c.pour.open_edges, "Site edges are drop-offs (material leaving is counted off-site) instead of walls");

  c.push_cmd = app.add_subcommand(
      "push", "Push a blade (vertical or raked) through a flat layer of soil and record its resistance along the push\n"
              "(the thesis's fig. 7.12): summary.json, resistance.csv, the final terrain height map");
  add_job_options(c.push_cmd, c.push.out_dir, c.push.soil_id, c.push.soil_table_path);
  c.push_cmd->add_option("--cells-per-m", c.push.cells_per_m, "Grid density, cells per metre")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.push_cmd->add_option("--layer-m", c.push.layer_m, "Depth of the flat layer of soil, m")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.push_cmd->add_option("--depth-m", c.push.depth_m, "Blade edge below the surface (H), m")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.push_cmd->add_option("--width-m", c.push.width_m, "Blade width (B), m")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.push_cmd->add_option("--rake-deg", c.push.rake_deg, "Blade face's angle from the horizontal (90: vertical), deg")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.push_cmd->add_option("--cutting-model", c.push.cutting_model, "earthmoving or thesis_wedge (default: the soil table's)");
  c.push_cmd->add_option("--speed-m-s", c.push.speed_m_s, "Push speed, m/s")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.push_cmd->add_option("--distance-m", c.push.distance_m, "Length of the push, m")->capture_default_str()->check(number_in(-1e300, 1e300));

  c.dig_cmd = app.add_subcommand(
      "dig", "The loader fills its bucket from a sand bank, carries the load to a truck bed and dumps it,\n"
             "driven by a built-in scripted operator: summary.json (masses, books), phases.csv, height maps");
  add_job_options(c.dig_cmd, c.dig.out_dir, c.dig.soil_id, c.dig.soil_table_path);
  c.dig_cmd->add_option("--cells-per-m", c.dig.cells_per_m, "Grid density of the site and the bucket, cells per metre")
      ->capture_default_str()->check(number_in(-1e300, 1e300));
  c.dig_cmd->add_option("--bank-m", c.dig.bank_height_m, "Height of the sand bank, m")->capture_default_str()->check(number_in(-1e300, 1e300));
  c.dig_cmd->add_option("--loader", c.dig.loader_path, "Loader parameter file (default: the shipped loader)");
}

// A session: run.
void add_session_command(CLI::App& app, Commands& c) {
  c.run_cmd = app.add_subcommand(
      "run", "Run a training session from an exercise file: its world, operator (a script, or commands over\n"
             "LCM), tasks and score; writes a run directory (report.json, report.html, session.lcmlog, final terrain)");
  c.run_cmd->add_option("exercise", c.run.exercise_path, "Exercise file")->required();
  c.run_cmd->add_option("--out", c.run.out_dir, "Run directory to write")->capture_default_str();
  c.run_cmd->add_option("--script", c.run.script_path, "Operator script (default: the exercise's operator)");
  c.run_cmd->add_option("--lcm", c.run.lcm_url, "LCM provider (default: the exercise's, else udpm on this host, ttl 0)");
  c.run_cmd->add_option("--mode", c.run.mode, "fast, realtime or lockstep (default: fast with a script, realtime over LCM)");
  c.run_cmd->add_option("--session", c.run.session,
                        "A live session's name: its LCM channels are its own (SKIDSIM_STATE@NAME...), so sessions on one\n"
                        "host never cross; an operator attaches by it (default: the exercise's name and the process id)");
  // 0 is refused rather than read as "no limit": a session always ends.
  c.run_cmd->add_option("--max-s", c.run.max_s, "Stop after this much simulated time, 0.001 to 86400 s (default: the exercise's limit)")
      ->check(number_in(0.001, 86400.0));
  c.run_cmd->add_flag("--record", c.run.record,
                    "Render frames (the exercise's <record>: rate, camera, size) into RUN/frames on a second thread;\n"
                    "a video too (session.mp4) when ffmpeg is on the PATH");
  c.run_cmd->add_option("--camera", c.run.camera, "With --record: cab, chase, aerial or fixed (default: the exercise's)");
  add_frame_size(*c.run_cmd, "--frame-width", "--frame-height", c.run.frame_width, c.run.frame_height,
                 "With --record: pixels (default: the exercise's)");
  c.run_cmd->add_option("--fps", c.run.frame_fps, "With --record: frames a second, at most 25 (default: the exercise's)")->check(number_in(0.1, skidsim::io::kMaxRecordFps));
  c.run_cmd->add_option("--render-backend", c.run.render_backend, "With --record: auto, egl or osmesa")->capture_default_str();
  c.run_cmd->add_flag("--terrain-tiles", c.run.terrain_tiles,
                    "Also send the soil's surface over LCM and to the log (SKIDSIM_TERRAIN): every 32 x 32 tile\n"
                    "at the start, then those that changed, every 0.5 s and at the end");
  c.run_cmd->add_option("--replay", c.run.replay_path,
                      "Replay a session: the controls its session.lcmlog applied, tick by tick (the same final state)");
}

// What works on sessions: render, review, batch, operator.
void add_session_tools(CLI::App& app, Commands& c) {
  c.render_cmd = app.add_subcommand(
      "render", "Render one frame of an exercise off-screen (EGL, else OSMesa): its world at the start, or after\n"
                "its operator script has played for --at-s seconds; from one of its cameras; a PNG");
  c.render_cmd->add_option("exercise", c.render_job.exercise_path, "Exercise file")->required();
  c.render_cmd->add_option("--out", c.render_job.out_path, "PNG to write")->capture_default_str();
  c.render_cmd->add_option("--camera", c.render_job.camera, "cab, chase, aerial or fixed (default: the exercise's)");
  c.render_cmd->add_option("--backend", c.render_job.backend, "auto, egl or osmesa")->capture_default_str();
  add_frame_size(*c.render_cmd, "--width", "--height", c.render_job.width, c.render_job.height, "Pixels (default: the exercise's <record>)");
  c.render_cmd->add_option("--script", c.render_job.script_path, "Operator script to play first");
  c.render_cmd->add_option("--at-s", c.render_job.at_s, "Simulated seconds of the script to play first")->check(number_in(0.0, 86400.0));

  c.review_cmd = app.add_subcommand(
      "review", "Build a run directory's review page (review.html: frames under a scrubber in step with the\n"
                "timeline plots and events, the score term by term) and contact_sheet.png; with --camera or --fps,\n"
                "first render the session again by replaying its log (frames_<camera>_<fps>fps)");
  c.review_cmd->add_option("run_dir", c.review_job.run_dir, "Run directory (of skidsim run)")->required();
  c.review_cmd->add_option("--camera", c.review_job.camera, "Re-render from this camera: cab, chase, aerial or fixed");
  c.review_cmd->add_option("--fps", c.review_job.fps, "Re-render at this rate (frames a second, at most 25)")->check(number_in(0.1, skidsim::io::kMaxRecordFps));
  add_frame_size(*c.review_cmd, "--width", "--height", c.review_job.width, c.review_job.height, "Re-render size in pixels (default: the exercise's <record>)");
  c.review_cmd->add_option("--backend", c.review_job.backend, "Re-render with auto, egl or osmesa")->capture_default_str();
  c.review_cmd->add_option("--exercise", c.review_job.exercise_path, "The exercise file (default: the one report.json names)");

  c.view_cmd = app.add_subcommand(
      "view", "Draw a session from its scene stream without running the physics: frames from a camera at a\n"
              "rate, from a run directory's session.lcmlog, the pixels `run --record` draws (view_<camera>_<fps>fps),\n"
              "or live from a running session (--session NAME --exercise FILE)");
  c.view_cmd->add_option("source", c.view_job.source, "Run directory (of skidsim run), or a session.lcmlog with --exercise");
  c.view_cmd->add_option("--camera", c.view_job.camera, "cab, chase, aerial or fixed, or several separated by commas\n"
                                                        "(default: the exercise's)");
  c.view_cmd->add_option("--fps", c.view_job.fps, "Frames a second, at most 25 (default: the exercise's)")->check(number_in(0.1, skidsim::io::kMaxRecordFps));
  add_frame_size(*c.view_cmd, "--width", "--height", c.view_job.width, c.view_job.height, "Pixels (default: the exercise's <record>)");
  c.view_cmd->add_option("--backend", c.view_job.backend, "auto, egl or osmesa")->capture_default_str();
  c.view_cmd->add_option("--exercise", c.view_job.exercise_path, "The exercise file (default: the one report.json names)");
  c.view_cmd->add_option("--out", c.view_job.out_dir, "Where the frames go (default: RUN_DIR/view_<camera>_<fps>fps; live:\n"
                                                      "./view_<session>_<camera>_<fps>fps)");
  c.view_cmd->add_option("--session", c.view_job.session, "Draw this live session (skidsim run --session NAME) over LCM,\n"
                                                          "joining at any time, until it ends (needs --exercise)");
  c.view_cmd->add_option("--lcm", c.view_job.lcm_url, "Live: the LCM provider URL (default: this host's multicast)");
  c.view_cmd->add_option("--idle-s", c.view_job.idle_s, "Live: stop when no scene message came for this long (s)")->capture_default_str();
  c.view_cmd->add_flag("--every-frame", c.view_job.every_frame, "Live: draw every frame due even when behind (default: skip\n"
                                                                "to the latest)");

  c.station_cmd = app.add_subcommand(
      "station", "Serve a live session to browsers: its view from the trainee's camera and from above, its tasks,\n"
                 "events and score; the page holding the driver's token drives it with keys or a gamepad");
  c.station_cmd->add_option("--session", c.station_job.session, "The live session (skidsim run --session NAME)")->required();
  c.station_cmd->add_option("--exercise", c.station_job.exercise_path, "Its exercise file")->required();
  c.station_cmd->add_option("--lcm", c.station_job.lcm_url, "The LCM provider URL (default: this host's multicast)");
  c.station_cmd->add_option("--bind", c.station_job.bind, "The address to listen on (beyond this host: needs --token)")->capture_default_str();
  c.station_cmd->add_option("--port", c.station_job.port, "The HTTP port (0: any free one, printed)")->capture_default_str();
  c.station_cmd->add_option("--token", c.station_job.token, "A token every request must carry (?token=...)");
  c.station_cmd->add_option("--driver-token", c.station_job.driver_token, "The driver's token (default: drawn at random, printed)");
  c.station_cmd->add_option("--camera", c.station_job.camera, "The trainee's camera: cab, chase, aerial or fixed (default: the exercise's)");
  c.station_cmd->add_option("--fps", c.station_job.fps, "Frames a second, at most 25")->capture_default_str()->check(number_in(0.1, skidsim::io::kMaxRecordFps));
  c.station_cmd->add_option("--width", c.station_job.width, "Pixels")->capture_default_str()->check(number_in(16.0, 4096.0));
  c.station_cmd->add_option("--height", c.station_job.height, "Pixels")->capture_default_str()->check(number_in(16.0, 4096.0));
  c.station_cmd->add_option("--backend", c.station_job.backend, "auto, egl or osmesa")->capture_default_str();
  c.station_cmd->add_option("--linger-s", c.station_job.linger_s, "Serving on after the session ends (s)")->capture_default_str()->check(number_in(0.0, 3600.0));

  c.batch_cmd = app.add_subcommand(
      "batch", "Run many sessions at once, each `skidsim run` of a line of LIST (its arguments; each needs\n"
               "--script or --replay), at most --jobs at a time, each into OUT/NNN_exercise; then batch.json");
  c.batch_cmd->add_option("list", c.batch_job.list_path, "The list: one session's `skidsim run` arguments per line")->required();
  c.batch_cmd->add_option("--out", c.batch_job.out_dir, "Folder for the run directories and batch.json")->capture_default_str();
  c.batch_cmd->add_option("--jobs", c.batch_job.jobs, "Sessions at a time (default: the machine's cores)")->check(number_in(0.0, 256.0));
  c.batch_cmd->add_option("--index", c.batch_job.index, "Run only entry K (1-based): one task of a cluster's array job")->check(number_in(0.0, 1000000.0));

  c.operator_cmd = app.add_subcommand(
      "operator", "Play an operator script as a process of its own: listen to the simulator's state over LCM and\n"
                  "answer each with the command for that control tick");
  c.operator_cmd->add_option("script", c.operator_job.script_path, "Operator script")->required();
  c.operator_cmd->add_option("--lcm", c.operator_job.lcm_url, "LCM provider (default: udpm on this host, ttl 0)");
  c.operator_cmd->add_option("--session", c.operator_job.session, "The live session to drive (skidsim run --session, or the name it prints)")
      ->required();
  c.operator_cmd->add_option("--channel", c.operator_job.control_channel, "Control channel's base name (the exercise's <operator channel>)")
      ->capture_default_str();
  c.operator_cmd->add_option("--idle-s", c.operator_job.idle_timeout_s, "Stop when no state came for this long")
      ->capture_default_str()->check(number_in(0.01, 86400.0));
}

// bench (and bench report), check, soils.
void add_tool_commands(CLI::App& app, Commands& c) {
  c.bench_cmd = app.add_subcommand(
      "bench", "Run the benchmarks (Google Benchmark): a table by default, --json for machines");
  c.bench_cmd->add_flag("--json", c.bench_json, "Print JSON instead of a table");
  c.bench_cmd->add_option("--filter", c.bench_filter, "Regular expression selecting benchmarks");
  c.bench_cmd->add_option("--min-time", c.bench_min_time, "Minimum seconds per benchmark")->check(number_in(0.0, 3600.0));
  c.bench_cmd->add_option("--out", c.bench_out, "Also write the results as JSON to this file");
  c.report_cmd = c.bench_cmd->add_subcommand(
      "report", "Measure speed against error (ladders of cell sizes, error against each case's reference, cost per\n"
                "simulated second) and write docs/performance.md with its SVG plots");
  c.report_cmd->add_option("--out", c.report_job.out_path, "The page to write (the plots go beside it)")->capture_default_str();
  c.report_cmd->add_flag("--quick", c.report_job.quick, "Short ladders (for a quick look or a test)");

  c.check_cmd = app.add_subcommand(
      "check", "Validate a file without running it. An exercise: its site, tasks, events, scoring and the\n"
               "loader it names. A loader (parameter file, its URDF and meshes; the shipped one by default):\n"
               "what it implies: mass, static tipping load, rated capacity, cycle times, travel speed, push force");
  c.check_cmd->add_option("file", c.check_path, "An exercise or a loader parameter file");
  c.check_cmd->add_option("--loader", c.loader_path, "Loader parameter file (its <loader_parameters> names the URDF)")
      ->capture_default_str();
  c.check_cmd->add_flag("--json", c.check_json, "Print JSON");

  c.soils_cmd = app.add_subcommand("soils", "List the soils of the soil table");
  c.soils_cmd->add_option("--table", c.soil_table, "Soil table XML")->capture_default_str();
}

// A mistyped command is named (CLI11 alone says only that one is required).
bool known_command(CLI::App& app, const char* name) {
  std::string names;
  bool known = false;
  for (const CLI::App* sub : app.get_subcommands([](CLI::App*) { return true; })) {
    known = known || sub->check_name(name);
    names += (names.empty() ? "" : ", ") + sub->get_name();
  }
  if (!known) std::cerr << "skidsim: unknown command '" << name << "' (expected one of " << names << "; skidsim --help)\n";
  return known;
}

int run_command(const Commands& c) {
  if (*c.pour_cmd) return skidsim::jobs::run_pour_job(c.pour);
  if (*c.push_cmd) return skidsim::jobs::run_push_job(c.push);
  if (*c.dig_cmd) return skidsim::jobs::run_dig_job(c.dig);
  if (*c.run_cmd) return skidsim::apps::run_session(c.run);
  if (*c.operator_cmd) return skidsim::apps::run_operator(c.operator_job);
  if (*c.render_cmd) return skidsim::apps::render_frame(c.render_job);
  if (*c.review_cmd) return skidsim::apps::review_session(c.review_job);
  if (*c.view_cmd) return skidsim::apps::run_view(c.view_job);
  if (*c.station_cmd) return skidsim::station::run_station(c.station_job);
  if (*c.batch_cmd) return skidsim::apps::run_batch(c.batch_job);
  if (*c.report_cmd) return skidsim::report::write_perf_report(c.report_job);
  if (*c.bench_cmd) return run_bench(c.bench_json, c.bench_filter, c.bench_min_time, c.bench_out);
  if (*c.soils_cmd) return list_soils(c.soil_table);
  if (*c.check_cmd) return c.check_path.empty() ? check_loader(c.loader_path, c.check_json) : check_file(c.check_path, c.check_json);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "skidsim: a headless training simulator for a skid-steer loader working sand and soil.\n"
      "The granular terrain is a cellular automaton (docs/terrain_model.md)."};
  app.require_subcommand(1);
  Commands c;
  add_job_commands(app, c);
  add_session_command(app, c);
  add_session_tools(app, c);
  add_tool_commands(app, c);

  if (argc > 1 && argv[1][0] != '-' && !known_command(app, argv[1])) return 2;
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; anything else the command line got wrong
    // is bad input: 2, like every other bad input.
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    return run_command(c);
  } catch (const skidsim::jobs::Interrupted& e) {
    std::cerr << "skidsim: " << e.what() << "\n";
    return 128 + e.signal_number;
  } catch (const skidsim::io::InputError& e) {
    std::cerr << "skidsim: " << e.what() << "\n";
    return 2;
  } catch (const std::invalid_argument& e) {
    std::cerr << "skidsim: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "skidsim: error: " << e.what() << "\n";
    return 1;
  }
  return 0;
}
