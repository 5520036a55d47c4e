// Agents' plans (issue 9): a person walks a route with pauses and stands at
// its end, keeps clear of a moving loader and of people coming the other
// way; a truck reverses to its loading spot, docks within tolerance, waits
// for its load and drives off; all deterministic.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/agents.h"

namespace skidsim::engine {
namespace {

constexpr double kDt = 0.002;  // the world's step

struct AgentRun {
  std::vector<AgentSpec> specs;
  std::vector<AgentState> states;
  std::vector<SteeringAgent> scratch;
  double t = 0.0;
  explicit AgentRun(std::vector<AgentSpec> s) : specs(std::move(s)), states(start_agents(specs)) {}
  void step(const SiteView& site) {
    step_agents(specs, states, site, t, kDt, scratch);
    t += kDt;
  }
};

TEST(Agents, APersonWalksTheRoutePausesAndStandsAtItsEnd) {
  AgentSpec walker;
  walker.route_m = {{0, 0}, {6, 0}, {6, 4}};
  walker.pause_s = 2.0;
  AgentRun run({walker});
  double paused_at_middle = 0.0;
  for (int k = 0; k < 10000; ++k) {
    run.step({});
    if ((run.states[0].body.position_m - Eigen::Vector2d(6, 0)).norm() < 0.15 && run.states[0].body.velocity_m_s.norm() < 0.05)
      paused_at_middle += kDt;
  }
  const AgentState& s = run.states[0];
  std::printf("[ measured ] walker: %.3f m from the route's end, stood %.2f s at its middle point\n",
              (s.body.position_m - Eigen::Vector2d(6, 4)).norm(), paused_at_middle);
  EXPECT_LT((s.body.position_m - Eigen::Vector2d(6, 4)).norm(), kReachedM);
  EXPECT_GE(paused_at_middle, 2.0);
  EXPECT_EQ(s.phase, AgentPhase::kPausing);
}

TEST(Agents, APersonKeepsClearOfAMovingLoader) {
  AgentSpec bystander;
  bystander.route_m = {{10, 0}};  // stands there
  AgentRun run({bystander});
  SiteView site;
  site.loader_velocity_m_s = Eigen::Vector2d(2.0, 0.0);  // the loader drives through where the person stands
  double closest = 1e9;
  for (int k = 0; k < 5000; ++k) {
    site.loader_m = Eigen::Vector2d(2.0 * run.t, 0.0);
    run.step(site);
    closest = std::min(closest, (run.states[0].body.position_m - site.loader_m).norm());
  }
  std::printf("[ measured ] a loader driven at 2 m/s through a standing person: closest %.2f m\n", closest);
  EXPECT_GT(closest, 2.0) << "the loader's half width (0.9 m) and a margin";
}

TEST(Agents, PeopleComingTheOtherWayPassWithoutTouching) {
  AgentSpec a, b;
  a.route_m = {{0, 0}, {10, 0.05}};
  b.route_m = {{10, 0}, {0, -0.05}};
  AgentRun run({a, b});
  double closest = 1e9;
  for (int k = 0; k < 8000; ++k) {
    run.step({});
    closest = std::min(closest, (run.states[0].body.position_m - run.states[1].body.position_m).norm());
  }
  std::printf("[ measured ] two walkers head on: closest %.2f m apart (bodies 0.6 m)\n", closest);
  EXPECT_GT(closest, 2.0 * kPersonRadiusM);
  EXPECT_LT((run.states[0].body.position_m - Eigen::Vector2d(10, 0.05)).norm(), kReachedM);
}

TEST(Agents, ATruckReversesToItsSpotDocksWaitsForItsLoadAndLeaves) {
  AgentSpec truck;
  truck.kind = AgentKind::kTruck;
  truck.speed_m_s = 2.5;
  truck.route_m = {{30, 10}, {20, 10}, {12, 10}};  // backing in along -x
  truck.leave_at_kg = 1000.0;
  truck.exit_m = {{25, 10}, {40, 10}};
  AgentRun run({truck});
  std::vector<double> bed = {0.0};
  SiteView site;
  site.bed_load_kg = &bed;
  double worst_past = 0.0;
  for (int k = 0; k < 15000; ++k) {
    run.step(site);
    worst_past = std::max(worst_past, 12.0 - run.states[0].body.position_m.x());
  }
  const AgentState& s = run.states[0];
  ASSERT_EQ(s.phase, AgentPhase::kDocked);
  const double heading_error_deg = std::abs(std::remainder(s.heading_rad - 0.0, 2.0 * M_PI)) * 180.0 / M_PI;
  std::printf("[ measured ] truck docked at %.1f s, %.3f m from its spot, facing %.2f deg off, %.3f m past it at most\n",
              s.docked_at_s, (s.body.position_m - Eigen::Vector2d(12, 10)).norm(), heading_error_deg, worst_past);
  EXPECT_LT((s.body.position_m - Eigen::Vector2d(12, 10)).norm(), kReachedM);
  EXPECT_LT(heading_error_deg, 2.0) << "reversed in: it faces +x, away from its motion";
  EXPECT_LT(worst_past, 0.02) << "no overshoot into the loading area";
  for (int k = 0; k < 5000; ++k) run.step(site);
  EXPECT_EQ(run.states[0].phase, AgentPhase::kDocked) << "waits while its bed is not full";
  bed[0] = 1200.0;
  for (int k = 0; k < 20000; ++k) run.step(site);
  EXPECT_EQ(run.states[0].phase, AgentPhase::kGone);
}

// A truck stops short while the loader stands in its way, and backs in
// once it has gone; the heading at its spot is the bed's.
TEST(Agents, ATruckWaitsWhileTheLoaderIsInItsWay) {
  AgentSpec truck;
  truck.kind = AgentKind::kTruck;
  truck.speed_m_s = 2.5;
  truck.route_m = {{30, 10}, {12, 10}};
  truck.dock_heading_rad = 0.05;
  AgentRun run({truck});
  SiteView site;
  site.loader_rear_m = Eigen::Vector2d(9.0, 10.0);  // parked across the loading spot
  site.loader_front_m = Eigen::Vector2d(9.0, 13.0);
  double closest = 1e9;
  for (int k = 0; k < 10000; ++k) {
    run.step(site);
    closest = std::min(closest, footprint_distance_m(site, run.states[0].body.position_m));
  }
  std::printf("[ measured ] truck held %.2f m from a loader parked in its way\n", closest);
  EXPECT_EQ(run.states[0].phase, AgentPhase::kMoving);
  EXPECT_GT(closest, kTruckRadiusM);
  EXPECT_LT(run.states[0].body.velocity_m_s.norm(), 0.01);
  site.loader_rear_m = site.loader_front_m = Eigen::Vector2d(0.0, 30.0);  // gone
  for (int k = 0; k < 10000; ++k) run.step(site);
  EXPECT_EQ(run.states[0].phase, AgentPhase::kDocked);
  EXPECT_EQ(run.states[0].heading_rad, 0.05);
}

// A spawn event: a held agent stays off site, whatever its start time,
// until it is released.
TEST(Agents, AHeldAgentWaitsForItsRelease) {
  AgentSpec walker;
  walker.route_m = {{0, 0}, {3, 0}};
  walker.held = true;
  AgentRun run({walker});
  for (int k = 0; k < 1000; ++k) run.step({});
  EXPECT_EQ(run.states[0].phase, AgentPhase::kNotYet);
  run.specs[0].held = false;  // what World::release_agent does (with start_s = now)
  run.specs[0].start_s = run.t;
  for (int k = 0; k < 3000; ++k) run.step({});
  EXPECT_TRUE(on_site(run.states[0]));
  EXPECT_LT((run.states[0].body.position_m - Eigen::Vector2d(3, 0)).norm(), kReachedM);
}

TEST(Agents, RepeatBitForBit) {
  const auto go = [] {
    AgentSpec a, b, t;
    a.route_m = {{0, 0}, {5, 5}, {0, 5}};
    a.loop = true;
    b.route_m = {{5, 0}, {0, 4}};
    b.start_s = 1.0;
    t.kind = AgentKind::kTruck;
    t.route_m = {{20, 0}, {10, 0}};
    AgentRun run({a, b, t});
    SiteView site;
    site.loader_m = Eigen::Vector2d(3, 3);
    site.loader_velocity_m_s = Eigen::Vector2d(0.5, 0);
    for (int k = 0; k < 5000; ++k) run.step(site);
    return run.states;
  };
  const auto x = go(), y = go();
  for (std::size_t k = 0; k < x.size(); ++k) {
    EXPECT_EQ(x[k].body.position_m, y[k].body.position_m);
    EXPECT_EQ(x[k].heading_rad, y[k].heading_rad);
  }
}

}  // namespace
}  // namespace skidsim::engine
