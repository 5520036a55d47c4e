#!/usr/bin/env python3
"""Direct shear box: Mohr-Coulomb fit (stdlib only).

Usage: shear.py OUT.csv SERIES.csv FILE_2000 FILE_5000 ...
  FILE_<sn>: fix ave/time output of shear_box.in (columns: step disp fx fn_plane fn_lid flid lidz),
  sn = target normal stress in Pa (taken from the file name, after the last '_').

For each test: normal stress = mean(fn_plane)/A (from the lower block's equilibrium) over the shear phase after 1 mm,
peak shear stress = max of the 5-point running mean of fx/A,
residual = mean of fx/A over the last 25 % of the displacement.
The Mohr-Coulomb line tau = c + sigma tan(phi) is fitted by least squares to the
(sigma, tau_peak) and (sigma, tau_residual) points.
SERIES.csv gets the shear curves (displacement, shear stress, normal stress) every 0.25 mm.
"""
import math
import os
import re
import sys

from dem_io import line_fit

A = 0.15 * 0.15


def read(path):
    rows = []
    with open(path) as f:
        for line in f:
            if line.startswith("#") or not line.strip():
                continue
            v = [float(x) for x in line.split()]
            rows.append(v)
    return rows


def main():
    out, series = sys.argv[1], sys.argv[2]
    tests = []
    ser = ["sn_target_Pa,displacement_m,shear_stress_Pa,normal_stress_Pa"]
    for p in sys.argv[3:]:
        sn = float(re.findall(r"_(\d+)", os.path.basename(p))[-1])
        rows = read(p)
        disp = [r[1] for r in rows]
        tau = [r[2] / A for r in rows]
        sig = [r[3] / A for r in rows]
        siglid = [r[4] / A for r in rows]
        dmax = disp[-1]
        k = 2
        idx = range(k, len(tau) - k)
        rm = lambda v, i: sum(v[j] for j in range(i - k, i + k + 1)) / (2 * k + 1)
        cand = [i for i in idx if disp[i] <= 0.1 * 0.15 + 1e-9]
        ip = max(cand, key=lambda i: rm(tau, i))
        peak, sigma, dpeak, slid = rm(tau, ip), rm(sig, ip), disp[ip], rm(siglid, ip)
        res_i = [i for i, d in enumerate(disp) if d >= 0.75 * dmax]
        resid = sum(tau[i] for i in res_i) / len(res_i)
        sig_end = sum(sig[i] for i in res_i) / len(res_i)
        tests.append((sn, sigma, peak, resid, dpeak, sig_end, slid))
        last = -1.0
        for d, t, s in zip(disp, tau, sig):
            if d - last >= 0.00025 - 1e-9:
                ser.append(f"{sn:.0f},{d:.5f},{t:.1f},{s:.1f}")
                last = d
    tests.sort()
    bp, cp = line_fit([(t[1], t[2]) for t in tests])
    br, cr = line_fit([(t[5], t[3]) for t in tests])
    bl, cl = line_fit([(t[6], t[2]) for t in tests])
    b0 = sum(t[1] * t[2] for t in tests) / sum(t[1] ** 2 for t in tests)  # c = 0 fit
    with open(out, "w") as f:
        f.write("sn_target_Pa,normal_stress_at_peak_Pa,peak_shear_stress_Pa,peak_displacement_m,"
                "normal_stress_end_Pa,end_shear_stress_Pa,lid_normal_stress_at_peak_Pa\n")
        for t in tests:
            f.write(f"{t[0]:.0f},{t[1]:.1f},{t[2]:.1f},{t[4]:.5f},{t[5]:.1f},{t[3]:.1f},{t[6]:.1f}\n")
        f.write(f"# Mohr-Coulomb peak: phi_deg={math.degrees(math.atan(bp)):.2f} c_Pa={cp:.1f}\n")
        f.write(f"# Mohr-Coulomb residual: phi_deg={math.degrees(math.atan(br)):.2f} c_Pa={cr:.1f}\n")
        f.write(f"# Mohr-Coulomb peak through the origin (c = 0): phi_deg={math.degrees(math.atan(b0)):.2f}\n")
        f.write(f"# Mohr-Coulomb peak with the lid normal stress: phi_deg={math.degrees(math.atan(bl)):.2f} c_Pa={cl:.1f}\n")
    with open(series, "w") as f:
        f.write("\n".join(ser) + "\n")
    print(f"peak phi {math.degrees(math.atan(bp)):.2f} deg, c {cp:.1f} Pa; "
          f"end phi {math.degrees(math.atan(br)):.2f} deg, c {cr:.1f} Pa; "
          f"peak c=0 phi {math.degrees(math.atan(b0)):.2f} deg; "
          f"peak with lid stress phi {math.degrees(math.atan(bl)):.2f} deg, c {cl:.1f} Pa")
    for t in tests:
        print("  sn %.0f: sigma %.1f Pa, peak %.1f Pa (at %.1f mm, ratio %.3f, lid ratio %.3f), end %.1f / %.1f Pa" %
              (t[0], t[1], t[2], t[4] * 1000, t[2] / t[1], t[2] / t[6], t[3], t[5]))


if __name__ == "__main__":
    main()
