// Safety on a site with people and trucks (issue 9; docs/exercises.md,
// the metrics: collisions with people and the truck, near misses): measured
// every control tick from the world's agents and the machine.
//
// The machine's footprint is a capsule around the segment from behind its
// chassis to its bucket, kMachineHalfWidthM wide each side; a person's
// distance to the machine is from their body's edge to the capsule's.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "engine/world.h"

namespace skidsim::session {

struct SafetyMetrics {
  double people_collisions = 0.0;  // contact episodes with people
  double truck_collisions = 0.0;   // with a truck (its cab, chassis or bed)
  double near_misses = 0.0;        // moving, a person came closer than kNearMissM and got away untouched
  double min_distance_to_people_m = kNoPeopleM;  // while the machine moves; kNoPeopleM with nobody on site
  double speed_near_people_s = 0.0;  // faster than kWalkingPaceMS within kNearPeopleM of a person
  static constexpr double kNoPeopleM = 50.0;
};

inline constexpr double kMachineHalfWidthM = 0.95, kNearMissM = 1.0, kNearPeopleM = 5.0, kWalkingPaceMS = 1.0;

class SafetyMonitor {
 public:
  using Emit = std::function<void(double t, const std::string& kind, const std::string& text, int severity)>;
  void update(const engine::World& world, double t_s, double dt_s, const Emit& emit);
  const SafetyMetrics& metrics() const { return metrics_; }

 private:
  SafetyMetrics metrics_;
  std::vector<double> apart_s_;     // per agent: how long it has been clear of the machine
  std::vector<bool> touching_, near_, near_hit_;
  std::vector<double> near_gap_m_;  // the closest in the present near pass
  std::vector<int> touching_now_;   // scratch
};

// The distance from a point to the machine's footprint (0 inside).
double distance_to_machine_m(const engine::World& world, const Eigen::Vector2d& p);

}  // namespace skidsim::session
