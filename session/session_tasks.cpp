#include "session/session_tasks.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "io/atomic_file.h"

namespace skidsim::session {
namespace {

const io::Zone* find_zone(const io::Exercise& ex, const std::string& id) {
  for (const io::Zone& z : ex.zones)
    if (z.id == id) return &z;
  return nullptr;
}

constexpr double kTippingHoldS = 0.25;
constexpr double kTippingRearmS = 0.5;
constexpr double kTippingRearShare = 0.05;       // the rear axle "all but unloaded": under 5 % of the tyres' load
constexpr double kTippingRearmRearShare = 0.1;   // ... and carrying again: over 10 %
constexpr double kSampleS = 0.2;   // the bucket's load is looked at this often
constexpr double kSettleS = 2.0;   // after leaving the cut, before its load counts as carried
constexpr double kImpactMps2 = 40.0;  // about 4 g; the shipped scripts peak at 8-31
constexpr double kEventRearmS = 0.5;    // one impact, or one lasting contact, counts once within this
constexpr double kSettlingS = 1.0;      // the machine settling onto its wheels: no impacts counted
constexpr double kIdleSpeedMps = 0.05;  // slower than this the machine idles
constexpr double kSlipLimit = 0.3;      // a wheel slipping more than this spins
constexpr double kOutOfCutM = 0.3;      // the lip this far above the ground has left the cut
constexpr double kPassMinKg = 50.0;     // a load smaller than this is no pass
constexpr double kPassEndShare = 0.9;   // a pass ends when the bucket holds less than this share of it
constexpr double kEmptiedS = 0.4;       // ... or has been empty this long
// Stalls: the operator pushes (drive levers forward, or lift / tilt levers
// asking the arm or bucket to move) with the bucket in the soil, and the
// machine gets nowhere (the chassis under kIdleSpeedMps, or a wheel slipping
// past kSlipLimit; the commanded joints not turning).
constexpr double kStallDriveLever = 0.1;  // the drive levers' mean past this pushes forward (a creep onto a
                                          // target point, 0.08 in the scripts, does not)
constexpr double kStallImplementLever = 0.5;  // a lift or tilt lever past half way asks the joint to move; the
                                              // scripts' closed loops holding the arm or bucket stay under it
constexpr double kStallJointRadS = 0.02;  // a joint turning slower than this is held: free, the arm and bucket
                                          // turn at 0.4-0.9 rad/s at full lever (skidsim check's times)
constexpr double kStallOnsetS = 1.0;  // held up this long, the machine is stalled (and the whole time counts):
                                      // a lever's ramp or the check as the edge bites is not a stall, nor
                                      // the scripts' own 0.5 s at a standstill before they give up a cut
constexpr double kStallRearmM = 0.3;  // the next stall is a new one once the chassis has moved this far from
                                      // where the last was found (backed out of the cut, or broken through)
constexpr double kInSoilAheadM = 0.1;  // the soil the edge is about to meet: this far ahead of the lip
constexpr double kInSoilM = 0.02;      // the soil over the lip by more than this: the bucket is in it (a lip
                                       // riding on the surface is not)

// The middle of the bucket's front edge (its container's lip).
Eigen::Vector3d lip_of(const terrain::BodyAutomaton& b) {
  return b.pose() * Eigen::Vector3d(b.shape().length_m, 0.5 * b.shape().width_m, 0.0);
}

// The largest slip ratio of the machine's wheels.
double worst_slip_of(const vehicle::Loader& l) {
  double worst = 0.0;
  for (const vehicle::WheelState& wheel : l.wheels()) worst = std::max(worst, std::abs(wheel.slip_ratio));
  return worst;
}

}  // namespace

void check_tasks(const io::Exercise& ex, const engine::World& world) {
  SessionTasks tasks(ex, world);
  const auto where = [&](const io::Task& t) {
    return ex.path + ":" + std::to_string(t.line) + ": <task id=\"" + t.id + "\"> ";
  };
  for (std::size_t k = 0; k < ex.tasks.size(); ++k) {
    const io::Task& t = ex.tasks[k];
    const bool on_soil = t.type == io::Task::Type::kGrade || t.type == io::Task::Type::kMoveMaterial ||
                         t.type == io::Task::Type::kBackfill;
    if (on_soil) {
      const io::Zone* z = find_zone(ex, t.to);
      const Eigen::AlignedBox2i c = z ? tasks.zone_cells(world, *z) : Eigen::AlignedBox2i();
      if (!world.terrain() || !z || (c.max() - c.min()).minCoeff() < 1)
        throw io::InputError(where(t) + "its zone '" + t.to + "' covers no cell of a <soil>: it could never be done");
    }
  }
  tasks.update(world, 0.01);
  for (std::size_t k = 0; k < ex.tasks.size(); ++k)
    if (tasks.tasks()[k].done)
      throw io::InputError(where(ex.tasks[k]) + "is already done at the start (" + tasks.tasks()[k].detail + ")");
}

bool Metrics::measured(const std::string& name) {
  static const char* const kMeasured[] = {"completion_time_s", "material_moved_kg", "tasks_done",
                                          "tipping_margin_violations", "idle_time_s", "wheel_slip_time_s",
                                          "stall_time_s",
                                          "left_work_area_s", "material_rate_kg_h", "spillage_kg",
                                          "bucket_fill_per_pass", "engine_energy_MJ", "collisions",
                                          "bucket_impacts", "people_collisions", "truck_collisions", "near_misses",
                                          "min_distance_to_people_m", "speed_near_people_s"};
  for (const char* m : kMeasured)
    if (name == m) return true;
  return false;
}

double Metrics::value(const std::string& name) const {
  if (name == "completion_time_s") return completion_time_s;
  if (name == "material_moved_kg") return material_moved_kg;
  if (name == "tasks_done") return tasks_done;
  if (name == "tipping_margin_violations") return tipping_margin_violations;
  if (name == "idle_time_s") return idle_time_s;
  if (name == "wheel_slip_time_s") return wheel_slip_time_s;
  if (name == "stall_time_s") return stall_time_s;
  if (name == "left_work_area_s") return left_work_area_s;
  if (name == "material_rate_kg_h") return material_rate_kg_h;
  if (name == "spillage_kg") return spillage_kg;
  if (name == "bucket_fill_per_pass") return bucket_fill_per_pass;
  if (name == "engine_energy_MJ") return engine_energy_MJ;
  if (name == "collisions") return collisions + safety.people_collisions + safety.truck_collisions;  // objects, trucks, people
  if (name == "bucket_impacts") return bucket_impacts;
  if (name == "people_collisions") return safety.people_collisions;
  if (name == "truck_collisions") return safety.truck_collisions;
  if (name == "near_misses") return safety.near_misses;
  if (name == "min_distance_to_people_m") return safety.min_distance_to_people_m;
  if (name == "speed_near_people_s") return safety.speed_near_people_s;
  return 0.0;
}

SessionTasks::SessionTasks(const io::Exercise& exercise, const engine::World& world) : exercise_(exercise) {
  for (const io::Task& t : exercise.tasks) {
    TaskProgress p;
    p.id = t.id;
    p.type = io::task_type_name(t.type);
    tasks_.push_back(p);
    double baseline = 0.0;
    if (t.type == io::Task::Type::kMoveMaterial || t.type == io::Task::Type::kBackfill)
      baseline = zone_material_kg(world, t.to);
    baseline_kg_.push_back(baseline);
    next_gate_.push_back(0);
  }
  fired_.assign(exercise.events.size(), false);
  last_bucket_kg_ = world.bucket_material() ? world.bucket_material()->material_mass_kg() : 0.0;
  const Eigen::Vector2d start = world.loader().link_pose(0).translation().head<2>();
  for (const io::Zone& z : exercise.zones) was_in_zone_.push_back(z.region.contains(start));
}

Eigen::AlignedBox2i SessionTasks::zone_cells(const engine::World& w, const io::Zone& z) const {
  const terrain::GranularGrid* g = w.terrain();
  Eigen::AlignedBox2i cells(Eigen::Vector2i(0, 0), Eigen::Vector2i(0, 0));
  if (!g) return cells;
  // Cells whose centres lie in the zone.
  const Eigen::Vector2d lo = (z.region.min() - g->spec().origin_m) / g->cell_size_m();
  const Eigen::Vector2d hi = (z.region.max() - g->spec().origin_m) / g->cell_size_m();
  const auto clampi = [](double v, int n) { return static_cast<int>(std::clamp(v, 0.0, static_cast<double>(n))); };
  cells.min() = Eigen::Vector2i(clampi(std::ceil(lo.x()), g->nx()), clampi(std::ceil(lo.y()), g->ny()));
  cells.max() = Eigen::Vector2i(clampi(std::floor(hi.x()) + 1, g->nx()), clampi(std::floor(hi.y()) + 1, g->ny()));
  return cells;
}

double SessionTasks::zone_material_kg(const engine::World& w, const std::string& id) const {
  const io::Zone* z = find_zone(exercise_, id);
  const terrain::GranularGrid* g = w.terrain();
  if (!z || !g) return 0.0;
  const Eigen::AlignedBox2i c = zone_cells(w, *z);
  double kg = 0.0;
  for (int j = c.min().y(); j < c.max().y(); ++j)
    for (int i = c.min().x(); i < c.max().x(); ++i) kg += g->material_mass_kg(i, j);
  return kg;
}

void SessionTasks::sample_bucket(const engine::World& w, double t) {
  const vehicle::Loader& l = w.loader();
  const double bucket_kg = w.bucket_material() ? w.bucket_material()->material_mass_kg() : 0.0;
  // Material leaves over the lip: the middle of the container's front edge.
  Eigen::Vector3d lip_m = l.link_pose(static_cast<int>(l.description().links.size()) - 1).translation();
  if (const terrain::BodyAutomaton* b = w.bucket_material()) lip_m = lip_of(*b);
  const bool out_of_cut = lip_m.z() - ground_height_m(w, lip_m.head<2>()) > kOutOfCutM;
  const double lost = std::max(0.0, last_bucket_kg_ - bucket_kg);
  last_bucket_kg_ = bucket_kg;
  out_of_cut_s_ = out_of_cut ? out_of_cut_s_ + kSampleS : 0.0;
  if (out_of_cut_s_ < kSettleS - 1e-9) return;  // in the cut, or lifting out of it
  if (pass_load_kg_ == 0.0 || out_of_cut_s_ < kSettleS + 0.5 * kSampleS) {
    // Just settled: this is what the pass carries.
    if (bucket_kg >= kPassMinKg && (pass_load_kg_ == 0.0 || bucket_kg > pass_load_kg_)) pass_load_kg_ = bucket_kg;
    return;
  }
  if (lost > 0.0 && !over_target(lip_m.head<2>())) metrics_.spillage_kg += lost;
  emptied_s_ = bucket_kg < pass_load_kg_ / 3.0 ? emptied_s_ + kSampleS : 0.0;
  if (emptied_s_ >= kEmptiedS - 1e-9) end_pass(t);
}

void SessionTasks::end_pass(double t) {
  ++metrics_.passes;
  passes_kg_ += pass_load_kg_;
  metrics_.bucket_fill_per_pass = passes_kg_ / metrics_.passes;
  emit(t, "pass", "pass " + std::to_string(metrics_.passes) + ": " + std::to_string(std::lround(pass_load_kg_)) +
                      " kg carried");
  pass_load_kg_ = 0.0;
  emptied_s_ = 0.0;
}

void SessionTasks::finish(const engine::World& w) {
  // A pass whose dump had begun when the session ended (its task done
  // mid-dump) counts.
  const double bucket_kg = w.bucket_material() ? w.bucket_material()->material_mass_kg() : 0.0;
  if (pass_load_kg_ >= kPassMinKg && bucket_kg < kPassEndShare * pass_load_kg_) end_pass(w.time_s());
}

double SessionTasks::ground_height_m(const engine::World& w, const Eigen::Vector2d& xy) const {
  const terrain::GranularGrid* g = w.terrain();
  if (!g) return 0.0;
  const Eigen::Vector2d ij = (xy - g->spec().origin_m) / g->cell_size_m();
  const int i = static_cast<int>(std::lround(ij.x())), j = static_cast<int>(std::lround(ij.y()));
  return g->contains(i, j) ? g->surface_m(i, j) : 0.0;
}

bool SessionTasks::over_target(const Eigen::Vector2d& xy) const {
  for (const io::Task& t : exercise_.tasks) {
    if (t.type == io::Task::Type::kMoveMaterial || t.type == io::Task::Type::kBackfill) {
      const io::Zone* z = find_zone(exercise_, t.to);
      if (z && z->region.contains(xy)) return true;
    }
    if (t.type == io::Task::Type::kLoadTruck)
      for (const io::TruckBed& b : exercise_.trucks) {
        if (b.id != t.to) continue;
        // The bed's floor in its own frame: x along its length, y across.
        const double yaw = deg_to_rad(b.yaw_deg);
        const Eigen::Vector2d d = xy - b.back_corner_m;
        const double u = std::cos(yaw) * d.x() + std::sin(yaw) * d.y(), v = -std::sin(yaw) * d.x() + std::cos(yaw) * d.y();
        if (u >= 0.0 && u <= b.length_m && v >= 0.0 && v <= b.width_m) return true;
      }
  }
  return false;
}

std::string SessionTasks::active_task() const {
  for (const TaskProgress& p : tasks_)
    if (!p.done) return p.id;
  return "";
}

void SessionTasks::emit(double t, const std::string& kind, const std::string& text, int severity) {
  SessionEvent e{t, kind, text, severity};
  pending_.push_back(e);
  log_.push_back(e);
}

void SessionTasks::update(const engine::World& w, double dt_s, const vehicle::LoaderControls& controls) {
  const double t = w.time_s();
  const Eigen::Vector2d xy = w.loader().link_pose(0).translation().head<2>();
  const double moved = update_task_progress(w, t, xy);
  metrics_.material_moved_kg = moved;
  metrics_.tasks_done = static_cast<double>(std::count_if(tasks_.begin(), tasks_.end(), [](const TaskProgress& p) { return p.done; }));
  // The time taken: when the last task was done, else the time so far (an
  // unfinished session must not score as if it had taken none).
  if (!done_) metrics_.completion_time_s = t;
  done_ = all_done();
  update_handling(w, t, dt_s);
  update_stall(w, t, dt_s, controls);
  const double work_s = metrics_.completion_time_s;
  metrics_.material_rate_kg_h = work_s > 0.0 ? moved * 3600.0 / work_s : 0.0;
  // Passes and spillage from the bucket's load, looked at every 0.2 s (the
  // load swings from step to step while the edge cuts). A pass's load is
  // what the bucket holds kSettleS after its lip has come out of the cut
  // (0.3 m over the ground): the heap above the bucket's capacity slides off
  // as it lifts out, onto the source, and is neither carried nor spilt. Load
  // lost after that, with the lip away from the targets, is spilt. The pass
  // ends when the bucket has stayed under a third of that load for 0.4 s.
  bucket_sample_s_ += dt_s;
  if (bucket_sample_s_ >= kSampleS - 1e-9) {
    bucket_sample_s_ = 0.0;
    sample_bucket(w, t);
  }
  const Eigen::AlignedBox2d site(Eigen::Vector2d::Zero(), exercise_.site_size_m);
  if (!site.contains(xy)) metrics_.left_work_area_s += dt_s;
  fire_exercise_events(t, xy);
}

// Each task's progress and detail, measured every tick, done or not
// (material delivered stays counted); a task that is done stays done.
// Returns the material moved to the tasks' targets.
double SessionTasks::update_task_progress(const engine::World& w, double t, const Eigen::Vector2d& xy) {
  double moved = 0.0;
  for (std::size_t k = 0; k < tasks_.size(); ++k) {
    const io::Task& task = exercise_.tasks[k];
    TaskProgress& p = tasks_[k];
    std::ostringstream d;
    switch (task.type) {
      case io::Task::Type::kMoveMaterial:
      case io::Task::Type::kBackfill: {
        const double in = zone_material_kg(w, task.to) - baseline_kg_[k];
        moved += std::max(0.0, in);
        p.progress = std::clamp(in / task.mass_kg, 0.0, 1.0);
        d << static_cast<long>(std::max(0.0, in)) << " of " << task.mass_kg << " kg in '" << task.to << "'";
        break;
      }
      case io::Task::Type::kLoadTruck: {
        double in = 0.0;
        for (std::size_t b = 0; b < exercise_.trucks.size(); ++b)
          if (exercise_.trucks[b].id == task.to && static_cast<int>(b) < w.tray_count()) in = w.tray(static_cast<int>(b)).material_mass_kg();
        moved += in;
        p.progress = std::clamp(in / task.mass_kg, 0.0, 1.0);
        d << static_cast<long>(in) << " of " << task.mass_kg << " kg in truck '" << task.to << "'";
        break;
      }
      case io::Task::Type::kDriveCourse: {
        std::size_t& gate = next_gate_[k];
        if (gate < task.gates.size() && task.gates[gate].contains(xy)) {
          ++gate;
          emit(t, "task_progress", "gate " + std::to_string(gate) + " of " + std::to_string(task.gates.size()));
        }
        p.progress = static_cast<double>(gate) / static_cast<double>(task.gates.size());
        d << gate << " of " << task.gates.size() << " gates";
        break;
      }
      case io::Task::Type::kClimb: {
        const io::Zone* z = find_zone(exercise_, task.to);
        p.progress = z && z->region.contains(xy) ? 1.0 : 0.0;
        d << (p.progress >= 1.0 ? "reached" : "not reached") << " '" << task.to << "'";
        break;
      }
      case io::Task::Type::kGrade: {
        const io::Zone* z = find_zone(exercise_, task.to);
        const terrain::GranularGrid* g = w.terrain();
        long cells = 0, within = 0;
        if (z && g) {
          const Eigen::AlignedBox2i c = zone_cells(w, *z);
          for (int j = c.min().y(); j < c.max().y(); ++j)
            for (int i = c.min().x(); i < c.max().x(); ++i) {
              ++cells;
              within += std::abs(g->surface_m(i, j) - task.height_m) <= task.tolerance_m;
            }
        }
        const double share = cells > 0 ? static_cast<double>(within) / static_cast<double>(cells) : 0.0;
        p.progress = std::min(1.0, share / task.coverage);
        d << within << " of " << cells << " cells within " << task.tolerance_m << " m of " << task.height_m
          << " m (" << static_cast<long>(task.coverage * 100.0 + 0.5) << " % asked)";
        break;
      }
    }
    p.detail = d.str();
    const double limit = task.time_limit_s > 0.0 ? task.time_limit_s : exercise_.time_limit_s;
    if (!p.done && p.progress >= 1.0 && t <= limit) {
      p.done = true;
      p.done_at_s = t;
      emit(t, "task_done", "task '" + p.id + "' done: " + p.detail);
    }
  }
  return moved;
}

// How the machine is handled: tipping, idling, wheel slip, bucket impacts,
// collisions, people and trucks, the engine's energy.
void SessionTasks::update_handling(const engine::World& w, double t, double dt_s) {
  const vehicle::Loader& l = w.loader();
  const vehicle::Loader::AxleLoads axles = l.axle_loads();
  const double rear = axles.rear_N, total = axles.total_N;
  // A scare is the rear axle all but unloaded for kTippingHoldS: long
  // enough for the machine to pitch forward, not the bounce of a pivot turn
  // on rough ground. It counts once and re-arms only after the rear axle
  // has carried a tenth of the load again for kTippingRearmS.
  const bool unloaded = total > 0.0 && rear < kTippingRearShare * total;
  rear_unloaded_s_ = unloaded ? rear_unloaded_s_ + dt_s : 0.0;
  rear_loaded_s_ = (total > 0.0 && rear > kTippingRearmRearShare * total) ? rear_loaded_s_ + dt_s : 0.0;
  if (rear_unloaded_s_ >= kTippingHoldS && !tipping_) {
    metrics_.tipping_margin_violations += 1.0;
    emit(t, "warning", "the rear wheels lifted: the machine is tipping forward", 2);
    tipping_ = true;
  }
  if (tipping_ && rear_loaded_s_ >= kTippingRearmS) tipping_ = false;
  if (l.chassis_velocity().head<2>().norm() < kIdleSpeedMps) metrics_.idle_time_s += dt_s;
  if (worst_slip_of(l) > kSlipLimit) metrics_.wheel_slip_time_s += dt_s;
  // Harsh handling: the bucket's centre of mass changing velocity faster
  // than kImpactMps2 over a tick (dropped onto the ground, slammed into a
  // stop or a truck's side); one impact counts once within kEventRearmS.
  {
    Eigen::Vector3d v, omega;
    l.link_velocity(static_cast<int>(l.description().links.size()) - 1, v, omega);
    since_impact_s_ += dt_s;
    if (have_bucket_velocity_) {
      const double a = (v - bucket_velocity_).norm() / dt_s;
      if (t > kSettlingS) metrics_.peak_bucket_acceleration_m_s2 = std::max(metrics_.peak_bucket_acceleration_m_s2, a);
      // (Not in the first second: the machine settling onto its wheels.)
      if (a > kImpactMps2 && since_impact_s_ >= kEventRearmS && t > kSettlingS) {
        metrics_.bucket_impacts += 1.0;
        since_impact_s_ = 0.0;
        emit(t, "warning", "bucket impact: " + std::to_string(std::lround(a / kGravity_m_s2)) + " g", 1);
      }
    }
    bucket_velocity_ = v;
    have_bucket_velocity_ = true;
  }
  // A collision: the machine's body, arm or bucket touching an obstacle or a
  // truck; one contact that lasts counts once, and a new one only after the
  // machine has been clear for kEventRearmS.
  const bool touching = w.machine_touches_obstacle();
  apart_s_ = touching ? 0.0 : apart_s_ + dt_s;
  if (touching && !touching_) {
    metrics_.collisions += 1.0;
    emit(t, "collision", "the machine hit an obstacle", 2);
  }
  if (touching) touching_ = true;
  if (touching_ && apart_s_ >= kEventRearmS) touching_ = false;
  safety_.update(w, t, dt_s, [this](double at, const std::string& kind, const std::string& text, int severity) {
    emit(at, kind, text, severity);
  });
  metrics_.safety = safety_.metrics();
  metrics_.engine_energy_MJ += l.engine_output_power_W() * dt_s * 1e-6;
}

// Whether the bucket is in the soil: the surface at its lip, or just ahead
// of it, stands over the lip (the edge is in the cut or pressing into a
// face). Sites without soil have none to be in.
bool SessionTasks::bucket_in_soil(const engine::World& w) const {
  const terrain::BodyAutomaton* b = w.bucket_material();
  if (!w.terrain() || !b) return false;
  const Eigen::Vector3d lip = lip_of(*b);
  const Eigen::Vector2d forward = (b->pose().linear() * Eigen::Vector3d::UnitX()).head<2>();
  const double n = forward.norm();
  const Eigen::Vector2d ahead = n > 0.0 ? Eigen::Vector2d(lip.head<2>() + kInSoilAheadM / n * forward) : lip.head<2>();
  const double soil_m = std::max(ground_height_m(w, lip.head<2>()), ground_height_m(w, ahead));
  return soil_m > lip.z() + kInSoilM;
}

// A stall: the operator pushes with the bucket in the soil and the machine
// gets nowhere, as a loader does when its hydraulics (the drive's relief,
// the cylinders') or its traction cannot beat the soil. Counted once it has
// lasted kStallOnsetS, then its whole length; an event once per stall.
void SessionTasks::update_stall(const engine::World& w, double t, double dt_s,
                                const vehicle::LoaderControls& controls) {
  const vehicle::Loader& l = w.loader();
  const Eigen::Vector2d xy = l.link_pose(0).translation().head<2>();
  if (!stall_armed_ && (xy - stall_at_m_).norm() >= kStallRearmM) stall_armed_ = true;
  const bool driving = 0.5 * (controls.drive_left + controls.drive_right) > kStallDriveLever;
  const bool drive_held = l.chassis_velocity().head<2>().norm() < kIdleSpeedMps || worst_slip_of(l) > kSlipLimit;
  // The implement: some joint asked to move, and none of those asked turning.
  const double levers[2] = {controls.lift, controls.tilt};
  bool asked = false, turning = false;
  for (int k = 0; k < 2; ++k)
    if (std::abs(levers[k]) > kStallImplementLever) {
      asked = true;
      turning = turning || std::abs(l.joint_speed(k)) >= kStallJointRadS;
    }
  const bool pushing = (driving && drive_held) || (asked && !turning);
  if (!pushing || !bucket_in_soil(w)) {
    stuck_s_ = 0.0;
    stalled_ = false;
    return;
  }
  stuck_s_ += dt_s;
  if (stalled_) {
    metrics_.stall_time_s += dt_s;
    return;
  }
  if (stuck_s_ < kStallOnsetS - 1e-9) return;
  // A stall: its onset counts too, and it gets an event unless it is the
  // last one again (the machine has not moved on since).
  stalled_ = true;
  metrics_.stall_time_s += stuck_s_;
  stall_at_m_ = xy;
  if (stall_armed_) {
    stall_armed_ = false;
    emit(t, "stall", "The bank stops the machine: take a thinner cut (back out, raise the edge and cut again)", 1);
  }
}

// The exercise's own events (at a time, on entering a zone, on a task done).
void SessionTasks::fire_exercise_events(double t, const Eigen::Vector2d& xy) {
  for (std::size_t k = 0; k < exercise_.events.size(); ++k) {
    if (fired_[k]) continue;
    const io::Event& e = exercise_.events[k];
    bool fire = false;
    if (e.when == io::Event::When::kAtTime) fire = t >= e.at_s;
    if (e.when == io::Event::When::kEnterZone)
      for (std::size_t zi = 0; zi < exercise_.zones.size(); ++zi)
        if (exercise_.zones[zi].id == e.subject) fire = !was_in_zone_[zi] && exercise_.zones[zi].region.contains(xy);
    if (e.when == io::Event::When::kTaskDone)
      for (const TaskProgress& p : tasks_) fire = fire || (p.id == e.subject && p.done);
    if (fire) {
      fired_[k] = true;
      emit(t, "message", e.message);
    }
  }
  for (std::size_t zi = 0; zi < exercise_.zones.size(); ++zi) was_in_zone_[zi] = exercise_.zones[zi].region.contains(xy);
}

bool SessionTasks::all_done() const {
  return std::all_of(tasks_.begin(), tasks_.end(), [](const TaskProgress& p) { return p.done; });
}

std::vector<SessionEvent> SessionTasks::take_events() {
  std::vector<SessionEvent> out;
  out.swap(pending_);
  return out;
}

double SessionTasks::score() const {
  double s = 0.0;
  for (const io::Metric& m : exercise_.scoring.metrics) s += m.weight * metrics_.value(m.name);
  return s;
}

}  // namespace skidsim::session
