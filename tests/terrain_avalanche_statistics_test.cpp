// Avalanche sizes follow a power law (thesis 4.4.5, fig. 4.10: r = 0.985):
// material dropped at random on a pile at its critical state sets off
// avalanches whose frequency falls as a power of their size.
//
// The statistics of 4.4.5 belong to the model of 4.3-4.4: no inertia
// (alpha_I = alpha) and no minimum flowing layer (h_stop = 0). The full model
// is measured too and reported, not asserted: with inertia, running material
// keeps flowing down slopes at alpha_I and avalanches acquire a typical size
// (Prado and Olami 1992 report the same loss of scale invariance).
#include <gtest/gtest.h>

#include <map>
#include <vector>

#include "tests/test_support.h"

namespace skidsim::terrain {
namespace {

using testing::kDt;

struct PowerLawFit {
  std::size_t avalanches = 0;
  double exponent = 0.0;     // log-log slope of frequency per unit size
  double correlation = 0.0;  // of that regression
  std::size_t octaves = 0;
};

PowerLawFit avalanche_statistics(const SoilFlowParameters& soil) {
  const int n = 40;
  const double cell = 0.05;
  GranularGrid g(testing::square_spec(n, cell, EdgeKind::kOpen), soil, kDt);
  // A pyramid just under the repose angle, draining over open edges.
  const double tan_alpha = std::tan(soil.repose_angle_deg * testing::kPi / 180.0);
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int edge_distance = std::min(std::min(i, j), std::min(n - 1 - i, n - 1 - j));
      g.set_material_m(i, j, 0.98 * tan_alpha * cell * (edge_distance + 1));
    }
  testing::settle(g, 100000);

  std::uint64_t rng = 7;
  const auto next = [&rng] {
    rng = rng * 6364136223846793005ull + 1442695040888963407ull;
    return rng >> 33;
  };
  // Random amounts (up to 1 cm of height) dropped on random cells; the size
  // of an avalanche is its area: the cells whose material changed, other than
  // the one the drop fell on, until the pile is at rest again.
  std::map<int, double> octave_counts;  // sizes in [2^k, 2^(k+1))
  PowerLawFit fit;
  std::vector<std::int64_t> before(static_cast<std::size_t>(n) * n);
  for (int drop = 0; drop < 20000; ++drop) {
    for (int c = 0; c < n * n; ++c) before[static_cast<std::size_t>(c)] = g.material_quanta(c % n, c / n);
    const int di = static_cast<int>(next() % n), dj = static_cast<int>(next() % n);
    g.add_material_m3(di, dj, 0.01 * cell * cell * static_cast<double>(next() % 1000 + 1) / 1000.0);
    while (!g.at_rest()) g.step();
    std::int64_t size = 0;
    for (int c = 0; c < n * n; ++c)
      size += c != g.index(di, dj) && g.material_quanta(c % n, c / n) != before[static_cast<std::size_t>(c)];
    if (drop > 4000 && size > 0) {  // after the transient
      octave_counts[static_cast<int>(std::floor(std::log2(static_cast<double>(size))))] += 1.0;
      ++fit.avalanches;
    }
  }
  EXPECT_TRUE(g.ledger().balanced());

  std::vector<double> xs, ys;
  for (const auto& [k, count] : octave_counts) {
    if (count < 5) continue;  // too few to estimate a frequency
    xs.push_back(std::log(std::pow(2.0, k + 0.5)));
    ys.push_back(std::log(count / std::pow(2.0, k)));
  }
  const double m = static_cast<double>(xs.size());
  double sx = 0, sy = 0, sxx = 0, syy = 0, sxy = 0;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    sx += xs[k]; sy += ys[k]; sxx += xs[k] * xs[k]; syy += ys[k] * ys[k]; sxy += xs[k] * ys[k];
  }
  fit.octaves = xs.size();
  fit.exponent = (m * sxy - sx * sy) / (m * sxx - sx * sx);
  fit.correlation = (m * sxy - sx * sy) / std::sqrt((m * sxx - sx * sx) * (m * syy - sy * sy));
  return fit;
}

TEST(AvalancheStatistics, SizesFollowAPowerLaw) {
  SoilFlowParameters base_model;  // the model of 4.3-4.4
  base_model.stop_angle_deg = base_model.repose_angle_deg;
  base_model.min_flow_layer_m = 0.0;
  const PowerLawFit fit = avalanche_statistics(base_model);
  std::printf("model of 4.3: %zu avalanches over %zu octaves, exponent %.3f, correlation %.4f\n", fit.avalanches,
              fit.octaves, fit.exponent, fit.correlation);
  RecordProperty("power_law_exponent", std::to_string(fit.exponent));
  RecordProperty("power_law_correlation", std::to_string(fit.correlation));
  EXPECT_GE(fit.octaves, 4u);
  EXPECT_LT(fit.exponent, -1.0);
  EXPECT_LT(fit.correlation, -0.95);  // issue tolerance; the thesis measured 0.985

  const PowerLawFit full = avalanche_statistics(SoilFlowParameters{});
  std::printf("full model (inertia, h_stop): exponent %.3f, correlation %.4f (reported only)\n", full.exponent,
              full.correlation);
  RecordProperty("full_model_correlation", std::to_string(full.correlation));
}

}  // namespace
}  // namespace skidsim::terrain
