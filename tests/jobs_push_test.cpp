// The push job (jobs/push_job) with the earthmoving equation: for every soil
// of the shipped table, a vertical and a raked blade at two depths and two
// cell sizes start within 5 % of the equation evaluated here from the
// table's parameters (terrain/earthmoving, itself checked against Rankine's
// and Coulomb's passive pressures in terrain_earthmoving_test).
#include "common/physical_constants.h"
#include "io/atomic_file.h"
#include "io/soil_table.h"
#include "jobs/push_job.h"
#include "terrain/earthmoving.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <filesystem>
#include <fstream>
#include <string>

namespace skidsim::jobs {
namespace {

namespace fs = std::filesystem;

double equation_N(const io::SoilRecord& soil, double depth_m, double width_m, double rake_deg) {
  terrain::CuttingSoil s;
  s.unit_weight_N_per_m3 = soil.flow.bulk_density_kg_m3 * kGravity_m_s2;
  s.cohesion_Pa = 1000.0 * soil.terramechanics.cohesion_kPa;
  s.friction_angle_rad = deg_to_rad(soil.terramechanics.friction_angle_deg);
  s.tool_adhesion_Pa = 1000.0 * soil.terramechanics.tool_adhesion_kPa;
  s.tool_friction_angle_rad = deg_to_rad(soil.terramechanics.tool_friction_angle_deg);
  terrain::CuttingTool t;
  t.depth_m = depth_m;
  t.width_m = width_m;
  t.rake_rad = deg_to_rad(rake_deg);
  return terrain::mckyes_ali(s, t).horizontal_N;
}

TEST(PushJob, StartOfPushMeetsTheEarthmovingEquationForEverySoil) {
  const io::SoilTable table = io::load_soil_table(io::default_soil_table_path());
  ASSERT_GE(table.size(), 5u);
  const fs::path out = fs::temp_directory_path() / "skidsim_jobs_push_test";
  for (const auto& [id, soil] : table)
    for (double cells_per_m : {10.0, 20.0})
      for (double rake_deg : {90.0, 60.0})
        for (double depth_m : {0.1, 0.2}) {
          fs::remove_all(out);
          PushJob job;
          job.soil_id = id;
          job.cells_per_m = cells_per_m;
          job.layer_m = 0.5;
          job.depth_m = depth_m;
          job.width_m = 0.6;
          job.rake_deg = rake_deg;
          job.cutting_model = "earthmoving";
          job.distance_m = 0.02;
          job.out_dir = out.string();
          ASSERT_EQ(run_push_job(job), 0);
          const nlohmann::json summary = nlohmann::json::parse(std::ifstream(out / "summary.json"));
          const double start = summary["result"]["resistance_at_start_N"].get<double>();
          const double expected = equation_N(soil, depth_m, 0.6, rake_deg);
          EXPECT_NEAR(start, expected, 0.05 * expected)
              << id << ", " << cells_per_m << " cells/m, rake " << rake_deg << ", depth " << depth_m;
          EXPECT_EQ(summary["cutting_model"], "earthmoving");
        }
  fs::remove_all(out);
}

TEST(PushJob, RefusesARakeOutOfRangeAndAnUnknownModel) {
  PushJob job;
  job.rake_deg = 5.0;
  EXPECT_THROW(run_push_job(job), io::InputError);
  job.rake_deg = 60.0;
  job.cutting_model = "bulldozer";
  EXPECT_THROW(run_push_job(job), io::InputError);
}

}  // namespace
}  // namespace skidsim::jobs
