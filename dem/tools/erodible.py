#!/usr/bin/env python3
"""A thin layer set moving on a deep bed of its own grains at rest
(dem/calibration/erodible.in): whether it stops or runs on into the bed,
and the friction it feels while it slows (stdlib only).

Usage: erodible.py OUT_DIR SCRATCH_DIR
  SCRATCH_DIR holds erodible_<tag>.csv and erodible_<tag>.txt (columns:
  step t v_top v_bed) for each angle the deck was run at.
Writes OUT_DIR/erodible_summary.csv, one row an angle:
  - rest_speed_m_s: the bed's fastest mean speed in the last 0.5 s before
    the kick (the control: a bed that flows by itself says nothing; the
    outcome is then "bed_flowing");
  - mu_top: the top layer's effective friction while it slows, from a
    least-squares line of its speed between 0.3 and 0.05 m/s against time,
    mu = tan(theta) - (du/dt) / (g cos theta);
  - top_travel_m: how far the top layer went after the kick;
  - bed_peak_m_s: the bed's fastest mean speed after the kick;
  - bed_travel_m: how far the bed's grains went after the kick, on the
    mean (sheared along under the layer, not carried away: the erosion
    question, docs/fast_flows.md);
  - bed_flowing: 1 where the bed flowed by itself before the kick (faster
    than 0.05 m/s: the run says nothing), else 0;
  - stopped: 1 where the top and the bed end slower than 0.01 m/s, else 0
    (numbers only, so that skidsim's CSV reader takes the file).
"""
import glob
import math
import os
import re
import sys

from dem_io import G, line_fit, read_quantities

STOPPED_M_S = 0.01
FIT_SPEEDS_M_S = (0.05, 0.3)


def series(path):
    rows = [[float(x) for x in l.split()] for l in open(path) if l.strip() and not l.startswith("#")]
    return [(r[1], r[2], r[3]) for r in rows]


def summarise(meta, rows, t_kick_s):
    theta = float(meta["theta_deg"])
    before = [r for r in rows if t_kick_s - 0.5 <= r[0] < t_kick_s]
    after = [r for r in rows if r[0] >= t_kick_s]
    if not after:
        sys.exit("erodible: no samples after the kick at %g s (did the run stop early?)" % t_kick_s)
    rest = max((abs(r[2]) for r in before), default=float("nan"))
    end = after[-1]
    stopped = abs(end[1]) < STOPPED_M_S and abs(end[2]) < STOPPED_M_S
    # the slowing phase: from the top's fastest sample after the kick on
    peak = max(range(len(after)), key=lambda k: after[k][1])
    slowing = [(r[0], r[1]) for r in after[peak:] if FIT_SPEEDS_M_S[0] <= r[1] <= FIT_SPEEDS_M_S[1]]
    mu = float("nan")
    if len(slowing) >= 3:
        dudt, _ = line_fit(slowing)
        mu = math.tan(math.radians(theta)) - dudt / (G * math.cos(math.radians(theta)))
    def travel(k):
        return sum(0.5 * (a[k] + b[k]) * (b[0] - a[0]) for a, b in zip(after, after[1:]))
    bed_flowing = rest > 5 * STOPPED_M_S
    return {
        "layers": meta["layers"], "top_layers": meta["top_layers"], "theta_deg": meta["theta_deg"],
        "v0_m_s": meta["v0_m_s"], "rest_speed_m_s": "%.4f" % rest, "mu_top": "%.4f" % mu,
        "top_travel_m": "%.4f" % travel(1), "bed_peak_m_s": "%.4f" % max(r[2] for r in after),
        "bed_travel_m": "%.4f" % travel(2),
        "bed_flowing": "1" if bed_flowing else "0", "stopped": "1" if stopped and not bed_flowing else "0",
    }


def main():
    out_dir, scratch = sys.argv[1], sys.argv[2]
    rows_out = []
    for meta_path in sorted(glob.glob(os.path.join(scratch, "erodible_*.csv"))):
        tag = re.sub(r"^erodible_|\.csv$", "", os.path.basename(meta_path))
        meta = read_quantities(meta_path)
        rows = series(os.path.join(scratch, "erodible_%s.txt" % tag))
        rows_out.append(summarise(meta, rows, float(meta.get("rest_s", "1.0"))))
    rows_out.sort(key=lambda r: (float(r["top_layers"]), float(r["theta_deg"])))
    keys = ["layers", "top_layers", "theta_deg", "v0_m_s", "rest_speed_m_s", "mu_top", "top_travel_m", "bed_peak_m_s",
            "bed_travel_m", "bed_flowing", "stopped"]
    with open(os.path.join(out_dir, "erodible_summary.csv"), "w") as f:
        f.write(",".join(keys) + "\n")
        for r in rows_out:
            f.write(",".join(r[k] for k in keys) + "\n")
            outcome = "the bed flowed by itself" if r["bed_flowing"] == "1" else (
                "stopped" if r["stopped"] == "1" else "ran on")
            print("erodible: %s grains at %s m/s, theta %s deg: %s, mu_top %s, travel %s m, bed peak %s m/s, bed travel %s m"
                  % (r["top_layers"], r["v0_m_s"], r["theta_deg"], outcome, r["mu_top"], r["top_travel_m"],
                     r["bed_peak_m_s"], r["bed_travel_m"]))


if __name__ == "__main__":
    main()
