#!/usr/bin/env python3
"""Bekker's pressure-sinkage parameters from the DEM plate tests (stdlib only).

Usage: plate_post.py OUT_DIR PLATE_TXT... (files named plate_r<radius mm>.txt, the
fix ave/time output of dem/wheel/plate.in: step, plate bottom height z_b, force F_z)

Bekker (3.19) with b the plate's radius: p = (k_c / b + k_phi) (z_s - z_b)^n on the first
loading leg, where z_s, the level of the bed's surface as the plates feel it, is fitted too
(the grains' tops are no flat surface: half a grain is 4 mm). One z_s, n, k_c and k_phi for
both plates: a grid over z_s and n, k_c and k_phi by least squares in log p given them.
Wong's unloading line (Wong 2008, 2.4.x): on unloading from z_max the pressure falls along
p = p_max - k_u (z_max - z); k_u from the first 1.5 mm of each unloading, and
k_u = k_0 + A_u z_max through the two unloadings.

Writes plate_r<mm>.csv (z_b, sinkage, force, pressure) and bekker.csv (the parameters, in the
units of assets/soils.xml too).
"""
import math
import os
import re
import sys


def read_plate(path):
    rows = []
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        step, zb, fz = line.split()[:3]
        rows.append((float(zb), float(fz)))
    return rows


def legs(rows):
    """Split into monotonic legs of the plate's motion (down, up, down, up)."""
    out, cur, sign = [], [rows[0]], 0
    for a, b in zip(rows, rows[1:]):
        s = -1 if b[0] < a[0] else 1
        if sign and s != sign:
            out.append(cur)
            cur = [a]
        sign = s
        cur.append(b)
    out.append(cur)
    return out


def lin_fit(xs, ys):
    n = len(xs)
    mx, my = sum(xs) / n, sum(ys) / n
    sxx = sum((x - mx) ** 2 for x in xs)
    sxy = sum((x - mx) * (y - my) for x, y in zip(xs, ys))
    k = sxy / sxx
    return k, my - k * mx


def bekker_fit(first_legs, p_min_Pa):
    """first_legs: {b: [(z_b, p)]} loading. Returns (z_s, n, k_c, k_phi, rms of log p)."""
    zs_lo = max(max(z for z, p in leg) for leg in first_legs.values()) - 0.012
    best = None
    for i in range(241):
        z_s = zs_lo + 0.0001 * i
        pts = [(b, z_s - z, p) for b, leg in first_legs.items() for z, p in leg if p > p_min_Pa and z_s - z > 1e-4]
        if len(pts) < 20 or min(p[1] for p in pts) <= 0:
            continue
        for j in range(61):
            n = 0.3 + 0.025 * j
            # p / z^n = k_c / b + k_phi: linear least squares in (1/b, 1) weighted in log space
            # (relative residuals): minimise sum (p - (k_c/b + k_phi) z^n)^2 / p^2
            a11 = a12 = a22 = r1 = r2 = 0.0
            for b, z, p in pts:
                u, v = z ** n / (b * p), z ** n / p
                a11 += u * u; a12 += u * v; a22 += v * v; r1 += u; r2 += v
            det = a11 * a22 - a12 * a12
            if abs(det) < 1e-300:
                continue
            kc = (r1 * a22 - r2 * a12) / det
            kp = (a11 * r2 - a12 * r1) / det
            err = 0.0
            for b, z, p in pts:
                q = (kc / b + kp) * z ** n
                if q <= 0:
                    err = float("inf")
                    break
                err += math.log(q / p) ** 2
            rms = math.sqrt(err / len(pts))
            if best is None or rms < best[4]:
                best = (z_s, n, kc, kp, rms, len(pts))
    return best


def main():
    out_dir, files = sys.argv[1], sys.argv[2:]
    os.makedirs(out_dir, exist_ok=True)
    plates = {}
    for f in files:
        m = re.search(r"plate_r(\d+)\.txt$", f)
        b = int(m.group(1)) / 1000.0
        plates[b] = legs(read_plate(f))
    area = {b: math.pi * b * b for b in plates}
    first = {b: [(z, f / area[b]) for z, f in lg[0]] for b, lg in plates.items()}
    p_max = min(max(p for z, p in leg) for leg in first.values())
    z_s, n, kc, kp, rms, npts = bekker_fit(first, 0.02 * p_max)

    # unloading lines: the first 1.5 mm of each upward leg, from its start
    unload = []
    for b, lg in plates.items():
        for k, leg in enumerate(lg):
            if leg[-1][0] <= leg[0][0]:
                continue  # a downward leg
            z0, f0 = leg[0]
            seg = [(z, f / area[b]) for z, f in leg if z - z0 <= 0.0015]
            if len(seg) < 4:
                continue
            slope, _ = lin_fit([z for z, p in seg], [p for z, p in seg])
            unload.append((b, z_s - z0, -slope, f0 / area[b]))
    # k_u = k0 + A_u z_max over every unloading (both plates)
    au, k0 = lin_fit([u[1] for u in unload], [u[2] for u in unload]) if len(unload) >= 2 else (0.0, unload[0][2])

    for b, lg in plates.items():
        mm = round(b * 1000)
        with open(os.path.join(out_dir, f"plate_r{mm}.csv"), "w") as f:
            f.write("plate_bottom_z_m,sinkage_m,force_z_N,pressure_Pa,leg\n")
            for k, leg in enumerate(lg):
                for z, fz in leg:
                    f.write(f"{z:.6f},{z_s - z:.6f},{fz:.3f},{fz / area[b]:.1f},{k + 1}\n")
    with open(os.path.join(out_dir, "bekker.csv"), "w") as f:
        f.write("quantity,value,unit,note\n")
        f.write(f"surface_level_m,{z_s:.4f},m,the bed's surface as the plates feel it (fitted)\n")
        f.write(f"n,{n:.3f},-,Bekker exponent (both plates)\n")
        f.write(f"k_c,{kc / 1000:.4g},kN/m^(n+1),b = plate radius\n")
        f.write(f"k_phi,{kp / 1000:.5g},kN/m^(n+2),\n")
        f.write(f"fit_rms_log,{rms:.4f},-,rms of ln(p_fit/p) over {npts} points (p > 2 % of the smaller plate's largest)\n")
        for b, z, ku, p in unload:
            f.write(f"k_u_r{round(b * 1000)}_z{1000 * z:.1f}mm,{ku / 1000:.4g},kPa/m,unloading slope from {p / 1000:.1f} kPa\n")
        f.write(f"unload_k0,{k0 / 1000:.5g},kPa/m,k_u = k0 + A_u z_max\n")
        f.write(f"unload_Au,{au / 1000:.5g},kPa/m^2,\n")
    print(open(os.path.join(out_dir, "bekker.csv")).read())


if __name__ == "__main__":
    main()
