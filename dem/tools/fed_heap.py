"""The fed heap (dem/calibration/fed_heap.in): the slope that carries each
flux (Python 3, stdlib only).

    fed_heap.py SCRATCH_DIR RESULTS_DIR [from_s]

For every fed_heap_Q<Q>.*.dump series in SCRATCH_DIR it writes

  fed_heap_Q<Q>.csv   t_s, tan_slope, mass_kg (one row per dump)

and one row per run in fed_heap_summary.csv, over the frames from `from_s`
seconds on (default 6; experiments/fed_heap.h averages the model's heap
over the same window): the feed Q (m^2/s of bulk soil per metre of width),
the slope's mean tangent, its 5th and 95th percentiles (a slowly fed heap
builds up to the angle at which an avalanche starts and falls to the one
at which it stops: about the two percentiles), the outflow over the
window as a share of the nominal feed (the feed less the mass the heap
gained over the window, from its first and last frames; 1 at steady state,
below 1 where the heap is still building up, as at the slowest feed, whose
avalanches come less often than the window), and the window's length.

The surface: the heap's height in bins of 2 d50 along x is the mass in the
bin spread over the bin at the soil's bulk density (the height a cell of a
height field holds there, as collapse.py's thickness); the slope is the
least-squares line through the bins from 0.08 m off the back wall (past the
feed's landing) to 0.06 m short of the edge (before the brink).
"""
import glob
import math
import os
import re
import sys

from dem_io import D50_M, DT_STEP_S, grain_mass, line_fit, read_dump, read_material

LY_M = 0.048           # fed_heap.in's defaults
L_M = 0.32
X_FROM_M = 0.08
X_TO_M = L_M - 0.06


def frame_of(path):
    return int(path.rsplit(".", 2)[-2])


def surface_tan(atoms, rho_bulk):
    width = 2.0 * D50_M
    nbins = int(round(L_M / width))
    mass = [0.0] * nbins
    for a in atoms:
        k = int(a["x"] / width)
        if 0 <= k < nbins:
            mass[k] += grain_mass(a["radius"])
    pts = [((k + 0.5) * width, m / (rho_bulk * width * LY_M)) for k, m in enumerate(mass)
           if X_FROM_M <= (k + 0.5) * width <= X_TO_M]
    slope, _ = line_fit(pts)
    return -slope


def percentile(values, p):
    v = sorted(values)
    x = p * (len(v) - 1)
    k = int(x)
    return v[k] if k + 1 >= len(v) else v[k] + (x - k) * (v[k + 1] - v[k])


def main():
    scratch, results = sys.argv[1], sys.argv[2]
    from_s = float(sys.argv[3]) if len(sys.argv) > 3 else 6.0
    here = os.path.dirname(os.path.abspath(__file__))
    rho_bulk = read_material(os.path.join(here, "..", "calibration", "material.csv"))["bulk_density_kg_m3"]
    runs = sorted({re.match(r"fed_heap_Q([0-9.e-]+)\.\d+\.dump", os.path.basename(p)).group(1)
                   for p in glob.glob(os.path.join(scratch, "fed_heap_Q*.dump"))}, key=float)
    os.makedirs(results, exist_ok=True)
    summary = ["Q_m2_s,tan_mean,tan_p05,tan_p95,slope_mean_deg,slope_p05_deg,slope_p95_deg,outflow_over_feed,window_s"]
    for q in runs:
        rows = []
        for path in sorted(glob.glob(os.path.join(scratch, "fed_heap_Q%s.*.dump" % q)), key=frame_of):
            atoms = read_dump(path)
            rows.append((frame_of(path) * DT_STEP_S, surface_tan(atoms, rho_bulk), sum(grain_mass(a["radius"]) for a in atoms)))
        with open(os.path.join(results, "fed_heap_Q%s.csv" % q), "w") as f:
            f.write("t_s,tan_slope,mass_kg\n")
            f.writelines("%.4f,%.5f,%.5f\n" % r for r in rows)
        win = [r for r in rows if r[0] >= from_s - 1e-9]
        tans = [r[1] for r in win]
        mean = sum(tans) / len(tans)
        span = win[-1][0] - win[0][0]
        feed = float(q) * LY_M * rho_bulk
        share = (feed - (win[-1][2] - win[0][2]) / span) / feed
        p05, p95 = percentile(tans, 0.05), percentile(tans, 0.95)
        deg = lambda t: math.degrees(math.atan(t))
        summary.append("%s,%.4f,%.4f,%.4f,%.2f,%.2f,%.2f,%.3f,%.2f" % (q, mean, p05, p95, deg(mean), deg(p05), deg(p95),
                                                                       share, span))
    with open(os.path.join(results, "fed_heap_summary.csv"), "w") as f:
        f.write("\n".join(summary) + "\n")
    print("\n".join(summary))


if __name__ == "__main__":
    main()
