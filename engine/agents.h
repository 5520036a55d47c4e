// People and vehicles on site (thesis 9.2.2's avatars; seed 004's steering
// behaviours): each agent is a steering character with a plan. A person
// walks a route (once or round and round), pausing at its points, keeps
// clear of the loader while it moves and of the other agents. A dump truck
// reverses along its route to a loading spot, stands there until its bed
// holds what it came for, then drives off along its exit. The plan and the
// motion are here, in the ground plane; the world turns agents into Bullet
// bodies (engine/world.h). Deterministic; nothing allocates per step.
#pragma once

#include <Eigen/Core>

#include <string>
#include <vector>

#include "engine/steering.h"

namespace skidsim::engine {

enum class AgentKind { kPerson, kTruck };

struct AgentSpec {
  std::string id;
  AgentKind kind = AgentKind::kPerson;
  // Person: walked from the first point. Truck: driven in reverse from the
  // first point to the last, the loading spot (its rear axle's centre...
  // here: the centre of its bed), arriving along the last leg.
  std::vector<Eigen::Vector2d> route_m;
  bool loop = false;          // person: from the last point back to the first, again and again
  double pause_s = 0.0;       // person: standing at each point
  double start_s = 0.0;       // appears (at the first point) at this time
  bool held = false;          // waits to be released (World::release_agent) whatever start_s says
  double speed_m_s = 1.3;     // top speed
  double keep_clear_m = 6.0;  // person: moves out of the way of a moving loader closer than this
  // Truck: the bed it carries (a tray of the world, posed at the loading
  // spot), the load it leaves with, and the way out (driven forwards).
  int tray = -1;
  double leave_at_kg = 0.0;
  std::vector<Eigen::Vector2d> exit_m;
  double dock_heading_rad = 0.0;  // the bed's heading at its spot (set by the world)
};

enum class AgentPhase { kNotYet, kMoving, kPausing, kDocked, kLeaving, kGone };

struct AgentState {
  SteeringAgent body;
  double heading_rad = 0.0;  // where the agent faces (a truck reversing faces away from its motion)
  AgentPhase phase = AgentPhase::kNotYet;
  int next_point = 1;        // into the route (or the exit when leaving)
  double phase_since_s = 0.0;
  double docked_at_s = -1.0;  // truck: when it reached its loading spot
};

// A person's and a truck's body, for steering and contact.
inline constexpr double kPersonRadiusM = 0.3, kPersonHeightM = 1.75, kPersonMassKg = 80.0;
inline constexpr double kTruckRadiusM = 1.6, kTruckMassKg = 12000.0;
inline constexpr double kTruckCabLengthM = 2.2, kTruckCabHeightM = 2.9;  // in front of its bed
// Reached: within this of a point and slower than kStoppedMS.
inline constexpr double kReachedM = 0.1, kStoppedMS = 0.05;

// The distance from a point to the machine's footprint (0 inside) and the
// footprint's nearest point.
double footprint_distance_m(const struct SiteView& site, const Eigen::Vector2d& p, Eigen::Vector2d* nearest = nullptr);
// Clear of the loader: a truck stops while the machine is this close to
// where it is going; a person never comes closer than kPersonClearM.
inline constexpr double kTruckClearM = 3.0, kPersonClearM = 1.0;

// What the agents see of the rest of the site each step.
struct SiteView {
  Eigen::Vector2d loader_m = Eigen::Vector2d::Constant(1e9);
  Eigen::Vector2d loader_velocity_m_s = Eigen::Vector2d::Zero();
  // The machine's footprint: a capsule of this half width around the
  // segment from behind its chassis to its bucket.
  Eigen::Vector2d loader_rear_m = Eigen::Vector2d::Constant(1e9), loader_front_m = Eigen::Vector2d::Constant(1e9);
  double loader_half_width_m = 0.95;
  // Per agent with a bed (by agent index): the mass in its bed.
  const std::vector<double>* bed_load_kg = nullptr;
};

// The agents' initial states (not yet on site until their start time).
std::vector<AgentState> start_agents(const std::vector<AgentSpec>& specs);

// One step of every agent: plans, steering, integration. `scratch` holds
// the agents' bodies at the start of the step (everyone sees one instant).
void step_agents(const std::vector<AgentSpec>& specs, std::vector<AgentState>& states, const SiteView& site, double t_s,
                 double dt_s, std::vector<SteeringAgent>& scratch);

// Whether an agent is on site (started and not gone).
inline bool on_site(const AgentState& s) { return s.phase != AgentPhase::kNotYet && s.phase != AgentPhase::kGone; }

}  // namespace skidsim::engine
