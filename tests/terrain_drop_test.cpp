// A hard case (docs/validation.md, "Stability on hard cases"): a body hitting soil at 10 m/s.
// Forces stay finite, the body does not pass through the hard base under
// 40 cm of soil, it comes to rest without jitter, material is conserved.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "terrain/body_shapes.h"
#include "terrain/soil_contact.h"
#include "tests/soil_contact_support.h"

namespace skidsim::terrain {
namespace {

struct DropResult {
  double max_force_N = 0.0;
  double max_base_penetration_m = 0.0;
  double final_speed_m_s = 0.0;
  double last_half_second_motion_m = 0.0;
  double rest_sinkage_m = 0.0;
  bool finite = true;
  bool balanced = false;
};

DropResult drop(double mass_kg, double cells_per_m) {
  const double dt = 0.002, depth = 0.4;
  GranularGrid g = testing::flat_site(cells_per_m, 2.5, depth, dt);
  SoilContactModel model(g, SoilMechanics{});
  testing::TranslatingBody body;
  body.mass_kg = mass_kg;
  body.position_m = {1.2137, 1.1871, depth + 0.5};  // bottom on the surface
  body.velocity_m_s = {0.0, 0.0, -10.0};
  OrientedBox cube;
  cube.half_extents_m = Eigen::Vector3d::Constant(0.5);
  DropResult out;
  double z_at_2_5 = 0.0, z_min = 1e9, z_max = -1e9;
  const int steps = 1500;  // 3 s
  for (int k = 0; k < steps; ++k) {
    cube.centre_m = body.position_m;
    const BodyReaction r = model.interact(0, cube, body.motion());
    out.finite = out.finite && r.force_N.allFinite() && r.torque_Nm.allFinite() &&
                 std::isfinite(r.normal_stiffness_N_per_m);
    out.max_force_N = std::max(out.max_force_N, r.force_N.norm());
    body.step(r, {0.0, 0.0, -mass_kg * kGravity_m_s2}, dt);
    g.step();
    out.max_base_penetration_m = std::max(out.max_base_penetration_m, -(body.position_m.z() - 0.5));
    if (k == steps - 250) z_at_2_5 = body.position_m.z();
    if (k >= steps - 250) {
      z_min = std::min(z_min, body.position_m.z());
      z_max = std::max(z_max, body.position_m.z());
    }
  }
  out.final_speed_m_s = body.velocity_m_s.norm();
  out.last_half_second_motion_m = std::max(z_max - z_at_2_5, z_at_2_5 - z_min);
  out.rest_sinkage_m = depth - (body.position_m.z() - 0.5);
  out.balanced = g.ledger().balanced();
  return out;
}

TEST(SoilImpact, BodyDroppedAtTenMetresPerSecondStopsFiniteAboveTheBaseAndRests) {
  for (double cells_per_m : {10.0, 20.0}) {
    // 1 t stops in the soil; 4 t reaches the hard base.
    for (double mass : {1000.0, 4000.0}) {
      const DropResult r = drop(mass, cells_per_m);
      SCOPED_TRACE(::testing::Message() << cells_per_m << " cells/m, " << mass << " kg: peak force "
                                        << r.max_force_N << " N, base penetration " << r.max_base_penetration_m
                                        << " m, rest sinkage " << r.rest_sinkage_m << " m");
      std::printf("%g cells/m, %g kg: peak force %.4g N, base penetration %.4g m, rest sinkage %.4g m, speed %.3g\n",
                  cells_per_m, mass, r.max_force_N, r.max_base_penetration_m, r.rest_sinkage_m, r.final_speed_m_s);
      EXPECT_TRUE(r.finite);
      // The soil softens the blow: the peak force stays below that of the
      // body hitting the bare hard base at 10 m/s, v sqrt(k_base A m).
      const double bare_base_N = 10.0 * std::sqrt(1000.0 * SoilMechanics{}.base_stiffness_kPa_per_m * mass);
      EXPECT_LT(r.max_force_N, 0.5 * bare_base_N);
      EXPECT_LT(r.max_base_penetration_m, 0.02);
      EXPECT_LT(r.final_speed_m_s, 1e-3);
      EXPECT_LT(r.last_half_second_motion_m, 1e-4);
      EXPECT_GT(r.rest_sinkage_m, 0.05);
      EXPECT_TRUE(r.balanced);
    }
  }
}

}  // namespace
}  // namespace skidsim::terrain

namespace skidsim::terrain {
namespace {

// The incompressible model (thesis 5.3): a ball set on soil that does not
// compact pushes material out from under it into a rim; nothing is
// compacted, material is conserved exactly and the ball comes to rest
// carried by the soil, at the depth the same Bekker soil gives when it
// compacts (the pressure law is the same; only where the volume goes
// differs).
struct BallRun {
  double sinkage_m = 0.0, rim_m = 0.0, compacted_m = 0.0, speed_m_s = 0.0, supported_N = 0.0;
  bool conserved = false;
};

BallRun settle_ball(VerticalLoadModel model_kind) {
  const double dt = 0.002, depth = 0.4, cells_per_m = 20.0;
  GranularGrid g = testing::flat_site(cells_per_m, 2.0, depth, dt);
  SoilMechanics soil;  // dry sand's Bekker law, n = 1.1
  soil.model = model_kind;
  SoilContactModel model(g, soil);
  const std::int64_t quanta_before = g.total_quanta();
  Sphere ball;
  ball.radius_m = 0.3;
  testing::TranslatingBody body;
  body.mass_kg = 300.0;
  body.position_m = {1.0137, 0.9871, depth + ball.radius_m};
  BodyReaction r;
  for (int k = 0; k < 2500; ++k) {
    ball.centre_m = body.position_m;
    r = model.interact(0, ball, body.motion());
    body.step(r, {0.0, 0.0, -body.mass_kg * kGravity_m_s2}, dt);
    g.step();
  }
  BallRun out;
  out.sinkage_m = depth - (body.position_m.z() - ball.radius_m);
  for (int j = 0; j < g.ny(); ++j) {
    for (int i = 0; i < g.nx(); ++i) {
      out.rim_m = std::max(out.rim_m, g.surface_m(i, j) - depth);
      out.compacted_m += g.compacted_m(g.index(i, j));
    }
  }
  out.speed_m_s = body.velocity_m_s.norm();
  out.supported_N = r.force_N.z();
  out.conserved = g.total_quanta() == quanta_before && g.ledger().balanced();
  return out;
}

TEST(IncompressibleSoil, LoadPushesMaterialAsideIntoARim) {
  const BallRun pushed = settle_ball(VerticalLoadModel::kIncompressible);
  const BallRun compacted = settle_ball(VerticalLoadModel::kBekker);
  std::printf("ball on incompressible soil: sinkage %.4f m, rim %.4f m; on compressible: sinkage %.4f m, rim %.4f m\n",
              pushed.sinkage_m, pushed.rim_m, compacted.sinkage_m, compacted.rim_m);
  const double weight = 300.0 * kGravity_m_s2;
  for (const BallRun* run : {&pushed, &compacted}) {
    EXPECT_TRUE(run->conserved);
    EXPECT_LT(run->speed_m_s, 1e-3);
    EXPECT_NEAR(run->supported_N, weight, 0.02 * weight);
    EXPECT_GT(run->sinkage_m, 0.02);
  }
  // Incompressible: nothing compacted, the volume stands in a rim.
  EXPECT_EQ(pushed.compacted_m, 0.0);
  EXPECT_GT(pushed.rim_m, 0.01);
  // Compressible: no rim, the volume is compacted.
  EXPECT_LT(compacted.rim_m, 1e-6);
  EXPECT_GT(compacted.compacted_m, 0.0);
  // The same pressure law: the rim carries a little, so the ball sinks a
  // little less where the soil is pushed aside.
  EXPECT_LT(pushed.sinkage_m, compacted.sinkage_m);
  EXPECT_GT(pushed.sinkage_m, 0.7 * compacted.sinkage_m);
}

}  // namespace
}  // namespace skidsim::terrain
