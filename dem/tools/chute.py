#!/usr/bin/env python3
"""Inclined layer (dem/calibration/chute.in): the friction of a flowing layer
against its speed, and the angle at which it stops (stdlib only).

Usage: chute.py OUT_DIR SCRATCH_DIR
  SCRATCH_DIR holds chute_<tag>.csv and chute_<tag>_theta<deg>.txt (columns:
  step t vx ztop) for each base and thickness the deck was run with.
Writes OUT_DIR/chute.csv (one row an angle and run: the layer's speed when
gravity turned to theta and 2 s later, whether it stopped),
OUT_DIR/chute_friction.csv (per run: the effective friction of the
decelerating layer in bins of speed, mu = tan(theta) - (du/dt) / (g cos theta),
pooled over the angles at which it decelerated) and OUT_DIR/chute_summary.csv
(per run: the stop angle), and prints the stop angles.

The stop angle: the layer's friction as its speed goes to zero, the mu_s of
the mu(I) law (Jop, Forterre and Pouliquen 2006); from the decelerating
phases with speeds between 0.05 and 0.5 m/s, a least-squares line mu(u)
taken at u = 0. The bracket (the steepest angle at which the layer stopped
within 2 s, the gentlest at which it did not) is written beside it.
"""
import glob
import math
import os
import re
import sys

from dem_io import G, line_fit, read_quantities

STOPPED_M_S = 0.01       # a layer slower than this at the end has stopped
FIT_SPEEDS_M_S = (0.05, 0.5)
WINDOW_S = 0.1           # du/dt over this span
BINS_M_S = [0.05, 0.1, 0.2, 0.3, 0.5, 0.75, 1.0, 1.5, 2.0, 3.0, 5.0, 8.0]


def series(path):
    rows = [[float(x) for x in l.split()] for l in open(path) if l.strip() and not l.startswith("#")]
    return [(r[1], r[2]) for r in rows]


def decelerating(theta_deg, ts):
    """(speed, friction) pairs of the phase in which the layer slows down."""
    out = []
    th = math.radians(theta_deg)
    k = max(1, round(WINDOW_S / (ts[1][0] - ts[0][0])))
    for i in range(len(ts) - k):
        (t0, u0), (t1, u1) = ts[i], ts[i + k]
        if u1 >= u0 or u1 < FIT_SPEEDS_M_S[0] * 0.5:
            continue
        a = (u1 - u0) / (t1 - t0)
        out.append((0.5 * (u0 + u1), math.tan(th) - a / (G * math.cos(th))))
    return out


def main():
    out_dir, scratch = sys.argv[1], sys.argv[2]
    runs = sorted(glob.glob(os.path.join(scratch, "chute_base*_n*.csv")))
    if not runs:
        sys.exit("chute.py: no chute_base*_n*.csv in " + scratch)
    table, friction, summary = [], [], []
    for meta_path in runs:
        tag = os.path.basename(meta_path)[len("chute_"):-len(".csv")]
        meta = read_quantities(meta_path)
        pairs, stopped, flowing = [], [], []
        for p in glob.glob(os.path.join(scratch, "chute_%s_theta*.txt" % tag)):
            theta = float(re.findall(r"theta([0-9.]+)\.txt$", p)[0])
            ts = series(p)
            u_end = sum(u for _, u in ts[-5:]) / 5
            halted = abs(u_end) < STOPPED_M_S
            (stopped if halted else flowing).append(theta)
            table.append((tag, theta, ts[0][1], u_end, halted))
            pairs += decelerating(theta, ts)
        fit = [(u, m) for u, m in pairs if FIT_SPEEDS_M_S[0] <= u <= FIT_SPEEDS_M_S[1]]
        if len(fit) < 3:
            sys.exit("chute.py: %s decelerated through %g-%g m/s at no angle" % ((tag,) + FIT_SPEEDS_M_S))
        slope, mu_s = line_fit(fit)
        for lo, hi in zip(BINS_M_S[:-1], BINS_M_S[1:]):
            ms = [m for u, m in pairs if lo <= u < hi]
            if ms:
                friction.append((tag, lo, hi, len(ms), sum(ms) / len(ms)))
        lo_b = max(stopped) if stopped else float("nan")
        hi_b = min((t for t in flowing if t > lo_b), default=float("nan"))
        summary.append({"run": tag, "base": int(meta["base_type"]), "layers": int(meta["layers"]),
                        "layer_m": float(meta["layer_m"]), "gap_m": float(meta.get("side_wall_gap_m", "0")),
                        "mu_s": mu_s, "slope": slope, "samples": len(fit), "stopped": lo_b, "flowed": hi_b})
    # Side walls: the walled layer's friction over the open layer's of the same base and
    # thickness is mu_w h / W (Jop et al. 2005), so mu_w = (mu_walled - mu_open) W / h.
    for r in summary:
        r["wall_mu"] = float("nan")
        if r["gap_m"] > 0:
            open_runs = [o for o in summary if o["gap_m"] == 0 and o["base"] == r["base"] and o["layers"] == r["layers"]]
            if open_runs:
                r["wall_mu"] = (r["mu_s"] - open_runs[0]["mu_s"]) * r["gap_m"] / r["layer_m"]
    table.sort()
    with open(os.path.join(out_dir, "chute.csv"), "w") as f:
        f.write("run,theta_deg,speed_at_turn_m_s,speed_after_2s_m_s,stopped\n")
        for r in table:
            f.write("%s,%g,%.4f,%.4f,%d\n" % (r[0], r[1], r[2], r[3], r[4]))
    with open(os.path.join(out_dir, "chute_friction.csv"), "w") as f:
        f.write("run,speed_from_m_s,speed_to_m_s,samples,mean_friction\n")
        for r in friction:
            f.write("%s,%g,%g,%d,%.4f\n" % r)
    summary.sort(key=lambda r: (r["base"], r["gap_m"], r["layers"]))
    with open(os.path.join(out_dir, "chute_summary.csv"), "w") as f:
        f.write("run,base_type,layers,side_wall_gap_m,mu_s,stop_angle_deg,mu_per_m_s,samples,"
                "stopped_up_to_deg,flowed_from_deg,wall_mu\n")
        for r in summary:
            f.write("%s,%d,%d,%g,%.4f,%.2f,%.4f,%d,%g,%g,%.4f\n"
                    % (r["run"], r["base"], r["layers"], r["gap_m"], r["mu_s"], math.degrees(math.atan(r["mu_s"])),
                       r["slope"], r["samples"], r["stopped"], r["flowed"], r["wall_mu"]))
    # Thin layers stop on steeper slopes (Pouliquen 1999): on the grains,
    # tan theta_stop(h) = tan theta_1 + (tan theta_2 - tan theta_1) exp(-h / (A d)), with theta_1 the
    # thickest layer's; ln(mu_s - mu_1) is a line in h / d through the thinner layers.
    grains = [r for r in summary if r["base"] == 1 and r["gap_m"] == 0]
    thick = max(grains, key=lambda r: r["layers"])
    thin = [(r["layers"], math.log(r["mu_s"] - thick["mu_s"])) for r in grains if r["mu_s"] - thick["mu_s"] > 0.01]
    if len(thin) < 2:
        sys.exit("chute.py: fewer than two layers on the grains stop above the thickest one's angle")
    slope, intercept = line_fit(thin)
    theta2 = math.degrees(math.atan(thick["mu_s"] + math.exp(intercept)))
    with open(os.path.join(out_dir, "chute_thickness.csv"), "w") as f:
        f.write("quantity,value,unit\n")
        f.write("flowing_friction_angle_deg,%.2f,deg\n" % math.degrees(math.atan(thick["mu_s"])))
        f.write("thin_layer_friction_angle_deg,%.2f,deg\n" % theta2)
        f.write("thin_layer_decay_grains,%.3f,-\n" % (-1.0 / slope))
        f.write("layers_fitted,%s,-\n" % " ".join(str(n) for n, _ in thin))
    print("  thickness law: theta_1 %.2f deg (%d grains), theta_2 %.2f deg, A %.2f grains"
          % (math.degrees(math.atan(thick["mu_s"])), thick["layers"], theta2, -1.0 / slope))
    for r in summary:
        print("  %s: mu_s %.3f (%.1f deg), stopped up to %g deg, flowed from %g deg%s"
              % (r["run"], r["mu_s"], math.degrees(math.atan(r["mu_s"])), r["stopped"], r["flowed"],
                 "" if math.isnan(r["wall_mu"]) else ", walls' mu_w %.3f" % r["wall_mu"]))


if __name__ == "__main__":
    main()
