// Awkward cases of the soil-body interaction, each one a defect found in
// review: two bodies over one cell, soil with nowhere to go, a body sliding
// off part of its imprint, a segment wholly inside a mesh, bodies far away.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "terrain/body_shapes.h"
#include "terrain/soil_contact.h"
#include "tests/soil_contact_support.h"

namespace skidsim::terrain {
namespace {

constexpr double kDepth = 0.5;

BodyMotion still_at(const Eigen::Vector3d& p) {
  BodyMotion m;
  m.reference_point_m = p;
  return m;
}

// A cell stays blocked while any body covers it.
TEST(ContactCases, ACellCoveredByTwoBodiesStaysCoveredWhenOneLeaves) {
  GranularGrid g = testing::flat_site(10.0, 2.0, kDepth);
  SoilContactModel model(g, SoilMechanics{});
  OrientedBox a, b;
  a.half_extents_m = b.half_extents_m = {0.3, 0.3, 0.1};
  a.centre_m = {0.83, 1.01, kDepth - 0.01 + 0.1};
  b.centre_m = {1.13, 1.01, kDepth - 0.01 + 0.1};  // overlaps a's right half
  model.interact(0, a, still_at(a.centre_m));
  model.interact(1, b, still_at(b.centre_m));
  const int shared = g.index(10, 10);  // x = 1.0: under both
  ASSERT_TRUE(g.covered(shared));
  model.release(0);
  EXPECT_TRUE(g.covered(shared));
  a.centre_m.z() += 1.0;  // body 0 comes back, lifted clear
  model.interact(0, a, still_at(a.centre_m));
  EXPECT_TRUE(g.covered(shared));
  model.release(1);
  EXPECT_FALSE(g.covered(shared));
}

// Incompressible soil under a plate flush with a closed wall: the soil that
// would leave from under it cannot; the force must not ratchet up.
TEST(ContactCases, ConfinedIncompressibleSoilDoesNotRatchet) {
  GranularGrid g = testing::flat_site(20.0, 1.0, kDepth);
  SoilMechanics soil;
  soil.model = VerticalLoadModel::kIncompressible;
  SoilContactModel model(g, soil);
  OrientedBox plate;
  plate.half_extents_m = {0.3, 0.3, 0.05};
  plate.centre_m = {0.3 - 0.025, 0.5, kDepth - 0.01 + 0.05};  // against the x = 0 wall, 1 cm in
  const double first = model.interact(0, plate, still_at(plate.centre_m)).force_N.z();
  double last = first;
  for (int k = 0; k < 2000; ++k) {
    last = model.interact(0, plate, still_at(plate.centre_m)).force_N.z();
    g.step();
  }
  EXPECT_GT(first, 0.0);
  EXPECT_LE(last, 1.001 * first);
  EXPECT_TRUE(g.ledger().balanced());
}

// A plate pressed 4 cm, slid 5 cm sideways at that height and back: every
// cell's peak sinkage stays near the 4 cm it really saw, and the plate is
// carried when it is back.
TEST(ContactCases, SlidingOffPartOfTheImprintKeepsSinkagesBounded) {
  GranularGrid g = testing::flat_site(20.0, 2.0, kDepth);
  SoilContactModel model(g, SoilMechanics{});
  OrientedBox plate;
  plate.half_extents_m = {0.4, 0.4, 0.05};
  const Eigen::Vector3d start(0.8137, 1.0071, kDepth + 0.05);
  BodyMotion m;
  for (int k = 0; k <= 100; ++k) {
    plate.centre_m = start - Eigen::Vector3d(0.0, 0.0, 0.04 * k / 100.0);
    model.interact(0, plate, still_at(plate.centre_m));
    g.step();
  }
  const double force_before = model.interact(0, plate, still_at(plate.centre_m)).force_N.z();
  for (int leg = 0; leg < 2; ++leg) {
    m.linear_velocity_m_s = {leg == 0 ? 0.1 : -0.1, 0.0, 0.0};
    for (int k = 0; k < 250; ++k) {
      plate.centre_m.x() += 0.002 * m.linear_velocity_m_s.x();
      m.reference_point_m = plate.centre_m;
      const BodyReaction r = model.interact(0, plate, m);
      ASSERT_TRUE(r.force_N.allFinite());
      g.step();
    }
  }
  double highest_peak = 0.0;
  for (int c = 0; c < g.nx() * g.ny(); ++c) highest_peak = std::max(highest_peak, model.peak_sinkage_m(c));
  EXPECT_LT(highest_peak, 0.06);
  const double force_after = model.interact(0, plate, still_at(plate.centre_m)).force_N.z();
  EXPECT_GT(force_after, 0.5 * force_before);
  EXPECT_LT(force_after, 1.2 * force_before);
  EXPECT_TRUE(g.ledger().balanced());
}

// A body leaving the soil faster than it springs back: no force, and no
// stiffness or damping that an implicit step would turn into a pull.
TEST(ContactCases, ABodyLiftingOffReportsNoStiffnessOrDamping) {
  GranularGrid g = testing::flat_site(20.0, 2.0, kDepth);
  SoilContactModel model(g, SoilMechanics{});
  OrientedBox plate;
  plate.half_extents_m = {0.5, 0.5, 0.05};
  for (int k = 0; k <= 50; ++k) {
    plate.centre_m = {1.0137, 1.0071, kDepth + 0.05 - 0.05 * k / 50.0};
    model.interact(0, plate, still_at(plate.centre_m));
  }
  plate.centre_m.z() += 0.001;
  BodyMotion rising = still_at(plate.centre_m);
  rising.linear_velocity_m_s = {0.0, 0.0, 1.0};
  const BodyReaction r = model.interact(0, plate, rising);
  EXPECT_EQ(r.force_N.z(), 0.0);
  EXPECT_EQ(r.normal_stiffness_N_per_m, 0.0);
  EXPECT_EQ(r.normal_damping_N_s_per_m, 0.0);
  EXPECT_EQ(r.shear_bound_N, 0.0);
  // Back at rest on the reload line it carries load again, and its shear
  // acts at the contact, not at the body's reference point.
  SoilMechanics sticky;
  sticky.tool_adhesion_kPa = 5.0;
  GranularGrid g2 = testing::flat_site(20.0, 2.0, kDepth);
  SoilContactModel model2(g2, sticky);
  plate.centre_m = {1.0137, 1.0071, kDepth + 0.05 - 0.02};
  BodyMotion above = still_at(plate.centre_m + Eigen::Vector3d(0.0, 0.0, 1.0));
  const BodyReaction loaded = model2.interact(0, plate, above);
  EXPECT_GT(loaded.shear_bound_N, 5000.0);  // 5 kPa over 1 m^2, plus friction
  EXPECT_NEAR(loaded.shear_point_m.z(), kDepth - 0.02, 1e-6);
}

// The wedge is made of the soil in front of the interface.
TEST(ContactCases, TheWedgeIsMadeOfTheSoilInFront) {
  SoilMechanics sand, clay;
  sand.friction_angle_deg = 35.0;
  clay.friction_angle_deg = 15.0;
  const auto wedge = [&](bool clay_in_front, bool clay_under) {
    GranularGrid g = testing::flat_site(20.0, 3.0, kDepth);
    SoilContactModel model(g, sand);
    const int clay_index = model.add_soil(clay);
    OrientedBox blade;
    blade.half_extents_m = {0.15, 0.5, 0.3};
    blade.centre_m = {1.0137, 1.5013, kDepth - 0.2 + 0.3};
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) {
        const bool ahead = (i + 0.5) / 20.0 > 1.0137 + 0.15;
        if ((ahead && clay_in_front) || (!ahead && clay_under)) model.set_soil_region(i, j, clay_index);
      }
    model.embed(0, blade, still_at(blade.centre_m));
    return model.interact(0, blade, still_at(blade.centre_m)).wedge[0].bound_N;
  };
  const double all_clay = wedge(true, true), all_sand = wedge(false, false);
  EXPECT_LT(all_clay, 0.7 * all_sand);
  EXPECT_DOUBLE_EQ(wedge(true, false), all_clay);
  EXPECT_DOUBLE_EQ(wedge(false, true), all_sand);
}

TEST(ContactCases, ASegmentWhollyInsideAMeshHitsAtItsLowEnd) {
  TriangleMesh mesh = TriangleMesh::box({1.0, 1.0, 1.0});
  VerticalHit hit;
  ASSERT_TRUE(mesh.lowest_hit(0.1, 0.2, -0.5, 0.5, &hit));
  EXPECT_DOUBLE_EQ(hit.z_m, -0.5);
  OrientedBox box;
  box.half_extents_m = {1.0, 1.0, 1.0};
  ASSERT_TRUE(box.lowest_hit(0.1, 0.2, -0.5, 0.5, &hit));
  EXPECT_DOUBLE_EQ(hit.z_m, -0.5);
  EXPECT_FALSE(mesh.lowest_hit(0.1, 0.2, 1.5, 2.5, &hit));  // above the mesh
}

TEST(ContactCases, FarAwayAndEmptyBodiesTouchNothing) {
  GranularGrid g = testing::flat_site(10.0, 1.0, kDepth);
  SoilContactModel model(g, SoilMechanics{});
  Sphere far;
  far.centre_m = {3.0e8, 0.5, 0.5};
  EXPECT_EQ(model.interact(0, far, BodyMotion{}).contact_cells, 0);
  TriangleMesh empty;
  empty.update();
  EXPECT_EQ(model.interact(1, empty, BodyMotion{}).contact_cells, 0);
}

}  // namespace
}  // namespace skidsim::terrain
