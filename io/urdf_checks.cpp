#include "io/urdf_checks.h"

#include <console_bridge/console.h>
#include <tinyxml2.h>
#include <urdf_parser/urdf_parser.h>

#include <cmath>
#include <cstdlib>
#include <sstream>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_file.h"
#include "io/xml_reader.h"

namespace skidsim::io {
namespace {

// urdfdom reports through console_bridge; keep its errors for our message
// instead of letting it print. The first is the specific one ("Malformed
// axis element for joint [bucket_joint]..."), the last often a summary
// naming nothing ("joint xml is not initialized correctly").
class CapturedLog : public console_bridge::OutputHandler {
 public:
  void log(const std::string& text, console_bridge::LogLevel level, const char*, int) override {
    if (level >= console_bridge::CONSOLE_BRIDGE_LOG_ERROR) errors.push_back(text);
  }
  std::vector<std::string> errors;
};

// urdfdom's number grammar (urdf_model/utils.h strToDouble: a classic-locale
// stream that must reach the end of the text): an optional sign, digits
// with an optional point, an optional exponent. Hexadecimal, "inf", "nan"
// and anything after the number are not numbers to it (it reads them as
// 0), so they are not numbers here either.
bool parse_decimal(const std::string& token, double& value) {
  std::size_t k = 0;
  const std::size_t n = token.size();
  auto digits = [&] {
    const std::size_t from = k;
    while (k < n && token[k] >= '0' && token[k] <= '9') ++k;
    return k - from;
  };
  if (k < n && (token[k] == '+' || token[k] == '-')) ++k;
  std::size_t mantissa = digits();
  if (k < n && token[k] == '.') {
    ++k;
    mantissa += digits();
  }
  if (mantissa == 0) return false;
  if (k < n && (token[k] == 'e' || token[k] == 'E')) {
    ++k;
    if (k < n && (token[k] == '+' || token[k] == '-')) ++k;
    if (digits() == 0) return false;
  }
  if (k != n) return false;
  value = std::strtod(token.c_str(), nullptr);
  return std::isfinite(value);
}

// One link or joint being checked: where it is, for messages.
struct UrdfScope {
  const std::string& path;
  std::string owner;  // "link 'bucket'", "joint 'bucket_joint'", "material 'steel'"

  [[noreturn]] void fail(const tinyxml2::XMLElement* e, const std::string& elements, const std::string& what) const {
    std::ostringstream msg;
    msg << path << ":" << e->GetLineNum() << ": " << owner << " " << elements << ": " << what;
    throw InputError(msg.str());
  }

  // `count` numbers separated by spaces (urdfdom splits on ' ' only), each
  // in [lo, hi]; nothing when the attribute is absent (urdfdom's default or
  // its own complaint applies). `rule`, if given, says what the range means.
  void numbers(const tinyxml2::XMLElement* e, const std::string& elements, const char* name, int count, double lo,
               double hi, const char* unit, const char* rule = nullptr) const {
    const char* text = e->Attribute(name);
    if (!text) return;
    std::vector<std::string> tokens;
    std::string token;
    if (count == 1) {
      // A single number is read whole: leading blanks are skipped, but
      // anything after it ("450 ") leaves urdfdom's stream short of its end.
      const char* p = text;
      while (*p == ' ' || *p == '\t' || *p == '\n' || *p == '\r') ++p;
      tokens.push_back(p);
    }
    for (const char* p = text; count > 1; ++p) {
      if (*p == ' ' || *p == '\0') {
        if (!token.empty()) tokens.push_back(token);
        token.clear();
        if (*p == '\0') break;
      } else {
        token += *p;
      }
    }
    const std::string quoted = std::string("attribute '") + name + "' = \"" + text + "\"";
    if (static_cast<int>(tokens.size()) != count)
      fail(e, elements, quoted + ": expected " + (count == 1 ? std::string("a number") : std::to_string(count) +
                                                   " numbers separated by spaces"));
    for (const std::string& t : tokens) {
      double v = 0.0;
      if (!parse_decimal(t, v))
        fail(e, elements, quoted + ": \"" + t + "\" is not a finite decimal number" +
                              (count == 1 ? " (urdfdom would read it as 0)" : ""));
      if (!(v >= lo && v <= hi)) {
        std::ostringstream msg;
        msg << quoted << ": " << v << " is out of range [" << lo << ", " << hi << "] " << unit;
        if (rule) msg << " (" << rule << ")";
        fail(e, elements, msg.str());
      }
    }
  }

  void origin(const tinyxml2::XMLElement* parent, const std::string& elements) const {
    for (const tinyxml2::XMLElement* o = parent->FirstChildElement("origin"); o; o = o->NextSiblingElement("origin")) {
      numbers(o, elements + "<origin>", "xyz", 3, -kMaxUrdfExtent_m, kMaxUrdfExtent_m, "m");
      numbers(o, elements + "<origin>", "rpy", 3, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
    }
  }

  void material(const tinyxml2::XMLElement* m, const std::string& elements) const {
    for (const tinyxml2::XMLElement* c = m->FirstChildElement("color"); c; c = c->NextSiblingElement("color"))
      numbers(c, elements + "<color>", "rgba", 4, 0.0, 1.0, "");
  }

  // <visual> or <collision>: its origin and its geometry's sizes.
  void shape(const tinyxml2::XMLElement* v, const std::string& elements) const {
    origin(v, elements);
    for (const tinyxml2::XMLElement* g = v->FirstChildElement("geometry"); g; g = g->NextSiblingElement("geometry"))
      for (const tinyxml2::XMLElement* s = g->FirstChildElement(); s; s = s->NextSiblingElement()) {
        const std::string kind = s->Name();
        const std::string at = elements + "<geometry><" + kind + ">";
        if (kind == "box") numbers(s, at, "size", 3, kMinUrdfSize_m, kMaxUrdfExtent_m, "m");
        if (kind == "cylinder" || kind == "capsule") {
          numbers(s, at, "radius", 1, kMinUrdfSize_m, kMaxUrdfExtent_m, "m");
          numbers(s, at, "length", 1, kMinUrdfSize_m, kMaxUrdfExtent_m, "m");
        }
        if (kind == "sphere") numbers(s, at, "radius", 1, kMinUrdfSize_m, kMaxUrdfExtent_m, "m");
        if (kind == "mesh") numbers(s, at, "scale", 3, kMinUrdfMeshScale, kMaxUrdfMeshScale, "");
      }
    for (const tinyxml2::XMLElement* m = v->FirstChildElement("material"); m; m = m->NextSiblingElement("material"))
      material(m, elements + "<material>");
  }

  void link(const tinyxml2::XMLElement* l) const {
    for (const tinyxml2::XMLElement* in = l->FirstChildElement("inertial"); in; in = in->NextSiblingElement("inertial")) {
      origin(in, "<inertial>");
      for (const tinyxml2::XMLElement* m = in->FirstChildElement("mass"); m; m = m->NextSiblingElement("mass"))
        numbers(m, "<inertial><mass>", "value", 1, 0.0, kMaxUrdfMass_kg, "kg",
                "a mass must be positive, 0 only on a massless wheel");
      for (const tinyxml2::XMLElement* i = in->FirstChildElement("inertia"); i; i = i->NextSiblingElement("inertia"))
        for (const char* name : {"ixx", "ixy", "ixz", "iyy", "iyz", "izz"})
          numbers(i, "<inertial><inertia>", name, 1, -kMaxUrdfInertia_kg_m2, kMaxUrdfInertia_kg_m2, "kg m^2");
    }
    for (const tinyxml2::XMLElement* v = l->FirstChildElement("visual"); v; v = v->NextSiblingElement("visual"))
      shape(v, "<visual>");
    for (const tinyxml2::XMLElement* c = l->FirstChildElement("collision"); c; c = c->NextSiblingElement("collision"))
      shape(c, "<collision>");
  }

  void joint(const tinyxml2::XMLElement* j) const {
    origin(j, "");
    auto each = [&](const char* child, auto check) {
      for (const tinyxml2::XMLElement* c = j->FirstChildElement(child); c; c = c->NextSiblingElement(child))
        check(c, std::string("<") + child + ">");
    };
    each("axis", [&](const tinyxml2::XMLElement* c, const std::string& at) { numbers(c, at, "xyz", 3, -1.0, 1.0, ""); });
    // Angles for revolute joints; a prismatic joint's metres fit the same bound.
    each("limit", [&](const tinyxml2::XMLElement* c, const std::string& at) {
      numbers(c, at, "lower", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
      numbers(c, at, "upper", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
      numbers(c, at, "effort", 1, 0.0, kMaxUrdfEffort, "N m");
      numbers(c, at, "velocity", 1, 0.0, kMaxUrdfVelocity, "rad/s");
    });
    each("dynamics", [&](const tinyxml2::XMLElement* c, const std::string& at) {
      numbers(c, at, "damping", 1, 0.0, kMaxUrdfEffort, "N m s/rad");
      numbers(c, at, "friction", 1, 0.0, kMaxUrdfEffort, "N m");
    });
    each("safety_controller", [&](const tinyxml2::XMLElement* c, const std::string& at) {
      numbers(c, at, "soft_lower_limit", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
      numbers(c, at, "soft_upper_limit", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
      numbers(c, at, "k_position", 1, 0.0, kMaxUrdfEffort, "");
      numbers(c, at, "k_velocity", 1, 0.0, kMaxUrdfEffort, "");
    });
    each("calibration", [&](const tinyxml2::XMLElement* c, const std::string& at) {
      numbers(c, at, "rising", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
      numbers(c, at, "falling", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
    });
    each("mimic", [&](const tinyxml2::XMLElement* c, const std::string& at) {
      numbers(c, at, "multiplier", 1, -1.0e3, 1.0e3, "");
      numbers(c, at, "offset", 1, -kMaxUrdfAngle_rad, kMaxUrdfAngle_rad, "rad");
    });
  }
};

}  // namespace

UrdfLines check_urdf_text(const std::string& path, const std::string& text) {
  tinyxml2::XMLDocument doc;
  parse_xml(doc, path, text);
  UrdfLines lines;
  const tinyxml2::XMLElement* robot = doc.RootElement();
  if (!robot || std::string(robot->Name()) != "robot") fail_at(path, robot, "expected the root element <robot>");
  for (const tinyxml2::XMLElement* e = robot->FirstChildElement(); e; e = e->NextSiblingElement()) {
    const std::string kind = e->Name();
    const char* name = e->Attribute("name");
    const std::string owner = kind + " '" + (name ? name : "") + "'";
    if (kind == "link") {
      if (name) lines.link[name] = e->GetLineNum();
      UrdfScope{path, owner}.link(e);
    } else if (kind == "joint") {
      if (name) lines.joint[name] = e->GetLineNum();
      UrdfScope{path, owner}.joint(e);
    } else if (kind == "material") {
      UrdfScope{path, owner}.material(e, "");
    }
  }
  return lines;
}

CheckedUrdf read_checked_urdf(const std::string& path) {
  const std::string text = read_input_file(path, kMaxXmlBytes, "URDF");
  CheckedUrdf out;
  out.lines = check_urdf_text(path, text);
  const UrdfLines& lines = out.lines;
  CapturedLog log;
  console_bridge::useOutputHandler(&log);
  const urdf::ModelInterfaceSharedPtr model = urdf::parseURDF(text);
  console_bridge::restorePreviousOutputHandler();
  if (!model) {
    // urdfdom names the link or joint ("[name]" or "'name'"), not the line:
    // find the line of the first element its messages name.
    int line = 0;
    std::string what;
    for (const std::string& error : log.errors) {
      what += (what.empty() ? "" : "; ") + error;
      size_t best = std::string::npos;
      int error_line = 0;
      for (const auto* index : {&lines.joint, &lines.link})
        for (const auto& [name, l] : *index)
          for (const std::string& quoted : {"[" + name + "]", "'" + name + "'"}) {
            const size_t at = error.find(quoted);
            if (at != std::string::npos && (best == std::string::npos || at < best)) {
              best = at;
              error_line = l;
            }
          }
      if (line == 0) line = error_line;
    }
    throw InputError(path + ":" + std::to_string(line) + ": not a valid URDF: " +
                     (what.empty() ? std::string("parse failed") : what));
  }
  out.model = model;
  return out;
}

}  // namespace skidsim::io
