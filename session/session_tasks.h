// A session's tasks, events and metrics at run time (docs/exercises.md,
// "Elements"; thesis 9.2.2, the exercise manager's evaluation): evaluated
// from the world once per control tick, never inside the 2 ms step.
#pragma once

#include <Eigen/Geometry>

#include <string>
#include <vector>

#include "session/session_safety.h"
#include "engine/world.h"
#include "io/exercise.h"

namespace skidsim::session {

struct TaskProgress {
  std::string id, type;
  bool done = false;
  double done_at_s = -1.0;
  double progress = 0.0;  // 0 to 1
  std::string detail;     // e.g. "612 of 1000 kg in 'target'"
};

struct SessionEvent {
  double time_s = 0.0;
  std::string kind, text;
  int severity = 0;
};

struct Metrics {
  double completion_time_s = 0.0;
  double material_moved_kg = 0.0;
  double tasks_done = 0.0;
  double tipping_margin_violations = 0.0;  // times the rear axle lost almost all its load for 0.25 s
  double idle_time_s = 0.0;
  double wheel_slip_time_s = 0.0;
  double stall_time_s = 0.0;           // pushing (drive or implement) with the bucket in the soil and getting nowhere
  double left_work_area_s = 0.0;
  double bucket_impacts = 0.0;         // times the bucket was stopped (or thrown) harder than kImpactMps2
  double peak_bucket_acceleration_m_s2 = 0.0;  // the hardest, over a 10 ms tick
  double collisions = 0.0;             // times the machine came into contact with an obstacle or truck
  double material_rate_kg_h = 0.0;     // material moved over the time taken
  double spillage_kg = 0.0;            // lost from the carried load away from the targets
  double bucket_fill_per_pass = 0.0;   // kg: the mean load carried per pass (a pass ends when the bucket is emptied)
  double engine_energy_MJ = 0.0;       // the engine's output, integrated per control tick
  SafetyMetrics safety;                // people and trucks on site
  int passes = 0;
  double value(const std::string& name) const;  // 0 for a metric not measured yet
  static bool measured(const std::string& name);
};

// Refuses (io::InputError naming the file, the task's line and id) a task
// that the world as built makes meaningless: one already done at the start,
// or one whose zone covers no cell of the soil it is measured on.
void check_tasks(const io::Exercise& exercise, const engine::World& world);

class SessionTasks {
 public:
  SessionTasks(const io::Exercise& exercise, const engine::World& world);
  // Once per control tick of `dt_s`, with the controls given at the tick
  // (the stall measure asks what the operator commanded).
  void update(const engine::World& world, double dt_s, const vehicle::LoaderControls& controls = {});
  bool all_done() const;
  const std::vector<TaskProgress>& tasks() const { return tasks_; }
  void add_event(double t, const std::string& kind, const std::string& text, int severity) {
    emit(t, kind, text, severity);
  }
  // The first task not done ("" when all are).
  std::string active_task() const;
  // Events since the last call (moved out).
  std::vector<SessionEvent> take_events();
  const std::vector<SessionEvent>& all_events() const { return log_; }
  const Metrics& metrics() const { return metrics_; }
  // Sum of weight x metric over the exercise's <scoring>; pass when every
  // task is done and the score reaches pass_score.
  double score() const;
  // The grid cells a zone covers: [i0, i1) x [j0, j1) (empty off the grid).
  Eigen::AlignedBox2i zone_cells(const engine::World& w, const io::Zone& zone) const;
  // At the session's end: counts a pass whose dump had begun.
  void finish(const engine::World& world);
  bool passed() const { return all_done() && score() >= exercise_.scoring.pass_score; }

 private:
  double zone_material_kg(const engine::World& w, const std::string& zone) const;

  void sample_bucket(const engine::World& w, double t);
  void end_pass(double t);
  double ground_height_m(const engine::World& w, const Eigen::Vector2d& xy) const;  // soil surface, else 0
  bool over_target(const Eigen::Vector2d& xy) const;  // over a move/backfill zone or a loaded truck's bed
  void emit(double t, const std::string& kind, const std::string& text, int severity = 0);
  double update_task_progress(const engine::World& w, double t, const Eigen::Vector2d& xy);
  void update_handling(const engine::World& w, double t, double dt_s);
  void update_stall(const engine::World& w, double t, double dt_s, const vehicle::LoaderControls& controls);
  bool bucket_in_soil(const engine::World& w) const;
  void fire_exercise_events(double t, const Eigen::Vector2d& xy);

  const io::Exercise& exercise_;
  std::vector<TaskProgress> tasks_;
  std::vector<double> baseline_kg_;     // per task: material in its target at the start
  std::vector<std::size_t> next_gate_;  // drive_course
  std::vector<bool> fired_;             // per exercise event
  std::vector<bool> was_in_zone_;       // per zone: the machine was in it at the last tick
  double rear_unloaded_s_ = 0.0;        // how long the rear axle has been all but unloaded
  double rear_loaded_s_ = 1e9;          // how long the rear axle has carried load again (tipping re-arm)
  std::vector<SessionEvent> pending_, log_;
  Metrics metrics_;
  bool tipping_ = false;
  double last_bucket_kg_ = 0.0, left_bucket_kg_ = 0.0;  // spillage: all that has left the bucket
  double pass_load_kg_ = 0.0, passes_kg_ = 0.0;  // this pass's carried load; all passes'
  double out_of_cut_s_ = 0.0;                      // how long the lip has been out of the cut
  bool done_ = false;
  double bucket_sample_s_ = 0.0, emptied_s_ = 0.0;
  bool touching_ = false;
  Eigen::Vector3d bucket_velocity_ = Eigen::Vector3d::Zero();
  bool have_bucket_velocity_ = false;
  double since_impact_s_ = 1e9;
  double apart_s_ = 1e9;  // how long the machine has been clear of obstacles (collision re-arm)
  double stuck_s_ = 0.0;  // how long the operator has been pushing and getting nowhere
  bool stalled_ = false;  // ... long enough to be a stall
  bool stall_armed_ = true;  // the next stall gets an event (re-armed once the machine has moved on)
  Eigen::Vector2d stall_at_m_ = Eigen::Vector2d::Zero();  // where the chassis stood when the last stall was found
  SafetyMonitor safety_;
};

}  // namespace skidsim::session
