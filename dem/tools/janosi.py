#!/usr/bin/env python3
"""Janosi and Hanamoto's shear deformation modulus K from the DEM shear box (stdlib only).

Usage: janosi.py SHEAR_CURVES.csv OUT.csv

Janosi-Hanamoto (Wong 2008, 2.5): tau = tau_max (1 - exp(-j / K)). The box's normal stress
drifts during the test, so the curve fitted is the stress ratio tau / sigma against the
shear displacement j, r = r_max (1 - exp(-j / K)): for each normal stress, and for all three
together (one K, one r_max), least squares over K on a 0.05 mm grid with r_max in closed form.
"""
import math
import sys


def fit(points):
    best = None
    for i in range(1, 601):
        K = 0.00005 * i
        e = [1.0 - math.exp(-j / K) for j, r in points]
        r_max = sum(ei * r for ei, (j, r) in zip(e, points)) / sum(ei * ei for ei in e)
        sse = sum((r - r_max * ei) ** 2 for ei, (j, r) in zip(e, points))
        if best is None or sse < best[2]:
            best = (K, r_max, sse)
    K, r_max, sse = best
    return K, r_max, math.sqrt(sse / len(points))


def main():
    src, out = sys.argv[1], sys.argv[2]
    curves = {}
    for line in open(src):
        if line.startswith("sn_target") or line.startswith("#") or not line.strip():
            continue
        sn, j, tau, sigma = (float(x) for x in line.split(","))
        curves.setdefault(int(sn), []).append((j, tau / sigma))
    rows = [(sn, *fit(pts)) for sn, pts in sorted(curves.items())]
    every = [p for pts in curves.values() for p in pts]
    K, r_max, rms = fit(every)
    with open(out, "w") as f:
        f.write("sn_target_Pa,K_m,ratio_max,rms_ratio\n")
        for sn, k, r, e in rows:
            f.write(f"{sn},{k:.5f},{r:.4f},{e:.4f}\n")
        f.write(f"all,{K:.5f},{r_max:.4f},{rms:.4f}\n")
    print(open(out).read())


if __name__ == "__main__":
    main()
