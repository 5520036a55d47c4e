#!/usr/bin/env python3
"""A flowing layer coming to rest, through its depth (dem/calibration/stopping.in;
Python 3, stdlib only): how its speed falls at every depth, where its grains
stop and how far its mass travels before it does, for a depth-averaged
layer's deposition to be checked against (docs/fast_flows.md, "A layer
coming to rest").

    stopping.py SCRATCH_DIR RESULTS_DIR

For every run (stopping_<tag>.csv and stopping_<tag>.dump in SCRATCH_DIR) it
writes stopping_<tag>.csv, one row per dump frame:

  t_s            time since gravity turned to theta
  mean_m_s       the mass-weighted mean downslope velocity of every mobile
                 grain (the layer's momentum over its mass)
  top_m_s        the mean velocity of the grains within d50 of the surface
  flowing_m_s    the mass-weighted mean velocity of the grains above the
                 grains at rest
  rest_layers    how many layers d50 thick, from the base up, move at under
                 a twentieth of the top's first speed (come to rest)
  depth_grains   the 98th percentile of the grains' centres over d50

and one row per run in stopping_summary.csv:

  mean0_m_s, top0_m_s   the first frame's mean and top velocities
  decel_top_m_s2        the top's deceleration (least squares over the
                        frames where it lies between 0.2 and 0.9 of top0)
  decel_mean0_m_s2      the mean's over the first 0.04 s
  friction_top          tan(theta) + decel_top / (g cos(theta)): the
                        friction that slows the flowing grains
  t_stop_s              the first frame whose top moves at under
                        a twentieth of top0
  stop_time_ratio       t_stop decel_top / mean0
  travel_ratio          the mass centre's travel to t_stop (the trapezoid
                        sum of mean_m_s) times decel_top / mean0^2
  fit_flowing_grains,   over the frames of decel_top's fit: the flowing
  fit_flowing_m_s       layer's mean depth (above the layers at rest, over
                        d50) and its grains' mean speed (flowing_m_s), the
                        layer whose friction friction_top measures

The two ratios are the deposition's dimensionless signature: a plug sliding
to rest (no deposition) has 1 and 1/2; a layer of linear profile whose every
depth slows alike, the static/flowing interface rising where its speed
reaches zero (Lusso et al. 2017) has 2 and 2/3; a layer that loses the speed
friction takes and lays its base down with its mean speed, 1 and 1/3.
"""
import math
import os

from dem_io import D50_M, DT_STEP_S, G, depth_98, line_fit, read_dump_frames, read_quantities, tool_args

REST_SHARE = 0.05     # a layer slower than this share of the top's first speed is at rest
TOP_FIT = (0.2, 0.9)  # the top's deceleration is fitted between these shares of top0
MEAN_FIT_S = 0.04     # the mean's first deceleration over this span


def mass_mean(grains):
    """The mass-weighted mean velocity of (radius, z, vx) grains."""
    m = sum(r ** 3 for r, _, _ in grains)
    return sum(r ** 3 * u for r, _, u in grains) / m if m > 0.0 else float("nan")


def frame_row(grains, rest_speed):
    """(mean, top, flowing mean, layers at rest, depth over d50) of a frame."""
    depth = depth_98(z for _, z, _ in grains)
    top = mass_mean([g for g in grains if g[1] > depth - D50_M])
    rest = 0
    for k in range(int(depth / D50_M) + 1):
        layer = [g for g in grains if k * D50_M <= g[1] < (k + 1) * D50_M]
        if not layer:
            rest += 1  # under the lowest mobile grains (the frozen base)
            continue
        if abs(mass_mean(layer)) >= rest_speed:
            break
        rest += 1
    flowing = [g for g in grains if g[1] >= rest * D50_M]
    return mass_mean(grains), top, mass_mean(flowing) if flowing else 0.0, rest, depth / D50_M


def post_run(scratch, results, meta_path):
    tag = os.path.basename(meta_path)[len("stopping_"):-len(".csv")]
    meta = read_quantities(meta_path)
    theta = math.radians(float(meta["theta_deg"]))
    snaps = [(step, [(a["radius"], a["z"], a["vx"]) for a in atoms])
             for step, atoms in read_dump_frames(os.path.join(scratch, "stopping_%s.dump" % tag))]
    if len(snaps) < 10:
        raise SystemExit("stopping.py: %s has %d frames" % (tag, len(snaps)))
    top0 = frame_row(snaps[0][1], 0.0)[1]
    rows = [(step * DT_STEP_S,) + frame_row(g, REST_SHARE * top0) for step, g in snaps]
    with open(os.path.join(results, "stopping_%s.csv" % tag), "w") as f:
        f.write("t_s,mean_m_s,top_m_s,flowing_m_s,rest_layers,depth_grains\n")
        for t, mean, top, flowing, rest, depth in rows:
            f.write("%.4f,%.4f,%.4f,%.4f,%d,%.2f\n" % (t, mean, top, flowing, rest, depth))
    mean0 = rows[0][1]
    # The frames in which the top slows through TOP_FIT of its first speed.
    window = [r for r in rows if TOP_FIT[0] * top0 <= r[2] <= TOP_FIT[1] * top0]
    fit = [(t, top) for t, _, top, _, _, _ in window]
    if len(fit) < 3:
        raise SystemExit("stopping.py: %s: the top never slowed through %g-%g of its speed" % ((tag,) + TOP_FIT))
    decel_top = -line_fit(fit)[0]
    # Over the same frames: the flowing layer's depth (above the layers at
    # rest, in grains) and its grains' mean speed, where its friction acts.
    fit_flowing_grains = sum(depth - rest for _, _, _, _, rest, depth in window) / len(window)
    fit_flowing_m_s = sum(flowing for _, _, _, flowing, _, _ in window) / len(window)
    decel_mean0 = -line_fit([(t, m) for t, m, _, _, _, _ in rows if t <= MEAN_FIT_S + 1e-9])[0]
    stops = [t for t, _, top, _, _, _ in rows if top < REST_SHARE * top0]
    if not stops:
        raise SystemExit("stopping.py: %s did not come to rest" % tag)
    t_stop = stops[0]
    travel = sum(0.5 * (a[1] + b[1]) * (b[0] - a[0]) for a, b in zip(rows, rows[1:]) if b[0] <= t_stop + 1e-9)
    return (meta["base_type"], meta["layers"], meta["theta_deg"], mean0, top0, decel_top, decel_mean0,
            math.tan(theta) + decel_top / (G * math.cos(theta)), t_stop, t_stop * decel_top / mean0,
            travel * decel_top / mean0 ** 2, fit_flowing_grains, fit_flowing_m_s)


def main():
    scratch, results, metas = tool_args("stopping.py", "stopping_base*.csv")
    rows = [post_run(scratch, results, m) for m in metas]
    rows.sort(key=lambda r: (int(r[0]), float(r[2]), int(r[1])))
    with open(os.path.join(results, "stopping_summary.csv"), "w") as f:
        f.write("base_type,layers,theta_deg,mean0_m_s,top0_m_s,decel_top_m_s2,decel_mean0_m_s2,friction_top,"
                "t_stop_s,stop_time_ratio,travel_ratio,fit_flowing_grains,fit_flowing_m_s\n")
        for r in rows:
            f.write("%s,%s,%s,%.4f,%.4f,%.3f,%.3f,%.4f,%.3f,%.3f,%.3f,%.2f,%.4f\n" % r)
            print("stopping base %s, %s grains, %s deg: stop time ratio %.2f, travel ratio %.2f, friction %.3f"
                  % (r[0], r[1], r[2], r[9], r[10], r[7]))


if __name__ == "__main__":
    main()
