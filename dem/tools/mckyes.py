#!/usr/bin/env python3
"""McKyes-Ali (1977) / McKyes (1985) three-dimensional earthmoving equation,
no adhesion, no surcharge (stdlib only).

  F  = w (gamma d^2 N_gamma + c d N_c)        (c_a = q = 0)
  D  = cos(a+delta) + sin(a+delta) cot(beta+phi)
  N_gamma = (r / 2d) [1 + (2/3)(r/w) sin rho'] / D
  N_c     = [1 + cot(beta) cot(beta+phi)] [1 + (r/w) sin rho'] / D
  r  = d (cot a + cot beta)           rupture distance ahead of the blade at the surface
  rho' = acos(d cot a / r)            half-angle of the side crescents (they end beside the edge)
  beta minimises F (1..89 deg, 0.01 deg grid; D > 0 required).
  Draft (x, against travel) H = F sin(a+delta); vertical force on the tool,
  upward positive, Vup = -F cos(a+delta).

Usage as a module: mckyes(alpha_deg, d, w, phi_deg, delta_deg, gamma, c=0) -> dict
Usage as a script: mckyes.py alpha_deg d w phi_deg delta_deg gamma [c]
"""
import math
import sys


def factors(a, beta, d, w, phi, delta):
    D = math.cos(a + delta) + math.sin(a + delta) / math.tan(beta + phi)
    if D <= 0:
        return None
    r = d * (1 / math.tan(a) + 1 / math.tan(beta))
    rho = math.acos(max(-1.0, min(1.0, d / math.tan(a) / r)))
    ng = r / (2 * d) * (1 + 2.0 / 3.0 * (r / w) * math.sin(rho)) / D
    nc = (1 + 1 / math.tan(beta) / math.tan(beta + phi)) * (1 + (r / w) * math.sin(rho)) / D
    return ng, nc, r, rho


def mckyes(alpha_deg, d, w, phi_deg, delta_deg, gamma, c=0.0, sides=True):
    a, phi, delta = (math.radians(x) for x in (alpha_deg, phi_deg, delta_deg))
    best = None
    for i in range(100, 8901):
        beta = math.radians(i / 100)
        res = factors(a, beta, d, w if sides else 1e30, phi, delta)
        if res is None:
            continue
        F = w * (gamma * d * d * res[0] + c * d * res[1])
        if best is None or F < best[0]:
            best = (F, beta) + res
    F, beta, Ng, Nc, r, rho = best
    return {"N_gamma": Ng, "N_c": Nc, "beta_deg": math.degrees(beta), "r_m": r, "rho_deg": math.degrees(rho),
            "F_N": F, "draft_N": F * math.sin(a + delta), "vertical_up_N": -F * math.cos(a + delta),
            "N_draft": F * math.sin(a + delta) / (gamma * d * d * w)}


if __name__ == "__main__":
    args = [float(x) for x in sys.argv[1:8]]
    for k, v in mckyes(*args).items():
        print(f"{k} {v:.4f}")
