// Tangential contact (thesis 5.4.2, Mohr-Coulomb), the wrench about the
// caller's point, and determinism of the soil-body interaction.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>

#include "common/physical_constants.h"
#include "terrain/body_shapes.h"
#include "terrain/soil_contact.h"
#include "tests/soil_contact_support.h"

namespace skidsim::terrain {
namespace {

constexpr double kDepth = 0.4;
constexpr double kDt = 0.002;

struct SlideRun {
  double shear_bound_N = 0.0;
  double weight_N = 0.0;
  double travel_m = 0.0;
};

// A 600 kg plate settles on the soil, then a horizontal force of
// `push_fraction` times its shear bound pulls it along +x for 1 s.
SlideRun pull_plate(double push_fraction) {
  GranularGrid g = testing::flat_site(20.0, 3.0, kDepth, kDt);
  SoilMechanics soil;
  soil.tool_adhesion_kPa = 0.5;
  SoilContactModel model(g, soil);
  OrientedBox plate;
  plate.half_extents_m = {0.5, 0.5, 0.05};
  testing::TranslatingBody body;
  body.mass_kg = 600.0;
  body.position_m = {1.0137, 1.5071, kDepth + 0.05};
  const Eigen::Vector3d weight(0.0, 0.0, -body.mass_kg * kGravity_m_s2);
  BodyReaction r;
  for (int k = 0; k < 1000; ++k) {  // settle
    plate.centre_m = body.position_m;
    r = model.interact(0, plate, body.motion());
    body.step(r, weight, kDt);
    g.step();
  }
  SlideRun out;
  out.shear_bound_N = r.shear_bound_N;
  out.weight_N = r.force_N.z();
  const double x0 = body.position_m.x();
  // Below the bound the plate must stick; the plate's shallow edges carry
  // wedges of their own, so the pull is compared with shear + wedge.
  const double pull = push_fraction * (r.shear_bound_N + r.wedge[0].bound_N);
  for (int k = 0; k < 500; ++k) {
    plate.centre_m = body.position_m;
    r = model.interact(0, plate, body.motion());
    body.step(r, weight + Eigen::Vector3d(pull, 0.0, 0.0), kDt);
    g.step();
  }
  out.travel_m = body.position_m.x() - x0;
  return out;
}

TEST(MohrCoulomb, ShearBoundIsAdhesionPlusNormalLoadTimesTanDeltaAndDecidesStickOrSlide) {
  const SlideRun stick = pull_plate(0.8);
  const SoilMechanics soil;
  const double expected = 0.5e3 * 1.0 + stick.weight_N * std::tan(soil.tool_friction_angle_deg * kPi / 180.0);
  EXPECT_NEAR(stick.weight_N, 600.0 * kGravity_m_s2, 0.01 * 600.0 * kGravity_m_s2);
  EXPECT_NEAR(stick.shear_bound_N, expected, 0.01 * expected);
  EXPECT_LT(std::abs(stick.travel_m), 1e-6);  // held: static friction
  const SlideRun slide = pull_plate(1.3);
  // Pulled beyond the bound it slides, the bound opposing the motion:
  // (1.3 - 1) F / m t^2 / 2 is about 0.2 m in 1 s.
  EXPECT_GT(slide.travel_m, 0.05);
}

// The wrench is about the caller's point: torque = sum (p - ref) x F, so
// moving the reference point by r changes it by -r x F.
TEST(Wrench, TorqueIsAboutTheCallersPoint) {
  GranularGrid g = testing::flat_site(20.0, 2.0, kDepth, kDt);
  SoilMechanics soft;
  SoilMechanics stiff = soft;
  stiff.k_phi_kN_per_m_n2 *= 3.0;
  SoilContactModel model(g, soft);
  const int stiff_index = model.add_soil(stiff);
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 20; i < g.nx(); ++i) model.set_soil_region(i, j, stiff_index);
  OrientedBox plate;
  plate.half_extents_m = {0.5, 0.5, 0.05};
  plate.centre_m = {1.0137, 1.0071, kDepth - 0.01 + 0.05};
  BodyMotion about_centre;
  about_centre.reference_point_m = plate.centre_m;
  const BodyReaction a = model.interact(0, plate, about_centre);
  // The stiff side (x > 0.975) carries more: the soil tips the plate
  // towards -x, a negative torque about y.
  EXPECT_LT(a.torque_Nm.y(), 0.0);
  EXPECT_NEAR(a.torque_Nm.y(), -(a.shear_point_m.x() - plate.centre_m.x()) * a.force_N.z(),
              1e-9 * a.force_N.norm());
  model.release(0);
  GranularGrid g2 = testing::flat_site(20.0, 2.0, kDepth, kDt);
  SoilContactModel model2(g2, soft);
  model2.add_soil(stiff);
  for (int j = 0; j < g2.ny(); ++j)
    for (int i = 20; i < g2.nx(); ++i) model2.set_soil_region(i, j, 1);
  BodyMotion about_corner = about_centre;
  const Eigen::Vector3d r(0.5, -0.5, 0.05);
  about_corner.reference_point_m += r;
  const BodyReaction b = model2.interact(0, plate, about_corner);
  EXPECT_NEAR((b.force_N - a.force_N).norm(), 0.0, 1e-9 * a.force_N.norm());
  EXPECT_NEAR((b.torque_Nm - (a.torque_Nm - r.cross(a.force_N))).norm(), 0.0, 1e-9 * a.force_N.norm());
}

// The same bodies and motions give the same terrain and reactions, bit for
// bit.
TEST(Determinism, SameSequenceGivesBitIdenticalTerrainAndReactions) {
  const auto run = [] {
    GranularGrid g = testing::flat_site(20.0, 3.0, kDepth, kDt);
    SoilContactModel model(g, SoilMechanics{});
    Sphere ball;
    ball.radius_m = 0.3;
    OrientedBox blade;
    blade.half_extents_m = {0.1, 0.5, 0.3};
    blade.centre_m = {0.6, 1.5, kDepth - 0.15 + 0.3};
    BodyMotion push;
    push.linear_velocity_m_s = {0.8, 0.2, 0.0};
    testing::TranslatingBody body;
    body.mass_kg = 400.0;
    body.position_m = {2.2, 2.0, kDepth + 0.3};
    body.velocity_m_s = {0.0, 0.0, -3.0};
    double checksum = 0.0;
    for (int k = 0; k < 600; ++k) {
      ball.centre_m = body.position_m;
      const BodyReaction rb = model.interact(0, ball, body.motion());
      body.step(rb, {0.0, 0.0, -body.mass_kg * kGravity_m_s2}, kDt);
      blade.centre_m += kDt * push.linear_velocity_m_s;
      push.reference_point_m = blade.centre_m;
      const BodyReaction rp = model.interact(1, blade, push);
      checksum += rb.force_N.sum() + rb.torque_Nm.sum() + rp.wedge[0].bound_N + rp.force_N.sum();
      g.step();
    }
    std::vector<double> surface;
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) surface.push_back(g.surface_m(i, j));
    surface.push_back(checksum);
    return surface;
  };
  const std::vector<double> a = run(), b = run();
  ASSERT_EQ(a.size(), b.size());
  EXPECT_EQ(std::memcmp(a.data(), b.data(), a.size() * sizeof(double)), 0);
}

}  // namespace
}  // namespace skidsim::terrain
