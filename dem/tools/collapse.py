"""Collapsing columns (dem/collapse/column.in): the front against time and the
final deposit of each run, from its position dumps (Python 3, stdlib only).

    collapse.py SCRATCH_DIR RESULTS_DIR

For every column_<geom>_a<a>.csv in SCRATCH_DIR (written by the deck before the
release) and its collapse_<geom>_a<a>.*.dump frames it writes

  front_<geom>_a<a>.csv    t_s, front_r99_m, front_edge_m, centre_height_m,
                           kinetic_energy_J (one row per dump)
  deposit_<geom>_a<a>.csv  r_m, thickness_m, top_m (the final frame)

and one row per run in summary.csv (slot: 1 for the slot, 0 for the tube and the
dropped column; drop_m: how far the column fell before it landed, 0 for those
standing on the floor; numbers only, as the performance report reads it). The distance r is from the column's axis
(tube) or from the back wall (slot). Definitions, chosen so a continuum model's
cells can be measured the same way:

  front_r99     the distance within which 99 % of the mass lies (stray grains
                that bounce ahead do not move it)
  front_edge    the outer edge of the deposit: the farthest bin of width d50
                whose mass, spread at the column's bulk density, is at least a
                quarter of d50 thick (a sparse layer of grains)
  thickness     the mass in a bin spread over the bin at the column's bulk
                density: the height a cell of a height field holds there
  centre height the top of the grains (z + radius) within 1.5 d50 of the axis
                or of the back wall
  t_stop        when the kinetic energy falls below 1e-3 of its peak

The run-out is (front - front at release) / r0 and the final height
H_inf / r0, the dimensionless forms of Lajeunesse et al. (2004) and Lube et
al. (2004). Both are taken against the column as released: the run-out from
the front at release (the grains' centres stand half a grain inside the
tube), the heights as the top grains' centres (the centre height less half
a grain, at release and at the end alike: the surface's roughness is the
same grains'). The column's released height H (its top grains' centres at
release) gives the released aspect ratio H / r0, which a model compares at,
the bulk density (the mass over the column's volume up to H) and the time
scale sqrt(H / g) (t_stop_over_sqrt_H0_g). A column that settled more than a
grain short of the deck's H0 is reported on stderr: it is still a column,
of its released aspect ratio.
"""
import glob
import math
import os
import sys

from dem_io import D50_M, DT_STEP_S, G, grain_mass, read_dump, read_quantities, tool_args


def distance(atom, slot):
    return atom["x"] if slot else math.hypot(atom["x"], atom["y"])


def bin_area(r_lo, r_hi, slot, width):
    if slot:
        return (r_hi - r_lo) * width
    return math.pi * (r_hi ** 2 - r_lo ** 2)


def profile(atoms, slot, width, rho_bulk):
    """Equivalent thickness and top per bin of width d50 from the axis or wall."""
    bins = {}
    for a in atoms:
        if a["z"] > 2.0:
            continue  # a grain thrown out of the domain would not be here; guard anyway
        k = int(distance(a, slot) / D50_M)
        m, top = bins.get(k, (0.0, 0.0))
        bins[k] = (m + grain_mass(a["radius"]), max(top, a["z"] + a["radius"]))
    rows = []
    for k in range(0, max(bins) + 1 if bins else 0):
        m, top = bins.get(k, (0.0, 0.0))
        area = bin_area(k * D50_M, (k + 1) * D50_M, slot, width)
        rows.append(((k + 0.5) * D50_M, m / (rho_bulk * area), top))
    return rows


def front_r99(atoms, slot):
    pairs = sorted((distance(a, slot), grain_mass(a["radius"])) for a in atoms)
    total = sum(m for _, m in pairs)
    acc = 0.0
    for r, m in pairs:
        acc += m
        if acc >= 0.99 * total:
            return r
    return pairs[-1][0] if pairs else 0.0


def front_edge(rows):
    edge = 0.0
    for r, thick, _ in rows:
        if thick >= 0.25 * D50_M:
            edge = r + 0.5 * D50_M
    return edge


def centre_height(atoms, slot):
    tops = [a["z"] + a["radius"] for a in atoms if distance(a, slot) <= 1.5 * D50_M]
    return max(tops) if tops else 0.0


def kinetic_energy(atoms):
    return sum(0.5 * grain_mass(a["radius"]) * (a["vx"] ** 2 + a["vy"] ** 2 + a["vz"] ** 2) for a in atoms)


def post_run(scratch, results, meta_path):
    meta = read_quantities(meta_path)
    geom = meta["geometry"]
    aspect = meta["aspect_ratio"]
    slot = geom == "slot"
    r0 = float(meta["r0_m"])
    h0 = float(meta["H0_m"])
    width = float(meta["slot_width_m"])
    drop = float(meta.get("drop_m", 0.0))
    mass = float(meta["mass_kg"])
    frames = sorted(glob.glob(os.path.join(scratch, "collapse_%s_a%s.*.dump" % (geom, aspect))),
                    key=lambda p: int(p.rsplit(".", 2)[1]))
    if not frames:
        raise SystemExit("collapse.py: no dumps for %s a %s in %s" % (geom, aspect, scratch))
    # the column as released (the first frame): its top grains' centres, a dropped column's above its shelf
    released = read_dump(frames[0])
    released_h = centre_height(released, slot) - drop - 0.5 * D50_M
    if released_h < h0 - D50_M:
        sys.stderr.write("collapse.py: %s a %s: the column stands %.4f m at release, %.4f m short of H0; "
                         "it is compared at its released aspect ratio %.3f (dem/collapse/column.in fills it)\n"
                         % (geom, aspect, released_h, h0 - released_h, released_h / r0))
    column_volume = r0 * width * released_h if slot else math.pi * r0 ** 2 * released_h
    rho_bulk = mass / column_volume
    series = []
    for k, path in enumerate(frames):
        step = int(path.rsplit(".", 2)[1])
        atoms = released if k == 0 else read_dump(path)
        rows = profile(atoms, slot, width, rho_bulk)
        series.append((step, front_r99(atoms, slot), front_edge(rows), centre_height(atoms, slot),
                       kinetic_energy(atoms)))
        last_rows = rows
    tag = "%s_a%s" % (geom, aspect)
    with open(os.path.join(results, "front_%s.csv" % tag), "w") as f:
        f.write("t_s,front_r99_m,front_edge_m,centre_height_m,kinetic_energy_J\n")
        for step, r99, edge, hc, ke in series:
            f.write("%.4f,%.5f,%.5f,%.5f,%.6g\n" % (step * DT_STEP_S, r99, edge, hc, ke))
    with open(os.path.join(results, "deposit_%s.csv" % tag), "w") as f:
        f.write("r_m,thickness_m,top_m\n")
        for r, thick, top in last_rows:
            f.write("%.4f,%.5f,%.5f\n" % (r, thick, top))
    # the kinetic energy rises to its peak as the column falls, then dies out
    peak = max(s[4] for s in series)
    i_peak = max(range(len(series)), key=lambda i: series[i][4])
    t_stop = next((series[i][0] * DT_STEP_S for i in range(i_peak, len(series)) if series[i][4] < 1e-3 * peak),
                  float("nan"))
    first, final = series[0], series[-1]
    return {
        "slot": 1 if slot else 0, "drop_m": drop, "aspect_ratio": float(aspect), "r0_m": r0, "H0_m": h0,
        "released_height_m": released_h, "released_aspect": released_h / r0,
        "slot_width_m": width if slot else 0.0,
        "grains": int(float(meta["grains"])), "mass_kg": mass, "bulk_density_kg_m3": rho_bulk,
        "runout_r99_m": final[1], "runout_edge_m": final[2], "final_height_m": final[3],
        "runout_r99_rel": (final[1] - first[1]) / r0, "runout_edge_rel": (final[2] - first[2]) / r0,
        "final_height_rel": (final[3] - 0.5 * D50_M) / r0, "t_stop_s": t_stop,
        "t_stop_over_sqrt_H0_g": t_stop / math.sqrt(released_h / G),
        "end_kinetic_over_peak": final[4] / peak,
    }


def main():
    scratch, results, metas = tool_args("collapse.py", "column_*_a*.csv")
    rows = [post_run(scratch, results, m) for m in metas]
    keys = list(rows[0].keys())
    with open(os.path.join(results, "summary.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for r in sorted(rows, key=lambda r: (r["slot"], r["drop_m"], r["aspect_ratio"])):
            f.write(",".join(("%.6g" % v) if isinstance(v, float) else str(v) for v in (r[k] for k in keys)) + "\n")


if __name__ == "__main__":
    main()
