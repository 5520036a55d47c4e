"""Shared by the post-processing scripts: reading LIGGGHTS text dumps and
quantity CSVs, a grain's mass, a layer's depth, a least-squares line, the
inclined layers' thickest open run and a tool's command line (Python 3,
stdlib only)."""
import glob
import math
import os
import sys

RHO_GRAIN = 2650.0  # dem/material.in, particle density (kg/m^3)
D50_M = 0.008       # dem/material.in: radii 3.6 / 4.0 / 4.4 mm
DT_STEP_S = 7.5e-5  # dem/material.in: the timestep (the decks dump every so many steps from step 0)
G = 9.80665         # standard gravity (m/s^2), as the decks and skidsim take it


def grain_mass(r):
    """A sphere of radius r (m) of the grains' material (kg)."""
    return RHO_GRAIN * 4.0 / 3.0 * math.pi * r ** 3



def read_dump_frames(path):
    """The snapshots of a LIGGGHTS text dump, as (timestep, atoms) with the
    atoms as dicts keyed by the dump's column names."""
    frames, cols, section = [], None, None
    with open(path) as f:
        for line in f:
            if line.startswith("ITEM:"):
                section = line.split()[1]
                if section == "ATOMS":
                    cols = line.split()[2:]
                continue
            if section == "TIMESTEP":
                frames.append((int(line), []))
                section = None
            elif section == "ATOMS":
                frames[-1][1].append({c: float(x) for c, x in zip(cols, line.split())})
    return frames


def read_dump(path):
    """The atoms of a LIGGGHTS text dump (every snapshot in it), as dicts
    keyed by the dump's column names."""
    return [a for _, atoms in read_dump_frames(path) for a in atoms]


def depth_98(heights):
    """A layer's depth: the 98th percentile of its grains' centres."""
    z = sorted(heights)
    return z[min(len(z) - 1, int(0.98 * len(z)))]


def read_quantities(path):
    """A quantity,value,unit CSV (the decks' metadata, the calibration's
    results) as {quantity: value text}."""
    out = {}
    for line in open(path):
        p = line.strip().split(",")
        if len(p) >= 2 and p[0] != "quantity":
            out[p[0]] = p[1]
    return out


def read_material(path):
    """dem/calibration/material.csv as {quantity: value}."""
    return {k: float(v) for k, v in read_quantities(path).items()}


def line_fit(points):
    """Least-squares line through (x, y) points: (slope, intercept)."""
    n = len(points)
    mx = sum(p[0] for p in points) / n
    my = sum(p[1] for p in points) / n
    sxx = sum((p[0] - mx) ** 2 for p in points)
    sxy = sum((p[0] - mx) * (p[1] - my) for p in points)
    return sxy / sxx, my - sxy / sxx * mx


def tool_args(tool, pattern):
    """SCRATCH_DIR and RESULTS_DIR from a post-processing tool's command line
    (RESULTS_DIR made), and the runs' metadata files in SCRATCH_DIR matching
    `pattern`, sorted; exits naming the tool where either is missing."""
    if len(sys.argv) != 3:
        raise SystemExit("usage: %s SCRATCH_DIR RESULTS_DIR" % tool)
    scratch, results = sys.argv[1], sys.argv[2]
    os.makedirs(results, exist_ok=True)
    metas = sorted(glob.glob(os.path.join(scratch, pattern)))
    if not metas:
        raise SystemExit("%s: no %s in %s" % (tool, pattern, scratch))
    return scratch, results, metas


def thickest_open_run(chute_rows, base_type):
    """Of the inclined layers (chute_summary.csv rows as dicts of text), the
    run on `base_type` ("1" the grains, "3" the columns' floor) without side
    walls and with the most layers: the friction a thick flow reaches there."""
    runs = [r for r in chute_rows if r["base_type"] == base_type and float(r["side_wall_gap_m"]) == 0.0]
    return max(runs, key=lambda r: int(r["layers"]))
