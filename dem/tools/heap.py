#!/usr/bin/env python3
"""The soil heaped in front of each blade after 1.5 d of travel (stdlib only).

Usage: heap.py RESULTS_DIR MATERIAL_CSV RAW_DIR
  RAW_DIR holds heap_a{rake}_d{mm}mm.dump (blade.in's write_dump after 1.5 d of travel:
  id x y z radius). The blade's geometry is blade.in's: 0.1 m wide, centred on y = 0,
  tip started at x = 0.10 m, at depth d under the nominal bed top 0.12 m.
Writes RESULTS_DIR/heap_summary.csv and RESULTS_DIR/heap_profile_a{rake}_d{mm}mm.csv.

Volumes are bulk volumes: a region's grain volume less what the undisturbed bed holds
under the same ground area (its columns far ahead, x 0.46-0.56 m), over the bed's grain
volume per bulk volume (bulk_density / grain density). Per unit blade width, in d^2:
  front_d2   ahead of the tip's vertical (to 4 d), within the blade's width
  on_face_d2 behind the tip's vertical but in front of the raked face (0 for 90 deg)
  sides_d2   both sides, from the blade's edges out to 1.5 d (the crescents' ground)
  swept_d2   what the blade has swept: 1.5 d * d
The profile: the surface max(z + radius) in 0.25 d bins ahead of the tip within the
blade's width, as (h - H0) / d, H0 the undisturbed bed's surface.
"""
import glob
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dem_io import read_dump, read_material  # noqa: E402

W, XTIP0, HTOP, GRAIN_DENSITY = 0.10, 0.10, 0.12, 2650.0
REF_X = (0.46, 0.56)


def grain_volume(g):
    return 4.0 / 3.0 * math.pi * g["radius"] ** 3


def main():
    res_dir, mat_csv, raw_dir = sys.argv[1:4]
    mat = read_material(mat_csv)
    solid_fraction = mat["bulk_density_kg_m3"] / GRAIN_DENSITY
    rows = []
    for path in sorted(glob.glob(os.path.join(raw_dir, "heap_a*_d*mm.dump"))):
        m = re.search(r"heap_a(\d+)_d(\d+)mm\.dump$", path)
        rake, d = float(m.group(1)), int(m.group(2)) / 1000.0
        grains = read_dump(path)
        x_tip, z_tip = XTIP0 + 1.5 * d, HTOP - d
        sa, ca = math.sin(math.radians(rake)), math.cos(math.radians(rake))
        # Undisturbed bed: grain volume per ground area, and its surface.
        ref = [g for g in grains if REF_X[0] <= g["x"] < REF_X[1] and abs(g["y"]) < 0.14]
        per_area = sum(map(grain_volume, ref)) / ((REF_X[1] - REF_X[0]) * 0.28)
        h0 = sorted(g["z"] + g["radius"] for g in ref)[-len(ref) // 50]  # the top 2 %'s lower edge

        def excess_d2(select, area_m2):
            solid = sum(grain_volume(g) for g in grains if select(g)) - per_area * area_m2
            return solid / solid_fraction / (W * d * d)

        front = excess_d2(lambda g: abs(g["y"]) < W / 2 and x_tip <= g["x"] < x_tip + 4 * d, W * 4 * d)
        # In front of the face plane through the tip, behind the tip's vertical, above the tip.
        on_face = 0.0
        if rake < 90:
            on_face = sum(
                grain_volume(g) for g in grains
                if abs(g["y"]) < W / 2 and g["x"] < x_tip and g["z"] > z_tip
                and (g["x"] - x_tip) * sa + (g["z"] - z_tip) * ca > 0) / solid_fraction / (W * d * d)
        sides = excess_d2(lambda g: W / 2 <= abs(g["y"]) < W / 2 + 1.5 * d and x_tip <= g["x"] < x_tip + 4 * d,
                          2 * 1.5 * d * 4 * d)
        rows.append((rake, d, 1.5 * d, front, on_face, sides, 1.5, h0))
        bins = {}
        for g in grains:
            if abs(g["y"]) < W / 2 and x_tip <= g["x"] < x_tip + 4 * d:
                k = int((g["x"] - x_tip) / (0.25 * d))
                bins[k] = max(bins.get(k, -1.0), g["z"] + g["radius"])
        name = f"heap_profile_a{int(rake)}_d{int(round(d * 1000))}mm.csv"
        with open(os.path.join(res_dir, name), "w") as f:
            f.write("x_ahead_over_d,heap_over_d\n")
            for k in sorted(bins):
                f.write(f"{(k + 0.5) * 0.25:.3f},{(bins[k] - h0) / d:.3f}\n")
        print(f"heap a{rake:g} d{d * 1000:g}mm: front {front:.2f} d^2, on the face {on_face:.2f}, "
              f"sides {sides:.2f}, swept 1.5 d^2")
    with open(os.path.join(res_dir, "heap_summary.csv"), "w") as f:
        f.write("rake_deg,depth_m,travel_m,front_d2,on_face_d2,sides_d2,swept_d2,bed_surface_m\n")
        for r in rows:
            f.write(f"{r[0]:g},{r[1]:.3f},{r[2]:.4f},{r[3]:.3f},{r[4]:.3f},{r[5]:.3f},{r[6]:.1f},{r[7]:.4f}\n")


if __name__ == "__main__":
    main()
