#!/usr/bin/env python3
"""Angle of repose from the final heap (stdlib only).

Usage: repose.py pile_final.dump out.csv

Reads the LIGGGHTS text dump (columns id type x y z radius), keeps the grains
on the pedestal (z > -0.002 m, r < 0.15 m), builds the surface profile
h(r) = max(z + radius) in radial bins of 5 mm (r measured from the heap's
centroid), and fits a straight line by least squares to the profile points
between 20 % and 80 % of the heap height. The angle of repose is atan(-slope).
The fit is also made on the 4 azimuthal quadrants separately (10 mm bins, so
that every bin holds a surface grain); their mean and spread are reported.
"""
import math
import sys

from dem_io import line_fit, read_dump


def profile(grains, cx, cy, nb=30, dr=0.005, sector=None, nsec=8):
    h = [None] * nb
    for g in grains:
        dx, dy = g["x"] - cx, g["y"] - cy
        if sector is not None:
            a = math.atan2(dy, dx) % (2 * math.pi)
            if int(a / (2 * math.pi / nsec)) != sector:
                continue
        r = math.hypot(dx, dy)
        k = int(r / dr)
        if k >= nb:
            continue
        top = g["z"] + g["radius"]
        if h[k] is None or top > h[k]:
            h[k] = top
    return [((k + 0.5) * dr, h[k]) for k in range(nb) if h[k] is not None]


def angle(prof, lo=0.2, hi=0.8):
    H = max(z for _, z in prof)
    pts = [(r, z) for r, z in prof if lo * H <= z <= hi * H]
    if len(pts) < 3:
        return float("nan"), H, len(pts)
    slope, _ = line_fit(pts)
    return math.degrees(math.atan(-slope)), H, len(pts)


def main():
    grains = [g for g in read_dump(sys.argv[1]) if g["z"] > -0.002 and math.hypot(g["x"], g["y"]) < 0.15]
    cx = sum(g["x"] for g in grains) / len(grains)
    cy = sum(g["y"] for g in grains) / len(grains)
    a_all, H, npts = angle(profile(grains, cx, cy))
    secs = [angle(profile(grains, cx, cy, nb=15, dr=0.01, sector=s, nsec=4))[0] for s in range(4)]
    secs = [a for a in secs if a == a]
    m = sum(secs) / len(secs)
    sd = math.sqrt(sum((a - m) ** 2 for a in secs) / max(1, len(secs) - 1))
    with open(sys.argv[2], "w") as f:
        f.write("quantity,value,unit\n")
        f.write(f"repose_angle_deg,{a_all:.2f},deg\n")
        f.write(f"repose_angle_quadrant_mean_deg,{m:.2f},deg\n")
        f.write(f"repose_angle_quadrant_sd_deg,{sd:.2f},deg\n")
        f.write(f"heap_height_m,{H:.4f},m\n")
        f.write(f"grains_on_pedestal,{len(grains)},-\n")
        f.write(f"profile_points_fitted,{npts},-\n")
    print(f"repose angle {a_all:.2f} deg (quadrants {m:.2f} +- {sd:.2f}), heap height {H:.4f} m, {len(grains)} grains")


if __name__ == "__main__":
    main()
