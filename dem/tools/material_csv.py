#!/usr/bin/env python3
"""Collects the calibrated bulk properties into dem/calibration/material.csv (stdlib only).

Usage: material_csv.py CALIBRATION_RESULTS_DIR OUT.csv
       material_csv.py --flow RESULTS_DIR OUT.csv
Reads repose.csv, shear_box.csv (Mohr-Coulomb comment lines), sliding_plate.csv
(mean line), chute_summary.csv, chute_thickness.csv, bed.csv and, where present,
erodible_summary.csv, impact_summary.csv and chute_rate.csv (the friction's rise
with the inertial number, dem/tools/rate_friction.py) from the results folder.

From the inclined layers (chute_summary.csv): a flowing layer's friction on
the grains (the thickest layer run: the limit a thick flow reaches, what a
metre-scale model holds), on the collapsing columns' floor (likewise), and
the slot's side walls on a flowing layer (the mean over the walled runs).

From the erodible bed (erodible_summary.csv): the bed's start angle, midway
between the steepest angle at which the bed, 24 grains deep, held at rest
under every layer set moving on it and the gentlest at which it flowed by
itself before the kick.

From the granular jet (impact_summary.csv, dem/tools/impact.py): the share of
its fall speed a landing's sheet keeps.

--flow: only what a flowing layer's law takes (the pile, the inclined layers,
the erodible bed, the grains' size), for a material calibrated on those tests
alone (the friction side study, scripts/dem_reference.sh, stage friction);
the walls' row only where walled runs were made.
"""
import math
import os
import re
import sys

from dem_io import thickest_open_run


def kv(path):
    out = {}
    for line in open(path):
        p = line.strip().split(",")
        if len(p) >= 2 and not line.startswith("#"):
            out[p[0]] = p[1]
    return out


def flow_rows(d):
    """The flow law's rows: {quantity: (value, unit, source)}."""
    rep = kv(os.path.join(d, "repose.csv"))
    chute = [l.strip().split(",") for l in open(os.path.join(d, "chute_summary.csv"))]
    cols = chute[0]
    chute = [dict(zip(cols, r)) for r in chute[1:] if r and r[0]]

    def thickest(base):
        r = thickest_open_run(chute, base)
        return float(r["stop_angle_deg"]), int(r["layers"])

    grains_deg, grains_n = thickest("1")
    floor_deg, floor_n = thickest("3")
    walls = [float(r["wall_mu"]) for r in chute if float(r["side_wall_gap_m"]) > 0.0]
    law = kv(os.path.join(d, "chute_thickness.csv"))
    rows = {
        "repose_angle_deg": (float(rep["repose_angle_deg"]), "deg", "calibration/pile.in"),
        "flowing_friction_angle_deg": (grains_deg, "deg",
                                       "calibration/chute.in (stop angle; on frozen grains, %d grains thick)" % grains_n),
        "thin_layer_friction_angle_deg": (float(law["thin_layer_friction_angle_deg"]), "deg",
                                          "calibration/chute.in (a layer's stop angle as it thins, Pouliquen 1999; layers %s)"
                                          % law["layers_fitted"]),
        "thin_layer_decay_grains": (float(law["thin_layer_decay_grains"]), "-",
                                    "calibration/chute.in (the thickness, in grains, over which it falls to the flowing friction)"),
        "floor_flowing_friction_angle_deg": (floor_deg, "deg",
                                             "calibration/chute.in (stop angle; on the columns' type-3 floor, %d grains thick)"
                                             % floor_n),
        "particle_diameter_m": (0.008, "m", "material.in (3 classes 7.2/8.0/8.8 mm, equal mass)"),
    }
    if walls:
        rows["slot_wall_flowing_friction_angle_deg"] = (
            math.degrees(math.atan(sum(walls) / len(walls))), "deg",
            "calibration/chute.in (steel side walls 0.08 m apart, %d runs)" % len(walls))
    erodible_path = os.path.join(d, "erodible_summary.csv")
    if os.path.exists(erodible_path):
        lines = [l.strip().split(",") for l in open(erodible_path) if l.strip()]
        runs = [dict(zip(lines[0], r)) for r in lines[1:]]
        flowed = [float(r["theta_deg"]) for r in runs if r["bed_flowing"] == "1"]
        held_all = sorted({float(r["theta_deg"]) for r in runs
                           if all(q["stopped"] == "1" for q in runs if q["theta_deg"] == r["theta_deg"])})
        if flowed and held_all and max(held_all) < min(flowed):
            rows["bed_start_angle_deg"] = (0.5 * (max(held_all) + min(flowed)), "deg",
                                           "calibration/erodible.in (held at %g deg under every layer, flowed by itself at %g)"
                                           % (max(held_all), min(flowed)))
    rate_path = os.path.join(d, "chute_rate.csv")
    if os.path.exists(rate_path):
        rate = kv(rate_path)
        fit = "against the inertial number; dem/tools/rate_friction.py"
        source = "calibration/chute.in (the layers as they slow, %s)" % fit
        rows["rate_friction_angle_deg"] = (float(rate["rate_friction_angle_deg"]), "deg", source)
        rows["rate_friction_i0"] = (float(rate["rate_friction_i0"]), "-", source)
        if "floor_rate_friction_i0" in rate:
            rows["floor_rate_friction_i0"] = (float(rate["floor_rate_friction_i0"]), "-",
                                              "calibration/chute.in (the layers on the columns' floor as they slow, %s)" % fit)
    return rows


RATE_ROWS = ("rate_friction_angle_deg", "rate_friction_i0", "floor_rate_friction_i0")


def write(out, rows):
    with open(out, "w") as f:
        f.write("quantity,value,unit,source_deck\n")
        for q, v, u, s in rows:
            f.write(f"{q},{v:.4g},{u},{s}\n")
    print(open(out).read())


def main():
    if sys.argv[1] == "--flow":
        d, out = sys.argv[2], sys.argv[3]
        flow = flow_rows(d)
        order = ("repose_angle_deg", "flowing_friction_angle_deg", "thin_layer_friction_angle_deg",
                 "thin_layer_decay_grains", "floor_flowing_friction_angle_deg", "slot_wall_flowing_friction_angle_deg",
                 "particle_diameter_m", "bed_start_angle_deg") + RATE_ROWS
        write(out, [(q,) + flow[q] for q in order if q in flow])
        return
    d, out = sys.argv[1], sys.argv[2]
    flow = flow_rows(d)
    bed = kv(os.path.join(d, "bed.csv"))
    shear = open(os.path.join(d, "shear_box.csv")).read()
    pk = re.search(r"peak: phi_deg=([-\d.]+) c_Pa=([-\d.]+)", shear)
    rs = re.search(r"residual: phi_deg=([-\d.]+) c_Pa=([-\d.]+)", shear)
    p0 = re.search(r"through the origin \(c = 0\): phi_deg=([-\d.]+)", shear)
    slide = open(os.path.join(d, "sliding_plate.csv")).read()
    dl = re.search(r"delta_deg=([-\d.]+)", slide)
    rows_optional = [("bed_start_angle_deg",) + flow["bed_start_angle_deg"]] if "bed_start_angle_deg" in flow else []
    impact_path = os.path.join(d, "impact_summary.csv")
    if os.path.exists(impact_path):
        jet = kv(impact_path)
        rows_optional.append(("impact_sheet_speed_ratio", float(jet["impact_sheet_speed_ratio"]), "-",
                              "collapse/column.in as a jet (%s m across, %s m long, let go %s m up; dem/tools/impact.py)"
                              % (2 * float(jet["jet_radius_m"]), jet["jet_length_m"], jet["drop_m"])))
    rows = [("repose_angle_deg",) + flow["repose_angle_deg"],
        ("friction_angle_deg", float(pk.group(1)), "deg", "calibration/shear_box.in (peak, 2-10 kPa)"),
        ("cohesion_kPa", float(pk.group(2)) / 1000, "kPa", "calibration/shear_box.in (peak intercept)"),
        ("friction_angle_c0_deg", float(p0.group(1)), "deg", "calibration/shear_box.in (peak, fit with c = 0)"),
        ("residual_friction_angle_deg", float(rs.group(1)), "deg", "calibration/shear_box.in (end: last 25 % of 18 mm)"),
        ("residual_cohesion_kPa", float(rs.group(2)) / 1000, "kPa", "calibration/shear_box.in (residual intercept)"),
        ("tool_friction_angle_deg", float(dl.group(1)), "deg", "calibration/sliding_plate.in")] + [
        (q,) + flow[q] for q in ("flowing_friction_angle_deg", "thin_layer_friction_angle_deg", "thin_layer_decay_grains",
                                 "floor_flowing_friction_angle_deg", "slot_wall_flowing_friction_angle_deg")] + [
        ("bulk_density_kg_m3", float(bed["bulk_density_kg_m3"]), "kg/m3", "blade/bed.in (core of the settled bed)"),
        ("particle_diameter_m",) + flow["particle_diameter_m"],
        ("particle_density_kg_m3", 2650.0, "kg/m3", "material.in"),
    ] + rows_optional + [(q,) + flow[q] for q in RATE_ROWS if q in flow]
    write(out, rows)


if __name__ == "__main__":
    main()
