#include "io/exercise.h"
#include "common/physical_constants.h"

#include <tinyxml2.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <set>
#include <sstream>

#include "io/input_file.h"
#include "io/loader_files.h"
#include "io/soil_table.h"
#include "io/xml_reader.h"

namespace skidsim::io {
namespace {

namespace fs = std::filesystem;

Region read_region(AttributeReader& a, const char* name) {
  const Eigen::VectorXd v = a.numbers_in(name, 4, -kMaxCoordinate_m, kMaxCoordinate_m);
  if (!(v[0] < v[2] && v[1] < v[3]))
    a.fail(std::string("attribute '") + name + "': expected \"x0 y0 x1 y1\" with x0 < x1 and y0 < y1");
  return Region(Eigen::Vector2d(v[0], v[1]), Eigen::Vector2d(v[2], v[3]));
}

Eigen::Vector2d read_point(AttributeReader& a, const char* name) {
  const Eigen::VectorXd v = a.numbers_in(name, 2, -kMaxCoordinate_m, kMaxCoordinate_m);
  return {v[0], v[1]};
}

// "x y; x y; ...": at least `least` points, finite.
std::vector<Eigen::Vector2d> read_points(AttributeReader& a, const char* name, std::size_t least) {
  const std::string text = a.text(name, true);
  std::vector<Eigen::Vector2d> points;
  std::size_t at = 0;
  while (at <= text.size()) {
    const std::size_t end = std::min(text.find(';', at), text.size());
    const std::string item = text.substr(at, end - at);
    at = end + 1;
    if (item.find_first_not_of(" \t\n\r") == std::string::npos) continue;
    const char* p = item.c_str();
    double x = 0.0, y = 0.0;
    const bool parsed = parse_decimal_number(p, x) && parse_decimal_number(p, y);
    if (!parsed || std::string(p).find_first_not_of(" \t\n\r") != std::string::npos ||
        !(std::abs(x) <= kMaxCoordinate_m) || !(std::abs(y) <= kMaxCoordinate_m))
      a.fail(std::string("attribute '") + name + "': \"" + item + "\" is not a point (expected \"x y; x y; ...\")");
    points.emplace_back(x, y);
    if (points.size() > 1000) a.fail(std::string("attribute '") + name + "': more than 1000 points");
  }
  if (points.size() < least) a.fail(std::string("attribute '") + name + "': expected at least " + std::to_string(least) + " points \"x y; x y; ...\"");
  return points;
}

// A file named in the exercise, resolved against its folder; it must exist.
std::string resolve_file(AttributeReader& a, const std::string& exercise_path, const char* name) {
  const std::string given = a.text(name, true);
  const fs::path p = fs::path(given).is_absolute() ? fs::path(given) : fs::path(exercise_path).parent_path() / given;
  try {
    check_input_file(p.string(), kMaxXmlBytes, "file");
  } catch (const InputError& e) {  // "no such file", "is a directory", ... named at this attribute
    a.fail(std::string("attribute '") + name + "' = \"" + given + "\": " + e.what());
  }
  return p.lexically_normal().string();
}

struct Reader {
  std::string path;
  Exercise ex;
  Region site;
  std::set<std::string> ids;  // zones, soils, trucks, boxes, tasks share one namespace

  void unique_id(AttributeReader& a, const std::string& id) {
    if (id.empty()) a.fail("attribute 'id' must not be empty");
    if (!ids.insert(id).second) a.fail("id '" + id + "' is used twice");
  }
  void on_site(AttributeReader& a, const Region& r, const char* what) {
    if (!site.contains(r)) {
      std::ostringstream m;
      m << what << " [" << r.min().transpose() << "] to [" << r.max().transpose() << "] is off the "
        << site.max().x() << " m x " << site.max().y() << " m site";
      a.fail(m.str());
    }
  }
  void on_site(AttributeReader& a, const Eigen::Vector2d& p, const char* what) { on_site(a, Region(p, p), what); }

  void read_soil(const tinyxml2::XMLElement* e, const SoilTable& table, const std::string& table_path) {
    AttributeReader a(path, e);
    SoilSite s;
    s.id = a.text("id", true);
    unique_id(a, s.id);
    s.region = read_region(a, "region");
    s.cell_m = a.number_in("cell_m", 0.01, 0.5);
    s.depth_m = a.number_in("depth_m", 0.0, 10.0);
    s.soil = a.text("type", true);
    if (a.has("model")) {
      const std::string model = a.text("model", true);
      if (model == "slippage") s.model = terrain::GroundModel::kSlippage;
      else if (model != "automaton")
        a.fail("attribute 'model' = \"" + model + "\": expected \"automaton\" or \"slippage\"");
    }
    if (a.has("fast_flow")) {
      const std::string fast = a.text("fast_flow", true);
      if (fast != "on" && fast != "off") a.fail("attribute 'fast_flow' = \"" + fast + "\": expected \"on\" or \"off\"");
      s.fast_flow = fast == "on";
    }
    a.reject_unknown();
    on_site(a, s.region, "the soil region");
    if (!table.count(s.soil)) a.fail("attribute 'type' = \"" + s.soil + "\": not a soil of " + table_path);
    const Eigen::Vector2d cells = s.region.sizes() / s.cell_m;
    if (cells.x() < 3.0 || cells.y() < 3.0) a.fail("the soil region must be at least 3 cells each way");
    if (cells.x() * cells.y() > 1.0e8) a.fail("the soil region has more than 1e8 cells: use larger cells");
    for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      AttributeReader b(path, c);
      const std::string name = c->Name();
      if (name == "pile") {
        SoilPile p;
        p.centre_m = read_point(b, "centre");
        p.radius_m = b.number_in("radius_m", 0.05, 100.0);
        p.height_m = b.number_in("height_m", 0.01, 20.0);
        b.reject_unknown();
        b.reject_content();
        if (!s.region.contains(p.centre_m)) b.fail("the pile's centre is outside its soil region");
        s.piles.push_back(p);
      } else if (name == "trench") {
        SoilTrench t;
        t.from_m = read_point(b, "from");
        t.to_m = read_point(b, "to");
        t.width_m = b.number_in("width_m", 0.05, 100.0);
        t.depth_m = b.number_in("depth_m", 0.01, 10.0);
        b.reject_unknown();
        b.reject_content();
        if (!s.region.contains(t.from_m) || !s.region.contains(t.to_m)) b.fail("the trench runs outside its soil region");
        if (t.depth_m > s.depth_m) b.fail("the trench is deeper than the soil layer (depth_m of <soil>)");
        s.trenches.push_back(t);
      } else if (name == "bank") {
        SoilBank k;
        k.region = read_region(b, "region");
        k.height_m = b.number_in("height_m", 0.01, 20.0);
        b.reject_unknown();
        b.reject_content();
        if (!s.region.contains(k.region)) b.fail("the bank is outside its soil region");
        s.banks.push_back(k);
      } else if (name == "slope") {
        SoilSlope k;
        k.region = read_region(b, "region");
        k.height_m = b.number_in("height_m", 0.01, 20.0);
        const std::string rising = b.text("rising", true);
        if (rising != "+x" && rising != "-x" && rising != "+y" && rising != "-y")
          b.fail("attribute 'rising' = \"" + rising + "\": expected +x, -x, +y or -y");
        k.rising_axis = rising[1] == 'x' ? 0 : 1;
        k.rising_up = rising[0] == '+';
        b.reject_unknown();
        b.reject_content();
        if (!s.region.contains(k.region)) b.fail("the slope is outside its soil region");
        s.slopes.push_back(k);
      } else {
        b.fail("unknown element (expected <pile>, <trench>, <bank> or <slope>)");
      }
    }
    ex.soils.push_back(s);
  }

  void read_site(const tinyxml2::XMLElement* e, const std::string& table_path) {
    AttributeReader a(path, e);
    const Eigen::VectorXd size = a.numbers_in("size_m", 2, -kMaxCoordinate_m, kMaxCoordinate_m);
    ex.firm_ground = a.boolean_or("firm_ground", true);
    a.reject_unknown();
    if (!(size[0] >= 1.0 && size[1] >= 1.0 && size[0] <= 2000.0 && size[1] <= 2000.0))
      a.fail("attribute 'size_m': each side in [1, 2000] m");
    ex.site_size_m = {size[0], size[1]};
    site = Region(Eigen::Vector2d::Zero(), ex.site_size_m);
    SoilTable table;
    bool table_read = false;
    for (const tinyxml2::XMLElement* c = e->FirstChildElement(); c; c = c->NextSiblingElement()) {
      const std::string name = c->Name();
      AttributeReader b(path, c);
      if (name == "soil") {
        if (!ex.soils.empty()) b.fail("this version builds one <soil> per exercise");
        if (!table_read) {
          table = load_soil_table(table_path);
          table_read = true;
        }
        read_soil(c, table, table_path);
      } else if (name == "zone") {
        Zone z;
        z.id = b.text("id", true);
        unique_id(b, z.id);
        z.region = read_region(b, "region");
        b.reject_unknown();
        b.reject_content();
        on_site(b, z.region, "the zone");
        ex.zones.push_back(z);
      } else if (name == "box") {
        BoxObstacle o;
        o.id = b.text("id", true);
        unique_id(b, o.id);
        o.centre_m = b.vector3_in("centre", -kMaxCoordinate_m, kMaxCoordinate_m);
        o.size_m = b.vector3_in("size", -kMaxCoordinate_m, kMaxCoordinate_m);
        o.yaw_deg = b.number_in_or("yaw_deg", -360.0, 360.0, 0.0);
        b.reject_unknown();
        b.reject_content();
        if (!(o.size_m.minCoeff() > 0.0 && o.size_m.maxCoeff() <= 100.0)) b.fail("attribute 'size': each side in (0, 100] m");
        on_site(b, footprint(o.centre_m.head<2>() - rotate(0.5 * o.size_m.head<2>(), o.yaw_deg), o.size_m.x(),
                             o.size_m.y(), o.yaw_deg),
                "the box");
        ex.boxes.push_back(o);
      } else if (name == "truck") {
        TruckBed t;
        t.id = b.text("id", true);
        unique_id(b, t.id);
        t.back_corner_m = read_point(b, "back_corner");
        t.yaw_deg = b.number_in_or("yaw_deg", -360.0, 360.0, 0.0);
        t.length_m = b.number_in("length_m", 0.5, 20.0);
        t.width_m = b.number_in("width_m", 0.5, 5.0);
        t.floor_height_m = b.number_in("floor_height_m", 0.0, 5.0);
        t.wall_height_m = b.number_in("wall_height_m", 0.05, 3.0);
        b.reject_unknown();
        b.reject_content();
        on_site(b, footprint(t.back_corner_m, t.length_m, t.width_m, t.yaw_deg), "the truck bed");
        ex.trucks.push_back(t);
      } else if (name == "agent") {
        read_agent(b, c);
      } else {
        b.fail("unknown element (expected <soil>, <zone>, <box>, <truck> or <agent>)");
      }
    }
    if (!ex.firm_ground && ex.soils.empty()) a.fail("a site without firm ground needs a <soil>");
  }

  void read_agent(AttributeReader& b, const tinyxml2::XMLElement* element) {
    if (ex.agents.size() >= 1000) b.fail("more than 1000 <agent>s");
    SiteAgent g;
    g.element = element;
    g.id = b.text("id", true);
    unique_id(b, g.id);
    const std::string kind = b.text("kind", true);
    if (kind == "person") {
      g.kind = SiteAgent::Kind::kPerson;
    } else if (kind == "truck") {
      g.kind = SiteAgent::Kind::kTruck;
    } else {
      b.fail("attribute 'kind' = \"" + kind + "\": expected person or truck");
    }
    const bool truck = g.kind == SiteAgent::Kind::kTruck;
    g.route_m = read_points(b, "route", 1);
    g.start_s = b.has("start_s") ? b.number_in("start_s", 0.0, 86400.0) : 0.0;
    g.start_after = b.text("start_after", false);  // checked once the tasks are read
    g.speed_m_s = b.has("speed_m_s") ? b.number_in("speed_m_s", 0.1, truck ? 10.0 : 3.0) : (truck ? 2.5 : 1.3);
    // People walk on the site; a truck may come from a road beyond it.
    const Region reach(site.min() - Eigen::Vector2d::Constant(truck ? 200.0 : 0.0), site.max() + Eigen::Vector2d::Constant(truck ? 200.0 : 0.0));
    for (const Eigen::Vector2d& p : g.route_m)
      if (!reach.contains(p)) b.fail("attribute 'route': the point " + std::to_string(p.x()) + " " + std::to_string(p.y()) + (truck ? " is more than 200 m off the site" : " is off the site"));
    if (truck) {
      g.bed = b.text("bed", true);
      const auto t = std::find_if(ex.trucks.begin(), ex.trucks.end(), [&](const TruckBed& x) { return x.id == g.bed; });
      if (t == ex.trucks.end()) b.fail("attribute 'bed' = \"" + g.bed + "\": no <truck> with that id before this <agent>");
      for (const SiteAgent& o : ex.agents)
        if (o.bed == g.bed) b.fail("attribute 'bed' = \"" + g.bed + "\": agent '" + o.id + "' already carries it");
      g.leave_at_kg = b.has("leave_at_kg") ? b.number_in("leave_at_kg", 0.0, 1e5) : 0.0;
      if (b.has("exit")) g.exit_m = read_points(b, "exit", 1);
      if (g.leave_at_kg > 0.0 && g.exit_m.empty()) b.fail("attribute 'leave_at_kg' needs an 'exit' to leave by");
      for (const Eigen::Vector2d& p : g.exit_m)
        if (!reach.contains(p)) b.fail("attribute 'exit': a point more than 200 m off the site");
    } else {
      g.loop = b.boolean_or("loop", false);
      g.pause_s = b.has("pause_s") ? b.number_in("pause_s", 0.0, 3600.0) : 0.0;
      g.keep_clear_m = b.has("keep_clear_m") ? b.number_in("keep_clear_m", 0.0, 50.0) : 6.0;
    }
    b.reject_unknown();
    b.reject_content();
    ex.agents.push_back(g);
  }

  // A length x width rectangle from `corner` along yaw: its bounds.
  static Eigen::Vector2d rotate(const Eigen::Vector2d& v, double yaw_deg) {
    return Eigen::Rotation2Dd(deg_to_rad(yaw_deg)) * v;
  }
  static Region footprint(const Eigen::Vector2d& corner, double length, double width, double yaw_deg) {
    Region r(corner, corner);
    for (const Eigen::Vector2d& c : {Eigen::Vector2d(length, 0), Eigen::Vector2d(0, width), Eigen::Vector2d(length, width)})
      r.extend(corner + rotate(c, yaw_deg));
    return r;
  }
  // The machine must start on the ground, not inside an obstacle or a bed.
  void check_start(AttributeReader& a) const {
    const Eigen::Vector2d p = ex.machine.position_m;
    if (!ex.firm_ground &&
        std::none_of(ex.soils.begin(), ex.soils.end(), [&](const SoilSite& s) { return s.region.contains(p); }))
      a.fail("the machine starts where there is neither firm ground nor soil");
    for (const BoxObstacle& o : ex.boxes)
      if (footprint(o.centre_m.head<2>() - rotate(0.5 * o.size_m.head<2>(), o.yaw_deg), o.size_m.x(), o.size_m.y(), o.yaw_deg)
              .exteriorDistance(p) < 1.0)
        a.fail("the machine starts within 1 m of box '" + o.id + "'");
    for (const TruckBed& t : ex.trucks)
      if (footprint(t.back_corner_m, t.length_m, t.width_m, t.yaw_deg).exteriorDistance(p) < 1.0)
        a.fail("the machine starts within 1 m of truck '" + t.id + "'");
  }

  bool is(const std::vector<Zone>& v, const std::string& id) const {
    return std::any_of(v.begin(), v.end(), [&](const Zone& z) { return z.id == id; });
  }

  void read_task(const tinyxml2::XMLElement* e) {
    AttributeReader a(path, e);
    Task t;
    t.line = e->GetLineNum();
    t.id = a.text("id", true);
    unique_id(a, t.id);
    const std::string type = a.text("type", true);
    t.time_limit_s = a.has("time_limit_s") ? a.number_in("time_limit_s", 1.0, 86400.0) : 0.0;
    const auto zone = [&](const char* attr) {
      const std::string id = a.text(attr, true);
      if (!is(ex.zones, id)) a.fail(std::string("attribute '") + attr + "' = \"" + id + "\": no <zone> with that id");
      return id;
    };
    if (type == "drive_course") {
      t.type = Task::Type::kDriveCourse;
      for (const tinyxml2::XMLElement* g = e->FirstChildElement(); g; g = g->NextSiblingElement()) {
        AttributeReader b(path, g);
        if (std::string(g->Name()) != "gate") b.fail("unknown element (expected <gate>)");
        const Region r = read_region(b, "region");
        b.reject_unknown();
        b.reject_content();
        on_site(b, r, "the gate");
        t.gates.push_back(r);
      }
      if (t.gates.empty()) a.fail("a drive_course needs at least one <gate region=\"x0 y0 x1 y1\"/>");
    } else if (type == "move_material" || type == "backfill") {
      t.type = type == "backfill" ? Task::Type::kBackfill : Task::Type::kMoveMaterial;
      t.from = a.text("from", true);
      if (!std::any_of(ex.soils.begin(), ex.soils.end(), [&](const SoilSite& s) { return s.id == t.from; }))
        a.fail("attribute 'from' = \"" + t.from + "\": no <soil> with that id");
      t.to = zone("to");
      t.mass_kg = a.number_in("mass_kg", 1.0, 1e7);
    } else if (type == "load_truck") {
      t.type = Task::Type::kLoadTruck;
      t.to = a.text("to", true);
      if (!std::any_of(ex.trucks.begin(), ex.trucks.end(), [&](const TruckBed& k) { return k.id == t.to; }))
        a.fail("attribute 'to' = \"" + t.to + "\": no <truck> with that id");
      t.mass_kg = a.number_in("mass_kg", 1.0, 1e7);
    } else if (type == "grade") {
      t.type = Task::Type::kGrade;
      t.to = zone("zone");
      t.height_m = a.number_in("height_m", -100.0, 100.0);
      t.tolerance_m = a.number_in("tolerance_m", 0.001, 1.0);
      t.coverage = a.has("coverage") ? a.number_in("coverage", 0.01, 1.0) : 0.9;
    } else if (type == "climb") {
      t.type = Task::Type::kClimb;
      t.to = zone("to");
    } else {
      a.fail("attribute 'type' = \"" + type +
             "\": expected drive_course, move_material, load_truck, grade, backfill or climb");
    }
    a.reject_unknown();
    if (t.type != Task::Type::kDriveCourse && e->FirstChildElement())
      fail_at(path, e->FirstChildElement(), "unknown element (only a drive_course has <gate>s)");
    ex.tasks.push_back(t);
  }

  void read_event(const tinyxml2::XMLElement* e) {
    AttributeReader a(path, e);
    Event v;
    const std::string when = a.text("when", true);
    v.message = a.text("message", true);
    if (when == "time") {
      v.when = Event::When::kAtTime;
      v.at_s = a.number_in("at_s", 0.0, 86400.0);
    } else if (when == "enter_zone") {
      v.when = Event::When::kEnterZone;
      v.subject = a.text("zone", true);
      if (!is(ex.zones, v.subject)) a.fail("attribute 'zone' = \"" + v.subject + "\": no <zone> with that id");
    } else if (when == "task_done") {
      v.when = Event::When::kTaskDone;
      v.subject = a.text("task", true);
      if (!std::any_of(ex.tasks.begin(), ex.tasks.end(), [&](const Task& t) { return t.id == v.subject; }))
        a.fail("attribute 'task' = \"" + v.subject + "\": no <task> with that id (tasks come before events)");
    } else {
      a.fail("attribute 'when' = \"" + when + "\": expected time, enter_zone or task_done");
    }
    a.reject_unknown();
    a.reject_content();
    ex.events.push_back(v);
  }
};

}  // namespace

const char* task_type_name(Task::Type type) {
  switch (type) {
    case Task::Type::kDriveCourse: return "drive_course";
    case Task::Type::kMoveMaterial: return "move_material";
    case Task::Type::kLoadTruck: return "load_truck";
    case Task::Type::kGrade: return "grade";
    case Task::Type::kBackfill: return "backfill";
    default: return "climb";
  }
}

const std::vector<std::string>& known_metrics() {
  static const std::vector<std::string> m = {
      "completion_time_s", "material_moved_kg", "material_rate_kg_h", "spillage_kg",      "bucket_fill_per_pass",
      "collisions",        "near_misses",       "tipping_margin_violations",            "bucket_impacts",
      "wheel_slip_time_s", "stall_time_s",      "idle_time_s",      "left_work_area_s", "engine_energy_MJ",
      "tasks_done",        "people_collisions", "truck_collisions", "min_distance_to_people_m",
      "speed_near_people_s"};
  return m;
}

Exercise load_exercise(const std::string& path, const std::string& soil_table_path) {
  tinyxml2::XMLDocument doc;
  load_xml(doc, path);
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "exercise") fail_at(path, root, "expected the root element <exercise>");
  Reader r;
  r.path = path;
  r.ex.path = path;
  const std::string table_path = soil_table_path.empty() ? default_soil_table_path() : soil_table_path;
  {
    AttributeReader a(path, root);
    r.ex.name = a.text("name", true);
    r.ex.version = static_cast<int>(a.number_in("version", 1, 1));
    r.ex.time_limit_s = a.number_in("time_limit_s", 1.0, 86400.0);
    a.reject_unknown();
  }
  bool have_site = false, have_machine = false, have_operator = false, have_scoring = false, have_record = false;
  for (const tinyxml2::XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string name = e->Name();
    AttributeReader a(path, e);
    const auto once = [&](bool& have) {
      if (have) a.fail("appears twice");
      have = true;
    };
    if (name == "site") {
      once(have_site);
      r.read_site(e, table_path);
    } else if (name == "machine") {
      once(have_machine);
      if (!have_site) a.fail("must come after <site>");
      MachineStart& m = r.ex.machine;
      m.loader = a.has("loader") ? resolve_file(a, path, "loader") : default_loader_path();
      m.position_m = read_point(a, "position");
      m.yaw_deg = a.number_in_or("yaw_deg", -360.0, 360.0, 0.0);
      m.lift_rad = a.has("lift_rad") ? a.number_in("lift_rad", 0.0, 1.7) : m.lift_rad;
      m.tilt_rad = a.has("tilt_rad") ? a.number_in("tilt_rad", -0.6, 2.4) : m.tilt_rad;
      a.reject_unknown();
      a.reject_content();
      r.on_site(a, m.position_m, "the machine's start");
      r.check_start(a);
    } else if (name == "operator") {
      once(have_operator);
      OperatorSource& o = r.ex.operator_source;
      const std::string source = a.text("source", true);
      if (source == "lcm") {
        o.kind = OperatorSource::Kind::kLcm;
        o.lcm_url = a.text("url", false);
        if (a.has("channel")) o.channel = a.text("channel", true);
        // A live session adds '@' and its name (within LCM's 63 bytes), and
        // LCM subscribes to a channel as a regular expression.
        if (o.channel.empty() || o.channel.size() > 30 || !channel_name_text(o.channel))
          a.fail("attribute 'channel' must be 1 to 30 of A-Z a-z 0-9 _ - (a live session adds '@' and its name)");
        o.watchdog_s = a.has("watchdog_ms") ? a.number_in("watchdog_ms", 10.0, 10000.0) / 1000.0 : o.watchdog_s;
      } else if (source == "script") {
        o.kind = OperatorSource::Kind::kScript;
        o.script = resolve_file(a, path, "script");
      } else {
        a.fail("attribute 'source' = \"" + source + "\": expected lcm or script");
      }
      a.reject_unknown();
      a.reject_content();
    } else if (name == "task") {
      if (!have_site) a.fail("must come after <site>");
      r.read_task(e);
    } else if (name == "event") {
      r.read_event(e);
    } else if (name == "scoring") {
      once(have_scoring);
      r.ex.scoring.pass_score = a.number_in_or("pass_score", -1e12, 1e12, 0.0);
      a.reject_unknown();
      std::set<std::string> seen;
      for (const tinyxml2::XMLElement* m = e->FirstChildElement(); m; m = m->NextSiblingElement()) {
        AttributeReader b(path, m);
        if (std::string(m->Name()) != "metric") b.fail("unknown element (expected <metric>)");
        Metric metric;
        metric.name = b.text("name", true);
        metric.weight = b.number_in("weight", -1e6, 1e6);
        b.reject_unknown();
        b.reject_content();
        const auto& known = known_metrics();
        if (std::find(known.begin(), known.end(), metric.name) == known.end()) {
          std::string list;
          for (const std::string& k : known) list += (list.empty() ? "" : ", ") + k;
          b.fail("attribute 'name' = \"" + metric.name + "\": expected one of " + list);
        }
        if (!seen.insert(metric.name).second) b.fail("metric '" + metric.name + "' is listed twice");
        r.ex.scoring.metrics.push_back(metric);
      }
    } else if (name == "record") {
      once(have_record);
      Recording& rec = r.ex.recording;
      rec.fps = a.number_in("fps", 0.1, kMaxRecordFps);  // frames come from the scene stream's messages
      rec.camera = a.text("camera", false);
      if (rec.camera.empty()) rec.camera = "chase";
      if (rec.camera != "cab" && rec.camera != "chase" && rec.camera != "aerial" && rec.camera != "fixed")
        a.fail("attribute 'camera' = \"" + rec.camera + "\": expected cab, chase, aerial or fixed");
      rec.width = static_cast<int>(a.has("width") ? a.number_in("width", kMinFramePixels, kMaxFramePixels) : rec.width);
      rec.height = static_cast<int>(a.has("height") ? a.number_in("height", kMinFramePixels, kMaxFramePixels) : rec.height);
      if (a.has("fixed_eye") != a.has("fixed_target")) a.fail("give both fixed_eye and fixed_target, or neither");
      if (a.has("fixed_eye")) {
        rec.fixed_eye_m = a.vector3_in("fixed_eye", -kMaxCoordinate_m, kMaxCoordinate_m);
        rec.fixed_target_m = a.vector3_in("fixed_target", -kMaxCoordinate_m, kMaxCoordinate_m);
        if ((rec.fixed_eye_m - rec.fixed_target_m).norm() < 0.1) a.fail("fixed_eye and fixed_target are the same point");
      }
      a.reject_unknown();
      a.reject_content();
    } else {
      a.fail("unknown element (expected <site>, <machine>, <operator>, <task>, <event>, <scoring> or <record>)");
    }
  }
  const auto need = [&](bool have, const char* what) {
    if (!have) fail_at(path, root, std::string("missing <") + what + ">");
  };
  need(have_site, "site");
  need(have_machine, "machine");
  need(have_operator, "operator");
  if (r.ex.tasks.empty()) fail_at(path, root, "an exercise needs at least one <task>");
  for (SiteAgent& g : r.ex.agents) {
    const auto* e = static_cast<const tinyxml2::XMLElement*>(g.element);
    g.element = nullptr;  // the document goes with this function
    if (!g.start_after.empty() &&
        std::none_of(r.ex.tasks.begin(), r.ex.tasks.end(), [&](const Task& t) { return t.id == g.start_after; }))
      fail_at(path, e, "attribute 'start_after' = \"" + g.start_after + "\": no <task> with that id");
  }
  return r.ex;
}

void check_frame_rate(double fps) {
  if (!(fps >= 0.1 && fps <= kMaxRecordFps)) throw InputError("--fps: expected 0.1 to 25 frames a second (the scene stream's rate)");
}

void check_frame_size(int width, int height, const std::string& options) {
  if (width < kMinFramePixels || height < kMinFramePixels || width > kMaxFramePixels || height > kMaxFramePixels)
    throw InputError(options + ": expected " + std::to_string(kMinFramePixels) + " to " + std::to_string(kMaxFramePixels) + " pixels");
}

}  // namespace skidsim::io
