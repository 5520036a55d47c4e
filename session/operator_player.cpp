#include "session/operator_player.h"
#include "common/physical_constants.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>

namespace skidsim::session {
namespace {

double wrap(double a) { return std::atan2(std::sin(a), std::cos(a)); }
double yaw_of(const skidsim_lcm::state_t& s) {
  const Eigen::Quaterniond q(s.chassis_orientation_wxyz[0], s.chassis_orientation_wxyz[1], s.chassis_orientation_wxyz[2],
                             s.chassis_orientation_wxyz[3]);
  const Eigen::Matrix3d r = q.toRotationMatrix();
  return std::atan2(r(1, 0), r(0, 0));
}
// The tilt lever that brings the bucket floor to `pitch_rad` (+ dumps).
double tilt_to(const skidsim_lcm::state_t& s, double pitch_rad, double max_lever = 1.0) {
  return std::clamp(6.0 * (s.bucket_pitch_rad - pitch_rad), -max_lever, max_lever);
}
double lift_to(const skidsim_lcm::state_t& s, double angle_rad) {
  return std::clamp(4.0 * (angle_rad - s.lift_angle_rad), -1.0, 1.0);
}
// Drive with the heading held on `heading_rad`: both levers `speed`, the
// difference steering.
void steer(vehicle::LoaderControls& c, double speed, double heading_error) {
  const double turn = std::clamp(1.5 * heading_error, -0.4, 0.4);
  c.drive_left = std::clamp(speed - turn, -1.0, 1.0);
  c.drive_right = std::clamp(speed + turn, -1.0, 1.0);
}

// A load worth easing the levers for (kg: more than a dump leaves behind,
// 2 % of a 550 kg fill) and the time over which an operator moves a drive
// lever its whole travel with one: thrown at once, the hydrostatic drive
// gives the machine about 3 m/s^2, which tips the heap's apparent gravity
// 17 deg (docs/material.md, "The load's apparent gravity").
constexpr double kLoadedKg = 50.0;
constexpr double kLoadedLeverTravelS = 4.0;

// A drive lever `in_phase_s` into a phase that starts from rest: `lever`,
// eased in with a load (a quarter of its travel a second).
double eased_in(double lever, double in_phase_s, double payload_kg) {
  return payload_kg > kLoadedKg ? std::min(lever, in_phase_s / kLoadedLeverTravelS) : lever;
}

}  // namespace

OperatorPlayer::OperatorPlayer(io::OperatorScript script) : script_(std::move(script)) {}

std::string OperatorPlayer::phase_name() const {
  return done() ? "done" : io::phase_kind_name(script_.phases[phase_].kind);
}

void OperatorPlayer::next(double time_s) {
  ++phase_;
  started_ = false;
  (void)time_s;
}

vehicle::LoaderControls OperatorPlayer::step(const skidsim_lcm::state_t& s) {
  vehicle::LoaderControls c;
  c.parking_brake = true;
  if (done()) return c;
  const io::ScriptPhase& p = script_.phases[phase_];
  const double t = s.sim_time_s;
  const Eigen::Vector2d xy(s.chassis_position_m[0], s.chassis_position_m[1]);
  if (!started_) {
    started_ = true;
    start_s_ = t;
    start_xy_ = xy;
    from_ = last_;
    start_payload_kg_ = check_payload_kg_ = s.bucket_payload_kg;
    check_s_ = t;
    slow_since_s_ = at_target_since_s_ = -1.0;
  }
  const double in_phase = t - start_s_;
  const double speed = std::hypot(s.chassis_velocity_m_s[0], s.chassis_velocity_m_s[1]);
  const double yaw = yaw_of(s);
  // The bucket while travelling: rolled back when loaded or raised.
  const double carry_pitch = (s.bucket_payload_kg > 1.0 || s.lift_angle_rad > 0.2) ? 0.3 : 0.0;
  bool goal = false;
  c.parking_brake = false;
  switch (p.kind) {
    case io::ScriptPhase::Kind::kHold:
    case io::ScriptPhase::Kind::kRamp: {
      const double f = p.kind == io::ScriptPhase::Kind::kRamp ? std::min(1.0, in_phase / p.duration_s) : 1.0;
      const auto mix = [f](double a, double b) { return a + f * (b - a); };
      c.drive_left = mix(from_.drive_left, p.levers.drive_left);
      c.drive_right = mix(from_.drive_right, p.levers.drive_right);
      c.lift = mix(from_.lift, p.levers.lift);
      c.tilt = mix(from_.tilt, p.levers.tilt);
      c.throttle = mix(from_.throttle, p.levers.throttle);
      c.parking_brake = p.levers.parking_brake;
      goal = in_phase >= p.duration_s;
      break;
    }
    case io::ScriptPhase::Kind::kDriveTo: {
      const Eigen::Vector2d to = p.target_m - xy;
      const double e = wrap(std::atan2(to.y(), to.x()) - yaw);
      if (std::abs(e) > 0.35) {
        steer(c, 0.0, e);  // pivot towards it first
      } else {
        // Slowing to a creep at the point: a loaded machine stopped hard from
        // speed pitches forward onto its bucket.
        steer(c, std::min(p.speed, 0.08 + 0.4 * to.norm()), e);
      }
      c.lift = lift_to(s, s.lift_angle_rad > 0.2 ? s.lift_angle_rad : 0.03);
      c.tilt = tilt_to(s, carry_pitch);
      goal = to.norm() < p.tolerance_m;
      break;
    }
    case io::ScriptPhase::Kind::kTurnTo: {
      const double e = wrap(deg_to_rad(p.yaw_deg) - yaw);
      steer(c, 0.0, e);
      c.tilt = tilt_to(s, carry_pitch);
      goal = std::abs(e) < 0.03 && std::abs(s.chassis_angular_velocity_rad_s[2]) < 0.05;
      break;
    }
    case io::ScriptPhase::Kind::kLower:
      c.lift = lift_to(s, 0.03);
      c.tilt = tilt_to(s, 0.0);
      goal = s.lift_angle_rad < 0.06 && std::abs(s.bucket_pitch_rad) < 0.03;
      break;
    case io::ScriptPhase::Kind::kAdvanceUntilFull: {
      steer(c, p.speed, 0.0);
      c.lift = lift_to(s, p.cut_lift_rad);
      c.tilt = tilt_to(s, deg_to_rad(p.cut_pitch_deg));
      if (in_phase > 1.5 && speed < 0.05) {
        if (slow_since_s_ < 0.0) slow_since_s_ = t;
      } else {
        slow_since_s_ = -1.0;
      }
      goal = s.bucket_payload_kg >= p.full_kg || (slow_since_s_ >= 0.0 && t - slow_since_s_ > p.stall_s) ||
             (xy - start_xy_).norm() > p.max_m;
      break;
    }
    case io::ScriptPhase::Kind::kRaise:
      c.lift = lift_to(s, p.angle_rad);
      c.tilt = tilt_to(s, 0.35);
      goal = std::abs(s.lift_angle_rad - p.angle_rad) < 0.03;
      break;
    case io::ScriptPhase::Kind::kDump: {
      const double target = deg_to_rad(p.pitch_deg);
      c.lift = lift_to(s, s.lift_angle_rad);
      c.tilt = tilt_to(s, target, 0.6);
      if (s.bucket_pitch_rad < target + 0.05) {
        if (at_target_since_s_ < 0.0) at_target_since_s_ = t;
      } else {
        at_target_since_s_ = -1.0;
      }
      if (t - check_s_ >= 0.5) {
        const bool stalled = at_target_since_s_ >= 0.0 && t - at_target_since_s_ > 1.5 &&
                             check_payload_kg_ - s.bucket_payload_kg < 0.01 * std::max(start_payload_kg_, 1.0);
        goal = s.bucket_payload_kg < 0.02 * std::max(start_payload_kg_, 1.0) || stalled;
        check_payload_kg_ = s.bucket_payload_kg;
        check_s_ = t;
      }
      break;
    }
    case io::ScriptPhase::Kind::kReverse:
      // With a load the levers go back gently: the machine pulled back at
      // once throws the heap forward over the lip.
      steer(c, -eased_in(p.speed, in_phase, s.bucket_payload_kg), 0.0);
      c.lift = lift_to(s, s.lift_angle_rad);
      c.tilt = tilt_to(s, 0.3);
      goal = (xy - start_xy_).norm() >= p.distance_m;
      break;
    case io::ScriptPhase::Kind::kWait:
      c.parking_brake = true;
      goal = in_phase >= p.duration_s;
      break;
  }
  last_ = {c.drive_left, c.drive_right, c.lift, c.tilt, c.throttle, c.parking_brake};
  // A timed phase runs its whole duration whatever its limit.
  const bool timed = p.kind == io::ScriptPhase::Kind::kHold || p.kind == io::ScriptPhase::Kind::kRamp ||
                     p.kind == io::ScriptPhase::Kind::kWait;
  const double limit = timed ? std::max(p.time_limit_s, p.duration_s + 1.0) : p.time_limit_s;
  if (!goal && in_phase > limit) {
    timed_out_.push_back("line " + std::to_string(p.line) + " " + io::phase_kind_name(p.kind));
    goal = true;
  }
  if (goal) next(t);
  return c;
}

}  // namespace skidsim::session
