#include "experiments/column_collapse.h"
#include "common/physical_constants.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <cmath>
#include <stdexcept>

namespace skidsim::terrain {
namespace {

// dem/tools/collapse.py's thresholds: the edge at a quarter grain of
// thickness, the centre within 1.5 grains of the axis; the grains the
// case's (scaled with r0), else the DEM columns' 8 mm at r0 = 0.1 m.
double grain_m(const CollapseCase& c) {
  return c.momentum_params.grain_diameter_m > 0.0 ? c.momentum_params.grain_diameter_m : 0.008 / 0.1 * c.r0_m;
}

// The domain reaches as far as the DEM deck's (dem/collapse/column.in).
double domain_reach_m(const CollapseCase& c) {
  return c.r0_m * (1.0 + 1.35 * (1.0 + 2.5 * std::sqrt(c.aspect)) + 2.0 * c.drop_over_r0);
}

double distance_m(const GranularGrid& g, const CollapseCase& c, int i, int j) {
  const Eigen::Vector2d p = g.spec().origin_m + g.cell_size_m() * Eigen::Vector2d(i, j);
  return c.slot ? p.x() : p.norm();
}

// The grid, with the column standing on it unless `empty`.
GranularGrid column_grid(const CollapseCase& c, const SoilFlowParameters& soil, bool empty = false) {
  if (!(c.aspect > 0.0 && c.r0_m > 0.0 && c.cell_m > 0.0 && c.cell_m < c.r0_m && c.drop_over_r0 >= 0.0))
    throw std::invalid_argument("column collapse: aspect, r0_m and cell_m must be > 0, cell_m below r0_m, drop_over_r0 >= 0");
  if (c.drop_over_r0 > 0.0 && c.slot) throw std::invalid_argument("column collapse: a dropped column is a tube");
  const double reach = domain_reach_m(c);
  GridSpec spec;
  spec.cell_size_m = c.cell_m;
  if (c.slot) {
    spec.nx = static_cast<int>(std::ceil(reach / c.cell_m));
    spec.ny = 1;
    spec.origin_m = Eigen::Vector2d(0.5 * c.cell_m, 0.0);  // the wall at x = 0
  } else {
    const int half = static_cast<int>(std::ceil(reach / c.cell_m));
    spec.nx = spec.ny = 2 * half + 1;  // the axis on the middle cell's centre
    spec.origin_m = Eigen::Vector2d::Constant(-half * c.cell_m);
  }
  GranularGrid g(spec, soil, c.step_dt_s, 100000);
  if (empty) return g;
  const double h0 = c.aspect * c.r0_m;
  for (int j = 0; j < spec.ny; ++j)
    for (int i = 0; i < spec.nx; ++i)
      if (distance_m(g, c, i, j) < c.r0_m) g.set_material_m(i, j, h0);
  return g;
}

}  // namespace

std::vector<double> radial_volumes_m3(const GranularGrid& g, const CollapseCase& c, std::vector<double>* area_m2) {
  // Bins along the distance from the axis (or wall), d wide, a cell in the
  // bin of its centre.
  const double d = g.cell_size_m();
  const int bins = static_cast<int>(std::ceil(domain_reach_m(c) * (c.slot ? 1.0 : std::sqrt(2.0)) / d)) + 2;
  std::vector<double> volume(bins, 0.0);
  if (area_m2) area_m2->assign(bins, 0.0);
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i) {
      const int k = std::min(bins - 1, static_cast<int>(distance_m(g, c, i, j) / d));
      volume[k] += g.material_m(i, j) * d * d;
      if (area_m2) (*area_m2)[k] += d * d;
    }
  return volume;
}

CollapseFrame measure_collapse(const GranularGrid& g, const CollapseCase& c, double t_s) {
  // The mass in each bin and the area it spreads over (the cells' own, so a
  // bin's thickness is the mean column height there).
  const double d = g.cell_size_m();
  std::vector<double> area;
  const std::vector<double> volume = radial_volumes_m3(g, c, &area);
  const int bins = static_cast<int>(volume.size());
  const double grain = grain_m(c);
  CollapseFrame f;
  f.t_s = t_s;
  double total = 0.0;
  for (double v : volume) total += v;
  for (int j = 0; j < g.ny(); ++j)
    for (int i = 0; i < g.nx(); ++i)
      if (distance_m(g, c, i, j) <= std::max(1.5 * grain, 0.5 * d)) f.centre_height_m = std::max(f.centre_height_m, g.material_m(i, j));
  if (!c.slot) {
    // The deposit's reach along the grid's axes and its diagonals from the
    // axis cell (the column stands centred on a cell): the farthest cell at
    // least the edge's thickness, the larger of each direction's four.
    const int ic = g.nx() / 2, jc = g.ny() / 2;
    for (int dir = 0; dir < 8; ++dir) {
      const int di = (dir < 4 ? (dir == 0) - (dir == 1) : (dir % 2 == 0 ? 1 : -1));
      const int dj = (dir < 4 ? (dir == 2) - (dir == 3) : (dir < 6 ? 1 : -1));
      for (int n = 1; g.contains(ic + n * di, jc + n * dj); ++n)
        if (g.material_m(ic + n * di, jc + n * dj) >= 0.25 * grain)
          (dir < 4 ? f.edge_along_axes_m : f.edge_along_diagonals_m) =
              std::max(dir < 4 ? f.edge_along_axes_m : f.edge_along_diagonals_m, distance_m(g, c, ic + n * di, jc + n * dj));
    }
  }
  double acc = 0.0;
  bool found = false;
  for (int k = 0; k < bins; ++k) {
    if (!found && acc + volume[k] >= 0.99 * total && volume[k] > 0.0) {
      f.front_r99_m = d * (k + (0.99 * total - acc) / volume[k]);  // linear within the bin
      found = true;
    }
    acc += volume[k];
    if (area[k] > 0.0 && volume[k] / area[k] >= 0.25 * grain) f.front_edge_m = d * (k + 1);
  }
  return f;
}

double published_runout_over_r0(double aspect) { return aspect < 1.7 ? 1.24 * aspect : 1.6 * std::sqrt(aspect); }

CollapseCase laboratory_column_case(double aspect, double cell_m) {
  CollapseCase c;  // defaults: r0 = 1 m, the soil's own grains, its bed's friction on the floor
  c.aspect = aspect;
  c.cell_m = cell_m;
  c.momentum = true;
  return c;
}

CollapseRun run_column_collapse(const CollapseCase& c, const SoilFlowParameters& soil) {
  CollapseRun run;
  run.c = c;
  const bool dropped = c.drop_over_r0 > 0.0;
  GranularGrid g = column_grid(c, soil, dropped);
  const double h0 = c.aspect * c.r0_m;
  const double t_scale = std::sqrt(h0 / kGravity_m_s2);
  const double max_time = c.max_time_s > 0.0 ? c.max_time_s : 40.0 * t_scale + std::sqrt(2.0 * c.drop_over_r0 * c.r0_m / kGravity_m_s2);
  const double frame_dt = c.frame_dt_s > 0.0 ? c.frame_dt_s : 0.1 * t_scale;
  const int max_steps = static_cast<int>(std::ceil(max_time / c.step_dt_s));
  const int frame_every = std::max(1, static_cast<int>(std::lround(frame_dt / c.step_dt_s)));
  std::unique_ptr<MomentumFlow> flow;
  if (c.momentum) {
    MomentumFlowParameters p = c.momentum_params;
    if (c.slot && c.slot_wall_friction_deg > 0.0) {
      p.side_wall_gap_m = c.slot_gap_over_r0 * c.r0_m;
      p.side_wall_friction_deg = c.slot_wall_friction_deg;
    }
    flow = std::make_unique<MomentumFlow>(g, p, c.step_dt_s);
    flow->wake_all(g);
  }
  // A dropped column: the same column as parcels, slabs of half a cell, at
  // rest drop_over_r0 r0 above the floor; measured as released on the floor.
  std::unique_ptr<MaterialExchange> exchange;
  std::int64_t released = 0;
  CollapseFrame as_released;
  if (!dropped) as_released = measure_collapse(g, c, 0.0);
  if (dropped) {
    const GranularGrid standing = column_grid(c, soil);
    as_released = measure_collapse(standing, c, 0.0);
    const int slabs = std::max(1, static_cast<int>(std::ceil(h0 / (0.5 * c.cell_m))));
    // Room for every parcel: one that finds none lands at once, unfallen.
    std::size_t parcels = 0;
    for (int cell = 0; cell < g.nx() * g.ny(); ++cell) parcels += standing.material_quanta(cell % g.nx(), cell / g.nx()) > 0 ? slabs : 0;
    exchange = std::make_unique<MaterialExchange>(&g, c.step_dt_s, parcels);
    exchange->set_ground_flow(flow.get());
    for (int j = 0; j < g.ny(); ++j)
      for (int i = 0; i < g.nx(); ++i) {
        const std::int64_t q = standing.material_quanta(i, j);
        if (q == 0) continue;
        const Eigen::Vector2d p = g.spec().origin_m + c.cell_m * Eigen::Vector2d(i, j);
        for (int k = 0; k < slabs; ++k) {
          const std::int64_t part = q * (k + 1) / slabs - q * k / slabs;
          const double z = c.drop_over_r0 * c.r0_m + (k + 0.5) * h0 / slabs;
          exchange->release(Eigen::Vector3d(p.x(), p.y(), z), Eigen::Vector3d::Zero(), part);
          released += part;
        }
      }
  }
  auto books = [&] {
    return g.ledger().balanced() && (!exchange || exchange->total_quanta() == released);
  };
  run.books_exact = books();
  run.frames.push_back(as_released);
  run.t_stop_s = max_time;
  const auto t0 = std::chrono::steady_clock::now();
  int s = 0;
  while (s < max_steps) {
    if (flow) flow->step(g);
    g.step();
    if (exchange) exchange->step();
    ++s;
    if (s % frame_every == 0) {
      run.frames.push_back(measure_collapse(g, c, s * c.step_dt_s));
      run.books_exact = run.books_exact && books();
    }
    if (g.at_rest() && (!flow || flow->at_rest()) && (!exchange || exchange->parcels().empty())) {
      run.at_rest = true;
      run.t_stop_s = s * c.step_dt_s;
      break;
    }
  }
  run.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  run.steps = s;
  run.flow_at_rest = !flow || flow->at_rest();
  run.final_state = measure_collapse(g, c, s * c.step_dt_s);
  run.deposit_volume_m3 = radial_volumes_m3(g, c, nullptr);
  run.books_exact = run.books_exact && books();
  const CollapseFrame& first = run.frames.front();
  run.runout_over_r0 = (run.final_state.front_r99_m - first.front_r99_m) / c.r0_m;
  run.edge_runout_over_r0 = (run.final_state.front_edge_m - first.front_edge_m) / c.r0_m;
  run.final_height_over_r0 = run.final_state.centre_height_m / first.centre_height_m * c.aspect;
  return run;
}

}  // namespace skidsim::terrain
