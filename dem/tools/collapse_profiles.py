"""The collapsing tubes' velocity through their depth, from the position and
velocity dumps of dem/collapse/column.in (Python 3, stdlib only): where the
grains slide on the floor and where they have come to rest under the grains
still running, for a depth-averaged model's basal friction and deposition to
be checked against (docs/fast_flows.md, "The flow on its own cells, taken
further").

    collapse_profiles.py SCRATCH_DIR RESULTS_DIR

For every tube standing on the floor (column_tube_a<a>.csv in SCRATCH_DIR) it
writes profile_tube_a<a>.csv, one row per dump frame and ring 0.2 r0 wide
holding at least 30 grains whose top moves at 0.05 m/s or more:

  t_s             the frame's time from the release
  r_from_over_r0, r_to_over_r0
                  the ring, from the column's axis
  depth_grains    the 98th percentile of the grains' centres above the floor,
                  over d50
  base_m_s        the mean radial velocity of the grains whose centres lie in
                  the lowest d50 (the layer on the floor)
  top_m_s         the same above 0.6 of the depth
  rest_layers     how many layers d50 thick, from the floor up, move along
                  the radius, either way, at under a tenth of the top's
                  speed (grains come to rest there)

and one row per tube in profile_summary.csv: the mean of base / top over the
rings behind each frame's outermost ring (behind_base_over_top) and over the
outermost rings (front_base_over_top), and the mean share of the depth at
rest behind the front (behind_rest_share).
"""
import glob
import math
import os
import sys

from dem_io import D50_M, DT_STEP_S, depth_98, read_dump, read_quantities

RING_R0 = 0.2        # ring width over r0
MIN_GRAINS = 30
MOVING_M_S = 0.05    # a ring whose top moves slower is at rest
REST_SHARE = 0.1     # a layer under this share of the top's speed is at rest


def mean(values):
    return sum(values) / len(values) if values else float("nan")


def rings(atoms, r0):
    """Per ring index: the grains' (height, radial velocity)."""
    out = {}
    for a in atoms:
        r = math.hypot(a["x"], a["y"])
        ur = (a["x"] * a["vx"] + a["y"] * a["vy"]) / r if r > 0.0 else 0.0
        out.setdefault(int(r / (RING_R0 * r0)), []).append((a["z"], ur))
    return out


def ring_row(grains):
    """(depth over d50, base, top, layers at rest) of one ring, or None where
    its top does not move."""
    depth = depth_98(z for z, _ in grains)
    top = mean([u for z, u in grains if z > 0.6 * depth])
    base = mean([u for z, u in grains if z < D50_M])
    if not top >= MOVING_M_S or math.isnan(base):
        return None
    rest = 0
    for k in range(int(depth / D50_M) + 1):
        layer = [u for z, u in grains if k * D50_M <= z < (k + 1) * D50_M]
        if not layer or abs(mean(layer)) >= REST_SHARE * top:
            break
        rest += 1
    return depth / D50_M, base, top, rest


def post_tube(scratch, results, meta_path):
    meta = read_quantities(meta_path)
    aspect, r0 = meta["aspect_ratio"], float(meta["r0_m"])
    frames = sorted(glob.glob(os.path.join(scratch, "collapse_tube_a%s.*.dump" % aspect)),
                    key=lambda p: int(p.rsplit(".", 2)[1]))
    if not frames:
        raise SystemExit("collapse_profiles.py: no dumps for the tube a %s in %s" % (aspect, scratch))
    behind, front, rest_share = [], [], []
    with open(os.path.join(results, "profile_tube_a%s.csv" % aspect), "w") as f:
        f.write("t_s,r_from_over_r0,r_to_over_r0,depth_grains,base_m_s,top_m_s,rest_layers\n")
        for path in frames:
            t = int(path.rsplit(".", 2)[1]) * DT_STEP_S
            by_ring = rings(read_dump(path), r0)
            rows = []
            for k in sorted(by_ring):
                if len(by_ring[k]) < MIN_GRAINS:
                    continue
                row = ring_row(by_ring[k])
                if row is None:
                    continue
                rows.append((k, row))
                depth, base, top, rest = row
                f.write("%.3f,%.1f,%.1f,%.2f,%.4f,%.4f,%d\n" % (t, k * RING_R0, (k + 1) * RING_R0, depth, base, top, rest))
            for n, (k, (depth, base, top, rest)) in enumerate(rows):
                if n + 1 < len(rows):
                    behind.append(base / top)
                    rest_share.append(rest / depth)
                else:
                    front.append(base / top)
    return "%s,%g,%.4g,%.4g,%.4g" % (aspect, r0, mean(behind), mean(front), mean(rest_share))


def main():
    if len(sys.argv) != 3:
        raise SystemExit("usage: collapse_profiles.py SCRATCH_DIR RESULTS_DIR")
    scratch, results = sys.argv[1], sys.argv[2]
    os.makedirs(results, exist_ok=True)
    metas = [m for m in sorted(glob.glob(os.path.join(scratch, "column_tube_a*.csv")))
             if float(read_quantities(m).get("drop_m", "0")) == 0.0]
    if not metas:
        raise SystemExit("collapse_profiles.py: no column_tube_*.csv in %s" % scratch)
    rows = [post_tube(scratch, results, m) for m in metas]
    with open(os.path.join(results, "profile_summary.csv"), "w") as f:
        f.write("aspect_ratio,r0_m,behind_base_over_top,front_base_over_top,behind_rest_share\n")
        for row in sorted(rows, key=lambda r: float(r.split(",")[0])):
            f.write(row + "\n")


if __name__ == "__main__":
    main()
