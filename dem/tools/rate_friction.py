#!/usr/bin/env python3
"""The friction of a flowing layer against its inertial number, fitted on the
inclined layers (dem/calibration/chute.in) as dem/tools/chute.py binned them
(stdlib only).

Usage: rate_friction.py RESULTS_DIR
  RESULTS_DIR holds chute_friction.csv, chute_summary.csv and
  chute_thickness.csv (chute.py's outputs). Writes RESULTS_DIR/chute_rate.csv
  (quantity,value,unit) and prints each bin's fit.

The law: Jop, Forterre and Pouliquen's mu(I) (2006, "A constitutive law for
dense granular flows", Nature 441, (2)) on the thin-layer stop friction
(Pouliquen 1999), with the layer's inertial number from its depth and mean
speed as Pouliquen and Forterre read it (2002, "Friction law for dense
granular flows: application to the motion of a mass down a rough inclined
plane", J. Fluid Mech. 453):
  mu(h, I) = mu_stop(h) + (mu_2 - mu_stop(h)) I / (I_0 + I),
  I = u d / (h sqrt(g h)),
with u the layer's mean speed, h its thickness (layers x d), d the grain size
and mu_stop(h) the thin-layer stop law chute.py fitted (Pouliquen 1999:
tan theta_1 + (tan theta_2 - tan theta_1) exp(-h / (A d))). A Bagnold profile's
inertial number at the base is 5 u d / (2 h sqrt(phi g h cos theta)); its
constant (and cos theta, the slopes' 18-32 deg) goes into I_0, so I_0 is the
layer's, read with the same I the model computes (terrain/momentum_flow.h).
On the columns' floor (base 3) the layer slides on a plane whose stop
friction is mu_floor (the floor's stop angle): the same law with mu_floor for
mu_stop(h), the same mu_2 and its own I_0.

Fitted by weighted least squares over the speed bins (weight: the bin's
samples, at most 50), mu_2 and I_0 on the grains' open runs, then the
floor's I_0 on the floor's open runs (the walled runs are the walls').
"""
import csv
import math
import os
import sys

from dem_io import D50_M, G, read_quantities, thickest_open_run

MAX_WEIGHT = 50      # a bin's weight: its samples, at most this many


def bins(path, base):
    """(layers, mean speed, friction, weight) of the open runs on `base`."""
    out = []
    for r in csv.DictReader(open(path)):
        tag = r["run"]
        if not tag.startswith("base%d_n" % base) or "_w" in tag:
            continue
        u = 0.5 * (float(r["speed_from_m_s"]) + float(r["speed_to_m_s"]))
        out.append((int(tag.split("_n")[1]), u, float(r["mean_friction"]), min(int(r["samples"]), MAX_WEIGHT)))
    return out


def inertial(layers, u):
    h = layers * D50_M
    return u * D50_M / (h * math.sqrt(G * h))


def law(mu_stop, mu_2, i0, i):
    return mu_stop + (mu_2 - mu_stop) * i / (i0 + i)


def fit(cost, start, steps, lower):
    """Coordinate search: each parameter stepped both ways while the cost
    falls, the steps halved when none does (to 1/2^40 of the first)."""
    best, cbest = list(start), cost(start)
    for _ in range(40):
        moved = True
        while moved:
            moved = False
            for k in range(len(best)):
                for s in (-steps[k], steps[k]):
                    p = list(best)
                    p[k] = max(lower[k], p[k] + s)
                    c = cost(p)
                    if c < cbest:
                        best, cbest, moved = p, c, True
        steps = [s * 0.5 for s in steps]
    return best


def main():
    res = sys.argv[1]
    thick = read_quantities(os.path.join(res, "chute_thickness.csv"))
    mu_1 = math.tan(math.radians(float(thick["flowing_friction_angle_deg"])))
    mu_2s = math.tan(math.radians(float(thick["thin_layer_friction_angle_deg"])))
    decay = float(thick["thin_layer_decay_grains"])

    def mu_stop(layers):
        return mu_1 + (mu_2s - mu_1) * math.exp(-layers / decay)

    grains = bins(os.path.join(res, "chute_friction.csv"), 1)
    if len({n for n, _, _, _ in grains}) < 2:
        sys.exit("rate_friction.py: fewer than two layers on the grains in " + res)

    def cost(p):
        return sum(w * (law(mu_stop(n), p[0], p[1], inertial(n, u)) - m) ** 2 for n, u, m, w in grains)

    mu_2, i0 = fit(cost, [mu_2s + 0.1, 0.1], [0.05, 0.05], [mu_2s, 1e-4])
    summary = list(csv.DictReader(open(os.path.join(res, "chute_summary.csv"))))
    floor = bins(os.path.join(res, "chute_friction.csv"), 3)
    rows = [("rate_friction_angle_deg", "%.2f" % math.degrees(math.atan(mu_2)), "deg"),
            ("rate_friction_i0", "%.4f" % i0, "-")]
    print("  grains: mu_2 %.4f (%.2f deg), I_0 %.4f" % (mu_2, math.degrees(math.atan(mu_2)), i0))
    for n, u, m, _ in grains:
        print("    %2d grains %5.2f m/s: DEM %.3f, law %.3f" % (n, u, m, law(mu_stop(n), mu_2, i0, inertial(n, u))))
    if floor:
        # The floor's stop friction: as material_csv.py takes it, the thickest open run's.
        mu_f = float(thickest_open_run(summary, "3")["mu_s"])

        def floor_cost(p):
            return sum(w * (law(mu_f, mu_2, p[0], inertial(n, u)) - m) ** 2 for n, u, m, w in floor)

        (i0_f,) = fit(floor_cost, [0.5], [0.2], [1e-4])
        rows.append(("floor_rate_friction_i0", "%.4f" % i0_f, "-"))
        print("  floor: mu_floor %.4f, I_0 %.4f" % (mu_f, i0_f))
        for n, u, m, _ in floor:
            print("    %2d grains %5.2f m/s: DEM %.3f, law %.3f" % (n, u, m, law(mu_f, mu_2, i0_f, inertial(n, u))))
    with open(os.path.join(res, "chute_rate.csv"), "w") as f:
        f.write("quantity,value,unit\n")
        for r in rows:
            f.write("%s,%s,%s\n" % r)


if __name__ == "__main__":
    main()
