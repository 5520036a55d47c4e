#!/usr/bin/env python3
"""Bucket scoop: time series and summary (stdlib only).

Usage: bucket_post.py RAW_DIR RESULTS_DIR MATERIAL_CSV
RAW_DIR: bucket_raw.txt (fix ave/time: step t fx fz m_carried edge_x edge_z, 100-step means),
bucket_phases.txt (phase,start_step,start_time_s,hinge_x_m,hinge_z_m), bucket_final.dump.
Writes RESULTS_DIR/scoop.csv (travel_m = the hinge's x displacement from the start) and
RESULTS_DIR/summary.csv.
Kinematics (bucket.in): dig 15 deg below horizontal at 0.2 m/s, push 0.2 m/s, curl 70 deg
in 0.7 s about the hinge, lift 0.2 m/s, hold.
force_x_N: soil force on the bucket against +x (travel), force_z_N: upward positive.
"""
import math
import os
import sys

from dem_io import read_dump, read_material

V, DIG = 0.2, math.radians(15.0)
CURL, TCURL = 70.0, 0.7
W, L, H = 0.12, 0.08, 0.08


def main():
    raw, res, mat_csv = sys.argv[1:4]
    rho = read_material(mat_csv)["bulk_density_kg_m3"]
    ph = [l.strip().split(",") for l in open(os.path.join(raw, "bucket_phases.txt"))][1:]
    phases = [(p[0], float(p[2]), float(p[3]), float(p[4])) for p in ph]
    t0, x0, z0 = phases[0][1], phases[0][2], phases[0][3]
    rows = [[float(x) for x in l.split()] for l in open(os.path.join(raw, "bucket_raw.txt"))
            if l.strip() and not l.startswith("#")]
    out = ["time_s,phase,travel_m,hinge_x_m,hinge_z_m,curl_deg,edge_x_m,edge_z_m,force_x_N,force_z_N,carried_mass_kg"]
    stats = {}
    for r in rows:
        t = r[1]
        name, ts, xs, zs = phases[0]
        for p in phases[:-1]:
            if t > p[1] + 1e-9:
                name, ts, xs, zs = p
        dt = t - ts
        x, z, a = xs, zs, 0.0
        if name == "dig":
            x, z = xs + V * math.cos(DIG) * dt, zs - V * math.sin(DIG) * dt
        elif name == "push":
            x = xs + V * dt
        elif name == "curl":
            a = CURL * min(1.0, dt / TCURL)
        elif name in ("lift", "hold"):
            a = CURL
            z = zs + (V * dt if name == "lift" else 0.0)
        out.append(f"{t - t0:.4f},{name},{x - x0:.4f},{x:.4f},{z:.4f},{a:.2f},{r[5]:.4f},{r[6]:.4f},{r[2]:.2f},{r[3]:.2f},{r[4]:.4f}")
        s = stats.setdefault(name, [])
        s.append((r[2], r[3]))
    os.makedirs(res, exist_ok=True)
    open(os.path.join(res, "scoop.csv"), "w").write("\n".join(out) + "\n")
    # payload from the final dump, in the bucket's frame (hinge, curl angle of the end state)
    name, ts, xh, zh = phases[-1]
    th = math.radians(-CURL)
    inside = 0.0
    for a in read_dump(os.path.join(raw, "bucket_final.dump")):
        dx, dz = a["x"] - xh, a["z"] - zh
        xb = math.cos(th) * dx - math.sin(th) * dz
        zb = math.sin(th) * dx + math.cos(th) * dz
        if 0 < xb < L and abs(a["y"]) < W / 2 and -H < zb < 0:
            inside += a["mass"]
    carried = rows[-1][4]
    vol = W * L * H
    summ = ["quantity,value,unit"]
    for name in ("dig", "push", "curl", "lift"):
        if name in stats:
            fx = [s[0] for s in stats[name]]
            fz = [s[1] for s in stats[name]]
            summ.append(f"{name}_peak_force_x_N,{max(fx):.2f},N")
            summ.append(f"{name}_mean_force_x_N,{sum(fx)/len(fx):.2f},N")
            summ.append(f"{name}_peak_force_z_N,{max(fz):.2f},N")
            summ.append(f"{name}_min_force_z_N,{min(fz):.2f},N")
    summ.append(f"payload_in_bucket_frame_kg,{inside:.4f},kg")
    summ.append(f"payload_above_0.20m_kg,{carried:.4f},kg")
    summ.append(f"bucket_struck_volume_m3,{vol:.6f},m3")
    summ.append(f"bulk_density_kg_m3,{rho:.1f},kg/m3")
    summ.append(f"fill_factor_in_frame,{inside/(rho*vol):.3f},-")
    summ.append(f"fill_factor_carried,{carried/(rho*vol):.3f},-")
    summ.append(f"edge_final_x_m,{rows[-1][5]:.4f},m")
    summ.append(f"edge_final_z_m,{rows[-1][6]:.4f},m")
    open(os.path.join(res, "summary.csv"), "w").write("\n".join(summ) + "\n")
    print("\n".join(summ))


if __name__ == "__main__":
    main()
