// Operator scripts: what a scripted operator does, phase by
// phase. Levers held or ramped for a time, and closed-loop phases a trainer
// would name (drive to a point, lower the bucket, advance until full,
// raise, dump, reverse). Played by session/operator_player.h; reference in
// docs/exercises.md.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

namespace skidsim::io {

struct ScriptLevers {
  double drive_left = 0.0, drive_right = 0.0, lift = 0.0, tilt = 0.0, throttle = 1.0;
  bool parking_brake = false;
};

struct ScriptPhase {
  enum class Kind {
    kHold,              // these levers for duration_s
    kRamp,              // from the previous levers to these over duration_s
    kDriveTo,           // turn towards the point, drive to within tolerance_m
    kTurnTo,            // pivot to heading yaw_deg
    kLower,             // arm down, bucket floor level
    kAdvanceUntilFull,  // forward, bucket held (lowered and level), until full_kg, stalled, or max_m driven
    kRaise,             // arm to angle_rad, bucket rolled back
    kDump,              // tip to pitch_deg until nothing more comes out
    kReverse,           // back distance_m, bucket rolled back
    kWait,              // parking brake on for duration_s
  } kind = Kind::kHold;
  int line = 0;  // in the script file, for messages
  ScriptLevers levers;
  double duration_s = 0.0;
  Eigen::Vector2d target_m = Eigen::Vector2d::Zero();
  double tolerance_m = 0.3, speed = 0.5;
  double yaw_deg = 0.0;
  double full_kg = 500.0, max_m = 5.0;
  // advance_until_full: where the bucket cuts (the arm's angle and the
  // floor's pitch held, + rolled back; the defaults are the lowered bucket,
  // floor level: a cut at the ground) and how long the machine may stand
  // in the cut before the phase gives up as stalled.
  double cut_lift_rad = 0.03, cut_pitch_deg = 0.0, stall_s = 0.5;
  double angle_rad = 0.9;
  double pitch_deg = -57.0;
  double distance_m = 1.0;
  double time_limit_s = 30.0;  // a phase that has not reached its goal by then moves on (and is reported)
};

struct OperatorScript {
  std::string path, name;
  std::vector<ScriptPhase> phases;
};

const char* phase_kind_name(ScriptPhase::Kind kind);

// Reads and validates a script: io::InputError naming the file, line,
// element and what was expected.
OperatorScript load_operator_script(const std::string& path);

}  // namespace skidsim::io
