// Digging forces against the DEM reference (dem/, scripts/dem_reference.sh):
// the lab-scale LIGGGHTS blade runs in dimensionless form, N = F / (gamma
// d^2 w) at the same d/w, rake and travel over d, beside the earthmoving
// equation and skidsim's push (the calibrated `dem_sand`, a 1 m blade) at
// two cell sizes, with the cost of each push.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "common/physical_constants.h"
#include "io/soil_table.h"
#include "jobs/push_job.h"
#include "report/dem_blades.h"
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {

namespace fs = std::filesystem;

ReportSection digging_dem_section(const ReportContext& ctx) {
  const fs::path dem_dir = repository_dem_dir() / "blade" / "results";
  std::vector<DemBlade> cases = read_dem_blades(dem_dir);
  if (ctx.quick && cases.size() > 1) cases.resize(1);
  const std::vector<double> rungs = ctx.quick ? std::vector<double>{10} : std::vector<double>{10, 20};
  std::vector<Rung> points;
  std::vector<Curve> along;
  std::string rows;
  for (const DemBlade& dem : cases) {
    std::string cells_columns;
    double equation = 0.0, up_equation = 0.0, up_finest = 0.0, heap_finest = 0.0;
    for (const double cells : rungs) {
      const PushResult r = push_like(dem, cells, ctx.work_dir / ("dig_dem_" + fmt("%g", cells)));
      equation = r.n_equation;
      up_equation = r.up_over_draft_equation;
      up_finest = r.up_over_draft;
      heap_finest = r.heap_d2;
      if (cells == rungs.back()) {
        const std::string name = fmt("%g deg", dem.rake_deg) + fmt(" d/w %.1f", dem.depth_m / dem.width_m);
        along.push_back({name + " DEM", dem_n_along(dem_dir, dem), false});
        along.push_back({name + " skidsim", r.n_along, true});
      }
      const double error = 100.0 * std::abs(r.n_mean - dem.n_mean) / dem.n_mean;
      cells_columns += " " + fmt("%.1f", r.n_mean) + " (" + fmt("%+.0f %%", 100.0 * (r.n_mean - dem.n_mean) / dem.n_mean) +
                       ", " + fmt("%.3f", r.cost) + ") |";
      points.push_back({fmt("%g deg", dem.rake_deg) + fmt(" d/w %.1f ", dem.depth_m / dem.width_m) + fmt("%g/m", cells),
                        r.cost, error, ""});
    }
    rows += "| " + fmt("%g deg", dem.rake_deg) + ", " + fmt("%.2f", dem.depth_m / dem.width_m) + " | " +
            fmt("%.1f", dem.n_peak) + " / " + fmt("%.1f", dem.n_mean) + " | " + fmt("%.1f", equation) + " |" +
            cells_columns + " " + fmt("%+.2f", dem.up_over_draft) + " / " + fmt("%+.2f", up_equation) + " / " +
            fmt("%+.2f", up_finest) + " | " + (dem.heap_front_d2 >= 0.0 ? fmt("%.2f", dem.heap_front_d2) : "-") +
            " / " + fmt("%.2f", heap_finest) + " |\n";
  }
  ReportSection out;
  const std::string svg = ctx.svg_name("digging_dem");
  out.svgs.emplace_back(svg, svg_plot("Blade against the DEM: mean resistance", "error against the DEM's mean (%)", points,
                                      "cost: wall s per simulated s (one core)"));
  const std::string svg_along = ctx.svg_name("digging_dem_along");
  out.svgs.emplace_back(svg_along, svg_curves("Blade against the DEM: draft along the push", "travel / d",
                                              "N = F / (gamma d^2 w)", along));
  std::string header = "| rake, d/w | DEM N peak / mean | equation N |";
  std::string rule = "|---|---|---|";
  for (const double cells : rungs) {
    header += " skidsim N mean, " + fmt("%g cells/m", cells) + " (vs DEM, cost) |";
    rule += "---|";
  }
  header += " V / H up: DEM / equation / skidsim " + fmt("%g cells/m", rungs.back()) + " |";
  header += " heap after 1.5 d, w d^2: DEM / skidsim " + fmt("%g cells/m", rungs.back()) + " |";
  rule += "---|---|";
  out.markdown =
      "## Digging forces against the DEM reference\n\n"
      "The LIGGGHTS blade runs of `dem/` (8 mm grains, calibrated first: repose 34.6 deg, phi 38.9 deg, "
      "delta 19.3 deg, 1532 kg/m^3; `dem/README.md`) against skidsim pushing a 1 m blade through the calibrated "
      "`dem_sand` at the same d/w, rake and travel over d, in N = F / (gamma d^2 w); the mean from 2 d of travel "
      "to the end, as the DEM's. The equation is McKyes-Ali's on flat ground (skidsim's start of push meets it within 5 %, "
      "jobs_tests). V / H: the soil's vertical force on the blade (up positive) over the draft, the DEM's means, the "
      "equation's on flat ground, and skidsim's along the push (the engine applies it with the horizontal reaction). "
      "The heap: the soil above the flat bed ahead of the blade after 1.5 d of travel (the DEM's within the blade's "
      "width to 4 d ahead, dem/tools/heap.py; skidsim's in its wedge); the blade has swept 1.5.\n\n" +
      header + "\n" + rule + "\n" + rows + "\n![error against the DEM against cost](" + svg +
      ")\n\n![N along the push: DEM solid, skidsim dashed, " + fmt("%g cells/m", rungs.back()) + "](" + svg_along +
      ")\n\nReading it: on flat ground the equation sits near the DEM at a vertical blade 0.4 as deep as wide and "
      "above it deeper, and gives a raked face far less than the DEM does; skidsim keeps about as much soil heaped "
      "in front as the DEM (more at 60 deg, where the DEM also carries soil on its face), and that heap, taken as "
      "surcharge on the central wedge, lifts its mean above the DEM's in every case. docs/soil_contact.md gives the "
      "equation the DEM's own heap: close at 60 deg, well over at 90 deg. The 15 % the earthmoving issue asks for is "
      "not reached; until it is, the soil table gives the equation only to `dem_sand` and the clays.\n\n";
  return out;
}

}  // namespace skidsim::report::perf
