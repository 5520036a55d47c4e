#!/usr/bin/env python3
"""Sliding plate: soil-steel friction angle (stdlib only).

Usage: slide.py OUT.csv FILE_<sn> ...
  FILE: fix ave/time output of sliding_plate.in (columns: step disp fx fz plate_z).
The friction ratio |Fx|/Fz is averaged over the sliding phase from 10 mm of
displacement to the end (after the peak of the start-up); delta = atan(ratio).
"""
import math
import os
import re
import sys


def main():
    out = sys.argv[1]
    res = []
    for p in sys.argv[2:]:
        sn = float(re.findall(r"_(\d+)", os.path.basename(p))[-1])
        rows = [[float(x) for x in l.split()] for l in open(p) if l.strip() and not l.startswith("#")]
        sl = [r for r in rows if r[1] >= 0.010]
        fx = sum(abs(r[2]) for r in sl) / len(sl)
        fz = sum(r[3] for r in sl) / len(sl)
        ratios = [abs(r[2]) / r[3] for r in sl if r[3] > 0]
        m = sum(ratios) / len(ratios)
        sd = math.sqrt(sum((x - m) ** 2 for x in ratios) / (len(ratios) - 1))
        res.append((sn, fz, fx, fx / fz, sd))
    res.sort()
    with open(out, "w") as f:
        f.write("sn_target_Pa,mean_normal_force_N,mean_tangential_force_N,friction_ratio,ratio_sd,delta_deg\n")
        for r in res:
            f.write(f"{r[0]:.0f},{r[1]:.2f},{r[2]:.2f},{r[3]:.4f},{r[4]:.4f},{math.degrees(math.atan(r[3])):.2f}\n")
        allr = sum(r[3] for r in res) / len(res)
        f.write(f"# mean: friction_ratio={allr:.4f} delta_deg={math.degrees(math.atan(allr)):.2f}\n")
    for r in res:
        print("  sn %.0f: Fz %.1f N, Fx %.1f N, ratio %.3f (sd %.3f), delta %.2f deg" %
              (r[0], r[1], r[2], r[3], r[4], math.degrees(math.atan(r[3]))))


if __name__ == "__main__":
    main()
