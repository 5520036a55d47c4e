#!/usr/bin/env python3
"""The DEM wheel runs (dem/wheel/wheel.in) reduced to their steady means (stdlib only).

Usage: wheel_post.py OUT_DIR BEKKER.csv RIM.csv WHEEL_CSV...   (files named wheel_<case>.csv:
wheel_towed.csv, wheel_s0.20.csv, wheel_s-0.30.csv, ...; RIM.csv: the sliding plate of the
rim's material, dem/calibration/results/sliding_plate_rim.csv, whose delta goes into
summary.csv beside the runs)

Each run's rows are chunks of 100 steps. The steady window is the travel from 0.12 m to the
end (0.30 m): past the first contact lengths, where the sinkage still grows. Sinkage is
measured from the bed's surface as the plates feel it (bekker.csv surface_level_m, also the bed's depth over its floor at z = 0), so the
plates' z and the wheel's z are counted from one level. Slip, from the wheel's motion:
s = 1 - v / (r omega) when r omega >= v (Wong's i), r omega / v - 1 otherwise (a skid).
Writes wheel_<case>.csv (the time series, copied) and summary.csv: per run (towed 1: free to
spin; 0: the slip held) the means over
the window of W (the grains' vertical force), DP (forward), T (the drive's torque), z, and
their dimensionless forms z / D, DP / W, T / (W r), with the standard deviation of the
chunk values about the mean (the scatter, not an error of the mean).
"""
import math
import os
import re
import shutil
import sys

from dem_io import read_quantities

RADIUS_M = 0.15  # dem/wheel/wheel.in and dem/tools/meshes.py
WIDTH_M = 0.10
WINDOW_FROM_M = 0.12


def stats(xs):
    m = sum(xs) / len(xs)
    return m, math.sqrt(sum((x - m) ** 2 for x in xs) / len(xs))


def main():
    out_dir, bekker, rim, files = sys.argv[1], sys.argv[2], sys.argv[3], sys.argv[4:]
    rim_delta = float(re.search(r"delta_deg=([-\d.]+)", open(rim).read()).group(1))
    os.makedirs(out_dir, exist_ok=True)
    z_s = float(read_quantities(bekker)["surface_level_m"])
    rows_out = []
    for path in files:
        case = re.search(r"wheel_(.+)\.csv$", path).group(1)
        if os.path.abspath(os.path.dirname(path)) != os.path.abspath(out_dir):
            shutil.copy(path, os.path.join(out_dir, os.path.basename(path)))
        head, data = None, []
        for line in open(path):
            p = line.strip().split(",")
            if head is None:
                head = p
                continue
            data.append(dict(zip(head, (float(x) for x in p))))
        rolling = [d for d in data if d["phase"] == 1]
        x0 = rolling[0]["axle_x_m"] - (rolling[1]["axle_x_m"] - rolling[0]["axle_x_m"])
        t0 = rolling[0]["time_s"] - (rolling[1]["time_s"] - rolling[0]["time_s"])
        v = (rolling[-1]["axle_x_m"] - x0) / (rolling[-1]["time_s"] - t0)
        win = [d for d in rolling if d["axle_x_m"] - x0 >= WINDOW_FROM_M]
        W, sW = stats([d["force_z_N"] for d in win])
        DP, sDP = stats([d["force_x_N"] for d in win])
        T, sT = stats([d["torque_Nm"] for d in win])
        z, sz = stats([z_s - (d["axle_z_m"] - RADIUS_M) for d in win])
        om, _ = stats([d["omega_rad_s"] for d in win])
        rw = om * RADIUS_M
        slip = 1.0 - v / rw if rw >= v else rw / v - 1.0
        travel = rolling[-1]["axle_x_m"] - x0
        rows_out.append((case, slip, W, sW, DP, sDP, T, sT, z, sz, v, len(win), travel))
    rows_out.sort(key=lambda r: r[1])
    with open(os.path.join(out_dir, "summary.csv"), "w") as f:
        f.write("towed,slip,load_N,load_sd_N,drawbar_pull_N,drawbar_pull_sd_N,torque_Nm,torque_sd_Nm,"
                "sinkage_m,sinkage_sd_m,speed_m_s,chunks,z_over_D,DP_over_W,T_over_Wr,radius_m,width_m,bed_depth_m,"
                "window_from_m,travel_m,rim_friction_angle_deg\n")
        for case, s, W, sW, DP, sDP, T, sT, z, sz, v, n, travel in rows_out:
            f.write(f"{int(case == 'towed')},{s:.4f},{W:.2f},{sW:.2f},{DP:.2f},{sDP:.2f},{T:.4f},{sT:.4f},{z:.5f},{sz:.5f},"
                    f"{v:.4f},{n},{z / (2 * RADIUS_M):.4f},{DP / W:.4f},{T / (W * RADIUS_M):.4f},{RADIUS_M},{WIDTH_M},"
                    f"{z_s:.4f},{WINDOW_FROM_M},{travel:.4f},{rim_delta}\n")
    print(open(os.path.join(out_dir, "summary.csv")).read())


if __name__ == "__main__":
    main()
