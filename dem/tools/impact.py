"""A dense granular jet landing on the floor (dem/collapse/column.in run as a
tall narrow column let go from a height, scripts/dem_reference.sh stage
impact): how much of its fall speed the sheet it sends out keeps (Python 3,
stdlib only).

    impact.py SCRATCH_DIR RESULTS_DIR

Reads column_drop_a<a>.csv and the collapse_drop_a<a>.*.dump frames in
SCRATCH_DIR and writes RESULTS_DIR/impact_summary.csv (quantity,value,unit):
the sheet's speed ratio below, and the jet's deposit measured as the
collapsing columns' are (dem/tools/collapse.py): the column's length at
release (settled, shorter than the deck's nominal H0) over R, its deposit's
edge and r99 beyond R over R, and its final height over R.

Each grain's fall speed V is its free fall from where it was let go to
the floor, sqrt(2 g (z0 - its radius)): the speed a parcel in skidsim lands
with (mean_fall_speed_m_s, over the grains that leave). Their largest
downward speed sampled inside the jet, r < R, every frame, is lower
(mean_sampled_fall_speed_m_s: 2.07 against 3.12 m/s), since the column's
upper grains are slowed by the ones stopping under them before they reach
the floor; it only picks the grains that fell, faster than 1 m/s.
Its sheet speed u is its outward radial speed in the first frame in which
it is beyond 2 R from the axis. The ratio c = sqrt(sum m u^2 / sum m V^2)
over the grains that leave (the share of the landing's kinetic energy the
sheet carries away is c^2): a jet on a plate sends its sheet out at c V,
c = 1 for an ideal fluid (Cheng et al. 2007); grains lose energy in their
collisions and on the floor between R and 2 R (docs/fast_flows.md: what a
landing in skidsim keeps).
"""
import glob
import math
import os
import re
import sys

from collapse import centre_height, front_edge, front_r99, profile
from dem_io import read_dump, read_quantities

MIN_FALL_SPEED_M_S = 1.0  # a grain that fell (the jet lands at 2-3.5 m/s)
GRAVITY_M_S2 = 9.80665  # dem/material.in's


def main():
    scratch, results = sys.argv[1], sys.argv[2]
    meta_paths = glob.glob(os.path.join(scratch, "column_drop_a*.csv"))
    if len(meta_paths) != 1:
        sys.exit("impact.py: expected one column_drop_a*.csv in %s, found %d" % (scratch, len(meta_paths)))
    meta = read_quantities(meta_paths[0])
    tag = re.search(r"column_(drop_a[\d.]+)\.csv$", meta_paths[0]).group(1)
    radius = float(meta["r0_m"])
    frames = sorted(glob.glob(os.path.join(scratch, "collapse_%s.*.dump" % tag)), key=lambda p: int(p.rsplit(".", 2)[1]))
    if len(frames) < 10:
        sys.exit("impact.py: too few frames of %s in %s" % (tag, scratch))
    fall, sheet = {}, {}
    first = last = None
    free_fall = {}
    for path in frames:
        atoms = read_dump(path)
        if first is None:
            first = atoms
            free_fall = {int(a["id"]): math.sqrt(2.0 * GRAVITY_M_S2 * max(a["z"] - a["radius"], 0.0)) for a in atoms}
        last = atoms
        for a in atoms:
            i = int(a["id"])
            r = math.hypot(a["x"], a["y"])
            if r < radius and a["vz"] < 0.0:
                fall[i] = max(fall.get(i, 0.0), -a["vz"])
            if r > 2.0 * radius and i not in sheet and fall.get(i, 0.0) > MIN_FALL_SPEED_M_S:
                m = a["radius"] ** 3  # the grains' density is one
                sheet[i] = (m, (a["x"] * a["vx"] + a["y"] * a["vy"]) / r, free_fall[i], fall[i])
    left = list(sheet.values())
    if not left:
        sys.exit("impact.py: no grain left the jet")
    mass = sum(m for m, _, _, _ in left)
    ratio = math.sqrt(sum(m * u * u for m, u, _, _ in left) / sum(m * v * v for m, _, v, _ in left))
    drop = float(meta["drop_m"])
    length = centre_height(first, False) - drop
    # the deposit's thickness at the column's bulk density as released (its settled length)
    rho_bulk = float(meta["mass_kg"]) / (math.pi * radius ** 2 * length)
    edge0, edge1 = front_edge(profile(first, False, 0.0, rho_bulk)), front_edge(profile(last, False, 0.0, rho_bulk))
    rows = [
        ("jet_radius_m", radius, "m"),
        ("jet_length_m", float(meta["H0_m"]), "m"),
        ("drop_m", drop, "m"),
        ("grains", int(meta["grains"]), "-"),
        ("mean_fall_speed_m_s", sum(v for _, _, v, _ in left) / len(left), "m/s"),
        ("mean_sampled_fall_speed_m_s", sum(s for _, _, _, s in left) / len(left), "m/s"),
        ("grains_beyond_2R", len(left), "-"),
        ("mean_sheet_speed_m_s", sum(m * u for m, u, _, _ in left) / mass, "m/s"),
        ("impact_sheet_speed_ratio", ratio, "-"),
        ("column_length_over_R", length / radius, "-"),
        ("edge_runout_over_R", (edge1 - edge0) / radius, "-"),
        ("r99_runout_over_R", (front_r99(last, False) - front_r99(first, False)) / radius, "-"),
        ("final_height_over_R", centre_height(last, False) / radius, "-"),
    ]
    os.makedirs(results, exist_ok=True)
    with open(os.path.join(results, "impact_summary.csv"), "w") as f:
        f.write("quantity,value,unit\n")
        for q, v, u in rows:
            f.write("%s,%s,%s\n" % (q, ("%.4g" % v) if isinstance(v, float) else v, u))
    print("impact: sheet speed ratio %.3f over %d grains" % (ratio, len(left)))


if __name__ == "__main__":
    main()
