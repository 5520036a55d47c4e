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
#include "report/perf_report_parts.h"

namespace skidsim::report::perf {
namespace {

namespace fs = std::filesystem;

struct DemBlade {
  double rake_deg = 0.0, depth_m = 0.0, width_m = 0.0, density_kg_m3 = 0.0;
  double n_peak = 0.0, n_mean = 0.0, mean_from_m = 0.0, travel_m = 0.0;
  double up_over_draft = 0.0;  // the mean vertical force (up) over the mean draft
  double heap_front_d2 = -1.0;  // soil heaped ahead of the blade after 1.5 d, over w d^2 (-1: not measured)
};

// A CSV of numbers with a header row, read by column name.
struct CsvNumbers {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name, const fs::path& path) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name) return k;
    throw std::runtime_error("performance report: " + path.string() + " has no column '" + name + "'");
  }
};

CsvNumbers read_csv_numbers(const fs::path& path) {
  std::ifstream in(path);
  if (!in) throw std::runtime_error("performance report: no DEM results at " + path.string());
  CsvNumbers out;
  std::string line;
  std::getline(in, line);
  for (std::stringstream ss(line); std::getline(ss, line, ',');) out.header.push_back(line);
  while (std::getline(in, line)) {
    if (line.empty()) continue;
    std::vector<double> v;
    for (std::stringstream ss(line); std::getline(ss, line, ',');) v.push_back(std::stod(line));
    if (v.size() < out.header.size()) throw std::runtime_error("performance report: short row in " + path.string());
    out.rows.push_back(std::move(v));
  }
  return out;
}

// dem/blade/results/summary.csv, and the heap after 1.5 d of travel from
// heap_summary.csv beside it (dem/tools/heap.py).
std::vector<DemBlade> read_dem_blades(const fs::path& dir) {
  const fs::path summary = dir / "summary.csv", heaps = dir / "heap_summary.csv";
  const CsvNumbers t = read_csv_numbers(summary);
  const auto c = [&](const char* name) { return t.column(name, summary); };
  const std::size_t rake = c("rake_deg"), depth = c("depth_m"), width = c("width_m"), density = c("bulk_density_kg_m3"),
                    peak = c("N_peak"), mean = c("N_mean"), from = c("mean_window_from_m"), travel = c("travel_m"),
                    fx = c("mean_force_x_N"), fz = c("mean_force_z_N");
  const CsvNumbers h = read_csv_numbers(heaps);
  const std::size_t h_rake = h.column("rake_deg", heaps), h_depth = h.column("depth_m", heaps),
                    h_front = h.column("front_d2", heaps);
  std::vector<DemBlade> out;
  for (const std::vector<double>& v : t.rows) {
    DemBlade b{v[rake], v[depth], v[width], v[density], v[peak], v[mean], v[from], v[travel], v[fz] / v[fx], -1.0};
    for (const std::vector<double>& r : h.rows)
      if (std::abs(r[h_rake] - b.rake_deg) < 1e-9 && std::abs(r[h_depth] - b.depth_m) < 1e-6) b.heap_front_d2 = r[h_front];
    out.push_back(b);
  }
  return out;
}

struct PushResult {
  double n_equation = 0.0, n_mean = 0.0, cost = 0.0;
  double up_over_draft_equation = 0.0, up_over_draft = 0.0;  // the face's vertical force (up) over the draft
  double heap_d2 = 0.0;  // the wedge's soil above flat ground after 1.5 d, over w d^2
  std::vector<std::pair<double, double>> n_along;  // (travel / d, N) every 2 cm
};

// skidsim's push of a 1 m blade at the DEM case's d/w and rake, over the same
// travel over d; N's mean over the DEM's window (from the same travel over d).
PushResult push_like(const DemBlade& dem, double cells_per_m, const fs::path& work) {
  const double scale = 1.0 / dem.width_m;  // a 1 m blade
  jobs::PushJob p;
  p.soil_id = "dem_sand";
  p.cutting_model = "earthmoving";
  p.cells_per_m = cells_per_m;
  p.width_m = 1.0;
  p.depth_m = dem.depth_m * scale;
  p.layer_m = 2.0 * p.depth_m + 0.4;
  p.rake_deg = dem.rake_deg;
  p.distance_m = dem.travel_m * scale;
  p.out_dir = work.string();
  if (jobs::run_push_job(p) != 0) throw std::runtime_error("performance report: the DEM-scale push failed");
  const nlohmann::json s = read_summary(work);
  const double gamma_d2_w = s["soil"]["bulk_density_kg_m3"].get<double>() * kGravity_m_s2 * p.depth_m * p.depth_m;
  std::ifstream csv(work / "resistance.csv");
  std::string line;
  std::getline(csv, line);
  PushResult r;
  // distance_m, resistance_N, wedge_weight_N, ..., face_vertical_down_N (the last column)
  double sum = 0.0, sum_down = 0.0, first_weight = -1.0, heap_weight = -1.0;
  int n = 0;
  while (std::getline(csv, line)) {
    std::vector<double> v;
    for (std::stringstream ss(line); std::getline(ss, line, ',');) v.push_back(std::stod(line));
    if (v.size() < 7) throw std::runtime_error("performance report: short row in the push's resistance.csv");
    if (first_weight < 0.0) first_weight = v[2];
    if (heap_weight < 0.0 && v[0] >= 1.5 * p.depth_m - 1e-9) heap_weight = v[2];
    r.n_along.emplace_back(v[0] / p.depth_m, v[1] / gamma_d2_w);
    if (v[0] >= dem.mean_from_m * scale - 1e-9) sum += v[1], sum_down += v[6], ++n;
  }
  r.heap_d2 = (heap_weight - first_weight) / (gamma_d2_w * p.width_m);
  r.up_over_draft = sum > 0.0 ? -sum_down / sum : 0.0;
  r.up_over_draft_equation = -s["reference"]["earthmoving_vertical_down_N"].get<double>() /
                             s["reference"]["earthmoving_N"].get<double>();
  r.n_equation = s["reference"]["earthmoving_N_over_gamma_d2_w"].get<double>();
  r.n_mean = n > 0 ? sum / n / gamma_d2_w : 0.0;
  r.cost = s["performance"]["us_per_step"].get<double>() * 1e-6 / 0.002;
  return r;
}

// The DEM's draft along the travel, N against travel over d
// (blade_a{rake}_d{mm}mm.csv: travel_m, force_x_N, force_z_N).
std::vector<std::pair<double, double>> dem_n_along(const fs::path& dir, const DemBlade& dem) {
  const fs::path path = dir / ("blade_a" + fmt("%g", dem.rake_deg) + "_d" + fmt("%.0f", dem.depth_m * 1000.0) + "mm.csv");
  const CsvNumbers t = read_csv_numbers(path);
  const std::size_t travel = t.column("travel_m", path), fx = t.column("force_x_N", path);
  const double gamma_d2_w = dem.density_kg_m3 * kGravity_m_s2 * dem.depth_m * dem.depth_m * dem.width_m;
  std::vector<std::pair<double, double>> out;
  for (const std::vector<double>& v : t.rows) out.emplace_back(v[travel] / dem.depth_m, v[fx] / gamma_d2_w);
  return out;
}

}  // namespace

ReportSection digging_dem_section(const ReportContext& ctx) {
  const fs::path root = fs::path(io::default_assets_dir()).parent_path();
  const fs::path dem_dir = root / "dem" / "blade" / "results";
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
