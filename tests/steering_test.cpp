// Steering behaviours (seed 004): arrival stops at the target without
// overshooting, separation keeps a crowd apart, path following stays in
// the corridor and ends at the last point, pursuit beats seek on a moving
// target, flee opens the gap; all bit for bit repeatable.
#include <gtest/gtest.h>

#include <cmath>

#include "engine/steering.h"

namespace skidsim::engine {
namespace {

constexpr double kDt = 0.01;  // the sessions' control tick

TEST(Steering, ArrivalStopsAtTheTargetWithoutOvershoot) {
  for (const double start_speed : {0.0, 1.4}) {
    SteeringAgent a;
    a.velocity_m_s = Eigen::Vector2d(0.0, start_speed);  // also arriving from a sideways walk
    const Eigen::Vector2d target(10.0, 0.0);
    double furthest_x = 0.0;
    for (int k = 0; k < 2000; ++k) {
      integrate(a, arrive(a, target, 3.0), kDt);
      furthest_x = std::max(furthest_x, a.position_m.x());
    }
    std::printf("[ measured ] arrival (start speed %.1f): %.4f m from the target, %.4f m past it at most, %.5f m/s\n",
                start_speed, (a.position_m - target).norm(), furthest_x - target.x(), a.velocity_m_s.norm());
    EXPECT_LT((a.position_m - target).norm(), 0.02);
    EXPECT_LT(furthest_x - target.x(), 0.02) << "no overshoot";
    EXPECT_LT(a.velocity_m_s.norm(), 0.01);
  }
}

TEST(Steering, SeparationKeepsACrowdApart) {
  std::vector<SteeringAgent> crowd(8);
  for (std::size_t k = 0; k < crowd.size(); ++k) {
    const double angle = 2.0 * M_PI * static_cast<double>(k) / static_cast<double>(crowd.size());
    crowd[k].position_m = Eigen::Vector2d(6.0 * std::cos(angle), 6.0 * std::sin(angle));
  }
  double closest = 1e9;
  for (int step = 0; step < 3000; ++step) {
    const std::vector<SteeringAgent> before = crowd;  // everyone sees the same instant
    for (SteeringAgent& a : crowd) integrate(a, arrive(a, Eigen::Vector2d::Zero(), 2.0) + 2.0 * separation(a, before, 2.0), kDt);
    if (step > 1000)
      for (std::size_t i = 0; i < crowd.size(); ++i)
        for (std::size_t j = i + 1; j < crowd.size(); ++j) closest = std::min(closest, (crowd[i].position_m - crowd[j].position_m).norm());
  }
  std::printf("[ measured ] eight walkers sent to one point: closest pair %.3f m apart\n", closest);
  EXPECT_GT(closest, 0.6) << "two bodies' radii (0.3 m each)";
}

TEST(Steering, PathFollowingStaysInTheCorridorAndEndsAtTheLastPoint) {
  Path path;
  path.points_m = {{0, 0}, {10, 0}, {10, 8}, {2, 8}};
  path.radius_m = 0.5;
  SteeringAgent a;
  a.position_m = Eigen::Vector2d(0.0, -1.0);
  double worst = 0.0;
  for (int k = 0; k < 4000; ++k) {
    integrate(a, follow_path(a, path, 1.0, true, 2.0), kDt);
    if (k > 300) worst = std::max(worst, (path_point_m(path, path_distance_m(path, a.position_m)) - a.position_m).norm());
  }
  std::printf("[ measured ] path of 26 m: at most %.3f m off it (corridor 0.5 m), %.4f m from its end\n", worst,
              (a.position_m - path.points_m.back()).norm());
  EXPECT_LT(worst, path.radius_m + 0.3);
  EXPECT_LT((a.position_m - path.points_m.back()).norm(), 0.05);
}

TEST(Steering, PursuitBeatsSeekAndFleeOpensTheGap) {
  const auto catch_time = [](bool predict) {
    SteeringAgent hunter, prey;
    hunter.max_speed_m_s = 2.0;
    prey.position_m = Eigen::Vector2d(5.0, 5.0);
    prey.velocity_m_s = Eigen::Vector2d(1.0, 0.0);
    for (int k = 0; k < 6000; ++k) {
      integrate(hunter, predict ? pursue(hunter, prey.position_m, prey.velocity_m_s) : seek(hunter, prey.position_m), kDt);
      prey.position_m += prey.velocity_m_s * kDt;
      if ((hunter.position_m - prey.position_m).norm() < 0.5) return k * kDt;
    }
    return 1e9;
  };
  const double pursued = catch_time(true), sought = catch_time(false);
  std::printf("[ measured ] caught a 1 m/s walker in %.2f s pursuing, %.2f s seeking\n", pursued, sought);
  EXPECT_LT(pursued, sought);
  SteeringAgent a;
  a.position_m = Eigen::Vector2d(1.0, 0.0);
  for (int k = 0; k < 300; ++k) integrate(a, flee(a, Eigen::Vector2d::Zero(), 5.0), kDt);
  EXPECT_GT(a.position_m.norm(), 4.0);
  SteeringAgent calm;
  calm.position_m = Eigen::Vector2d(8.0, 0.0);
  EXPECT_EQ(flee(calm, Eigen::Vector2d::Zero(), 5.0), Eigen::Vector2d::Zero()) << "beyond the panic distance";
}

TEST(Steering, RepeatsBitForBit) {
  const auto run = [] {
    std::vector<SteeringAgent> crowd(5);
    for (std::size_t k = 0; k < crowd.size(); ++k) crowd[k].position_m = Eigen::Vector2d(0.37 * k, 1.1 * k);
    for (int step = 0; step < 500; ++step) {
      const std::vector<SteeringAgent> before = crowd;
      for (SteeringAgent& a : crowd)
        integrate(a, arrive(a, Eigen::Vector2d(3, 3), 2.0) + separation(a, before, 2.0) + 0.5 * cohesion(a, before, 3.0) +
                         0.5 * alignment(a, before, 3.0),
                  kDt);
    }
    return crowd;
  };
  const auto a = run(), b = run();
  for (std::size_t k = 0; k < a.size(); ++k) {
    EXPECT_EQ(a[k].position_m, b[k].position_m);
    EXPECT_EQ(a[k].velocity_m_s, b[k].velocity_m_s);
  }
}

}  // namespace
}  // namespace skidsim::engine
