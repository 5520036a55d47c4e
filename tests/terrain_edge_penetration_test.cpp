// The cutting edge's penetration resistance (terrain/edge_penetration.h)
// against published bearing-capacity figures: Vesic's factors as tabulated
// (Vesic 1973; reproduced in Das, "Principles of Foundation Engineering",
// to two decimals) and the bearing pressure evaluated by hand from those
// tabulated factors and Hansen's depth factors.
#include "common/physical_constants.h"
#include "terrain/edge_penetration.h"

#include <gtest/gtest.h>

namespace skidsim::terrain {
namespace {

struct TableRow {
  double phi_deg, n_c, n_q, n_gamma;
};

TEST(EdgePenetration, FactorsMatchVesicsTable) {
  const TableRow rows[] = {{0, 5.14, 1.00, 0.00},     {10, 8.35, 2.47, 1.22},   {20, 14.83, 6.40, 5.39},
                           {30, 30.14, 18.40, 22.40}, {35, 46.12, 33.30, 48.03}, {40, 75.31, 64.20, 109.41},
                           {45, 133.88, 134.88, 271.76}};
  for (const TableRow& r : rows) {
    const BearingFactors f = bearing_factors(deg_to_rad(r.phi_deg));
    // The table rounds to two decimals.
    EXPECT_NEAR(f.n_c, r.n_c, 0.006 + 1e-4 * r.n_c) << r.phi_deg;
    EXPECT_NEAR(f.n_q, r.n_q, 0.006 + 1e-4 * r.n_q) << r.phi_deg;
    EXPECT_NEAR(f.n_gamma, r.n_gamma, 0.006 + 1e-4 * r.n_gamma) << r.phi_deg;
  }
}

CuttingSoil soil(double phi_deg, double c_kPa, double unit_weight_kN_m3) {
  CuttingSoil s;
  s.friction_angle_rad = deg_to_rad(phi_deg);
  s.cohesion_Pa = 1000.0 * c_kPa;
  s.unit_weight_N_per_m3 = 1000.0 * unit_weight_kN_m3;
  return s;
}

EdgeInSoil edge_of(double thickness_m, double width_m, double overburden_m) {
  EdgeInSoil e;
  e.thickness_m = thickness_m;
  e.width_m = width_m;
  e.overburden_m = overburden_m;
  return e;
}

TEST(EdgePenetration, DeepEdgeMatchesTheBearingPressureByHand) {
  // phi 30 deg, c 10 kPa, 16 kN/m^3; a 2 cm edge, 1 m wide, 0.3 m deep:
  // k = atan(15) = 1.50423, d_q = 1 + 2 tan30 (1 - sin30)^2 k = 1.43423,
  // d_c = d_q - (1 - d_q) / (N_c tan30) = 1.45919;
  // F = 0.02 (10e3 30.14 d_c + 16e3 0.3 18.40 d_q + 0.5 16e3 0.02 22.40) = 11401 N.
  const EdgeResistance r = edge_penetration(soil(30, 10, 16), edge_of(0.02, 1.0, 0.3));
  EXPECT_NEAR(r.force_N, 11401.1, 11401.1 * 2e-3);
  EXPECT_NEAR(r.cohesion_term_N + r.overburden_term_N + r.weight_term_N, r.force_N, 1e-9 * r.force_N);
  EXPECT_NEAR(r.pressure_Pa, r.force_N / 0.02, 1e-9 * r.pressure_Pa);
}

TEST(EdgePenetration, UndrainedClayIsPrandtlsPunchWithDepth) {
  // phi 0: N_c = 2 + pi, N_q = 1, N_gamma = 0, d_c = 1 + 0.4 k.
  // c 25 kPa, 18 kN/m^3, a 2 cm edge 1.5 m wide 0.25 m deep: k = atan(12.5)
  // = 1.49097; F = 0.03 (25e3 5.1416 (1 + 0.4 k) + 18e3 0.25) = 6289 N.
  const EdgeResistance r = edge_penetration(soil(0, 25, 18), edge_of(0.02, 1.5, 0.25));
  EXPECT_NEAR(r.force_N, 6289.1, 6289.1 * 1e-3);
  EXPECT_DOUBLE_EQ(r.weight_term_N, 0.0);
}

TEST(EdgePenetration, ShallowEdgeUsesTheLinearDepthFactor) {
  // z < t: k = z / t. phi 30, cohesionless, 16 kN/m^3, z = 1 cm under a
  // 2 cm edge 1 m wide: d_q = 1 + 2 tan30 0.25 0.5 = 1.144338;
  // F = 0.02 (16e3 0.01 18.40 1.144338 + 0.5 16e3 0.02 22.40) = 139.06 N.
  EXPECT_NEAR(edge_penetration(soil(30, 0, 16), edge_of(0.02, 1.0, 0.01)).force_N, 139.06, 139.06 * 2e-3);
}

TEST(EdgePenetration, NothingOutOfTheSoilAndMoreWithDepth) {
  const CuttingSoil sand = soil(35, 0, 15.5);
  EXPECT_EQ(edge_penetration(sand, edge_of(0.02, 1.0, 0.0)).force_N, 0.0);
  EXPECT_EQ(edge_penetration(sand, edge_of(0.02, 1.0, -0.1)).force_N, 0.0);
  EXPECT_EQ(edge_penetration(sand, edge_of(0.0, 1.0, 0.1)).force_N, 0.0);
  double previous = 0.0;
  for (double z = 0.005; z < 1.5; z *= 1.5) {
    const double f = edge_penetration(sand, edge_of(0.02, 1.0, z)).force_N;
    EXPECT_GT(f, previous) << z;
    previous = f;
  }
}

}  // namespace
}  // namespace skidsim::terrain
