#!/usr/bin/env python3
"""Blade runs: CSV per run, summary, and the McKyes-Ali comparison (stdlib only).

Usage: blade_post.py RESULTS_DIR MATERIAL_CSV RAW_DIR
  RAW_DIR holds blade_a{rake}_d{mm}mm.txt (fix ave/time: step travel fx fz, each row
  the mean over ~2 mm of travel). MATERIAL_CSV is dem/calibration/material.csv
  (friction_angle_deg, tool_friction_angle_deg, bulk_density_kg_m3).
Writes RESULTS_DIR/blade_a*_d*mm.csv (travel_m, force_x_N, force_z_N),
RESULTS_DIR/summary.csv and RESULTS_DIR/mckyes_comparison.csv. The McKyes-Ali draft
(dem/tools/mckyes.py) is evaluated twice: variant phi_c with the shear box's Mohr-Coulomb
phi and c, variant phi_c0 with the shear box's c = 0 fit; delta from the sliding plate.
force_x_N: soil force on the blade against the travel direction (draft), N.
force_z_N: soil force on the blade, upward positive, N.
Mean window: travel from 2 d to the end of the run.
"""
import glob
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from dem_io import G, read_material  # noqa: E402
from mckyes import mckyes  # noqa: E402

W = 0.10


def main():
    res_dir, mat_csv, raw_dir = sys.argv[1:4]
    mat = read_material(mat_csv)
    phi, delta, rho = mat["friction_angle_deg"], mat["tool_friction_angle_deg"], mat["bulk_density_kg_m3"]
    coh = mat["cohesion_kPa"] * 1000.0
    phi0 = mat["friction_angle_c0_deg"]
    gamma = rho * G
    os.makedirs(res_dir, exist_ok=True)
    summ = ["rake_deg,depth_m,width_m,bulk_density_kg_m3,peak_force_x_N,mean_force_x_N,mean_force_z_N,"
            "mean_window_from_m,N_peak,N_mean,travel_m"]
    comp = ["rake_deg,depth_m,variant,phi_deg,cohesion_Pa,delta_deg,gamma_N_m3,mckyes_beta_deg,mckyes_r_m,"
            "mckyes_draft_N,mckyes_vertical_up_N,mckyes_N_draft,dem_peak_force_x_N,dem_mean_force_x_N,"
            "dem_mean_force_z_N,ratio_dem_peak_to_mckyes,ratio_dem_mean_to_mckyes"]
    for p in sorted(glob.glob(os.path.join(raw_dir, "blade_a*_d*mm.txt"))):
        name = os.path.basename(p)[:-4]
        rake, dmm = (int(x) for x in re.findall(r"\d+", name))
        d = dmm / 1000.0
        rows = [[float(x) for x in l.split()] for l in open(p) if l.strip() and not l.startswith("#")]
        with open(os.path.join(res_dir, name + ".csv"), "w") as f:
            f.write("travel_m,force_x_N,force_z_N\n")
            for r in rows:
                f.write(f"{r[1]:.4f},{r[2]:.3f},{r[3]:.3f}\n")
        fx = [r[2] for r in rows]
        win = [r for r in rows if r[1] >= 2 * d]
        mfx = sum(r[2] for r in win) / len(win)
        mfz = sum(r[3] for r in win) / len(win)
        pk = max(fx)
        den = gamma * d * d * W
        summ.append(f"{rake},{d:.3f},{W:.3f},{rho:.1f},{pk:.2f},{mfx:.2f},{mfz:.2f},{2*d:.3f},"
                    f"{pk/den:.3f},{mfx/den:.3f},{rows[-1][1]:.4f}")
        for variant, ph, c in (("phi_c", phi, coh), ("phi_c0", phi0, 0.0)):
            m = mckyes(rake, d, W, ph, delta, gamma, c)
            comp.append(f"{rake},{d:.3f},{variant},{ph:.2f},{c:.0f},{delta:.2f},{gamma:.1f},{m['beta_deg']:.2f},"
                        f"{m['r_m']:.4f},{m['draft_N']:.2f},{m['vertical_up_N']:.2f},{m['N_draft']:.3f},{pk:.2f},"
                        f"{mfx:.2f},{mfz:.2f},{pk/m['draft_N']:.3f},{mfx/m['draft_N']:.3f}")
    open(os.path.join(res_dir, "summary.csv"), "w").write("\n".join(summ) + "\n")
    open(os.path.join(res_dir, "mckyes_comparison.csv"), "w").write("\n".join(comp) + "\n")
    print("\n".join(summ))
    print("\n".join(comp))


if __name__ == "__main__":
    main()
