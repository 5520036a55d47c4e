#include "io/operator_script.h"

#include <tinyxml2.h>

#include "io/xml_reader.h"

namespace skidsim::io {

const char* phase_kind_name(ScriptPhase::Kind kind) {
  switch (kind) {
    case ScriptPhase::Kind::kHold: return "hold";
    case ScriptPhase::Kind::kRamp: return "ramp";
    case ScriptPhase::Kind::kDriveTo: return "drive_to";
    case ScriptPhase::Kind::kTurnTo: return "turn_to";
    case ScriptPhase::Kind::kLower: return "lower";
    case ScriptPhase::Kind::kAdvanceUntilFull: return "advance_until_full";
    case ScriptPhase::Kind::kRaise: return "raise";
    case ScriptPhase::Kind::kDump: return "dump";
    case ScriptPhase::Kind::kReverse: return "reverse";
    default: return "wait";
  }
}

namespace {

void read_levers(AttributeReader& a, ScriptLevers& l) {
  if (a.has("drive")) {
    const Eigen::VectorXd d = a.numbers_in("drive", 2, -kMaxCoordinate_m, kMaxCoordinate_m);
    l.drive_left = d[0];
    l.drive_right = d[1];
    if (!(std::abs(l.drive_left) <= 1.0 && std::abs(l.drive_right) <= 1.0))
      a.fail("attribute 'drive': two levers in [-1, 1] (left right)");
  }
  if (a.has("lift")) l.lift = a.number_in("lift", -1.0, 1.0);
  if (a.has("tilt")) l.tilt = a.number_in("tilt", -1.0, 1.0);
  if (a.has("throttle")) l.throttle = a.number_in("throttle", 0.0, 1.0);
  l.parking_brake = a.boolean_or("brake", l.parking_brake);
}

}  // namespace

OperatorScript load_operator_script(const std::string& path) {
  tinyxml2::XMLDocument doc;
  load_xml(doc, path);
  const tinyxml2::XMLElement* root = doc.RootElement();
  if (!root || std::string(root->Name()) != "operator_script")
    fail_at(path, root, "expected the root element <operator_script>");
  OperatorScript script;
  script.path = path;
  {
    AttributeReader a(path, root);
    script.name = a.text("name", true);
    a.reject_unknown();
  }
  for (const tinyxml2::XMLElement* e = root->FirstChildElement(); e; e = e->NextSiblingElement()) {
    AttributeReader a(path, e);
    const std::string name = e->Name();
    ScriptPhase p;
    p.line = e->GetLineNum();
    p.time_limit_s = a.has("time_limit_s") ? a.number_in("time_limit_s", 0.1, 3600.0) : p.time_limit_s;
    if (name == "hold" || name == "ramp") {
      p.kind = name == "hold" ? ScriptPhase::Kind::kHold : ScriptPhase::Kind::kRamp;
      p.duration_s = a.number_in("duration_s", 0.002, 3600.0);
      read_levers(a, p.levers);
    } else if (name == "drive_to") {
      p.kind = ScriptPhase::Kind::kDriveTo;
      const Eigen::VectorXd xy = a.numbers_in("to", 2, -kMaxCoordinate_m, kMaxCoordinate_m);
      p.target_m = {xy[0], xy[1]};
      if (a.has("tolerance_m")) p.tolerance_m = a.number_in("tolerance_m", 0.05, 10.0);
      if (a.has("speed")) p.speed = a.number_in("speed", 0.05, 1.0);
    } else if (name == "turn_to") {
      p.kind = ScriptPhase::Kind::kTurnTo;
      p.yaw_deg = a.number_in("yaw_deg", -360.0, 360.0);
    } else if (name == "lower") {
      p.kind = ScriptPhase::Kind::kLower;
    } else if (name == "advance_until_full") {
      p.kind = ScriptPhase::Kind::kAdvanceUntilFull;
      if (a.has("speed")) p.speed = a.number_in("speed", 0.05, 1.0);
      if (a.has("full_kg")) p.full_kg = a.number_in("full_kg", 1.0, 1e5);
      if (a.has("max_m")) p.max_m = a.number_in("max_m", 0.1, 100.0);
      // The arm's whole travel, and pitches from tipped well forward to
      // rolled back past the carry position.
      if (a.has("lift_rad")) p.cut_lift_rad = a.number_in("lift_rad", 0.0, 1.7);
      if (a.has("pitch_deg")) p.cut_pitch_deg = a.number_in("pitch_deg", -60.0, 30.0);
      if (a.has("stall_s")) p.stall_s = a.number_in("stall_s", 0.1, 3600.0);
    } else if (name == "raise") {
      p.kind = ScriptPhase::Kind::kRaise;
      p.angle_rad = a.number_in("angle_rad", 0.0, 1.7);
    } else if (name == "dump") {
      p.kind = ScriptPhase::Kind::kDump;
      if (a.has("pitch_deg")) p.pitch_deg = a.number_in("pitch_deg", -80.0, 0.0);
    } else if (name == "reverse") {
      p.kind = ScriptPhase::Kind::kReverse;
      p.distance_m = a.number_in("distance_m", 0.05, 100.0);
      if (a.has("speed")) p.speed = a.number_in("speed", 0.05, 1.0);
    } else if (name == "wait") {
      p.kind = ScriptPhase::Kind::kWait;
      p.duration_s = a.number_in("duration_s", 0.002, 3600.0);
    } else {
      a.fail(
          "unknown element (expected <hold>, <ramp>, <drive_to>, <turn_to>, <lower>, <advance_until_full>, "
          "<raise>, <dump>, <reverse> or <wait>)");
    }
    a.reject_unknown();
    a.reject_content();
    script.phases.push_back(p);
  }
  if (script.phases.empty()) fail_at(path, root, "a script needs at least one phase");
  return script;
}

}  // namespace skidsim::io
