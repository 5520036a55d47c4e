#!/usr/bin/env python3
"""Generate the ASCII STL meshes used by the DEM decks (stdlib only).

Usage: meshes.py OUTDIR

Every mesh is built from flat quadrilaterals, split into triangles no longer
than ~10 mm a side so that LIGGGHTS' mesh neighbour search stays local.
Coordinates are in metres.

  blade_a90.stl, blade_a60.stl : flat blade, width 0.1 m (y = -0.05..0.05),
      cutting edge along the y axis at the origin, face rising to z = 0.16 m
      (vertical height), leaning back (towards -x) by 90 - rake degrees.
  pedestal.stl   : disc of radius 0.15 m at z = 0 (heap base, rough type 3).
  shear_lower_box.stl, shear_lower_floor.stl, shear_upper_ring.stl,
  shear_lid.stl  : direct shear box, 0.15 x 0.15 m, shear plane z = 0.04 m.
  slide_ring.stl, slide_plate.stl : interface shear (sliding plate) test: fixed
      ring 0.15 x 0.15 m (z 0.002..0.24) over a steel plate at z = 0.
  bucket.stl     : open bucket (floor, back, two sides), hinge line on the
      y axis at the top of the back plate.
  wheel_rim.stl, wheel_sides.stl : rigid wheel, radius 0.15 m, width 0.1 m,
      axle along y through the origin; the rim (120 facets round, a facet
      7.9 mm long, about a grain) and the two side discs (steel) that close it.
  plate_r30.stl, plate_r50.stl : circular sinkage plates of radius 0.03 and
      0.05 m at z = 0 (Bekker's pressure-sinkage test).
"""
import math
import os
import sys

H_MAX = 0.010  # largest triangle edge, m


def sub(a, b):
    return [a[i] - b[i] for i in range(3)]


def lerp(a, b, t):
    return [a[i] + (b[i] - a[i]) * t for i in range(3)]


def quad(p0, p1, p2, p3, h=H_MAX):
    """Quadrilateral p0-p1-p2-p3 (in order round the edge) as triangles."""
    l01 = math.dist(p0, p1)
    l12 = math.dist(p1, p2)
    n = max(1, math.ceil(l01 / h))
    m = max(1, math.ceil(l12 / h))
    tris = []
    for i in range(n):
        for j in range(m):
            def pt(u, v):
                a = lerp(p0, p1, u)
                b = lerp(p3, p2, u)
                return lerp(a, b, v)
            u0, u1, v0, v1 = i / n, (i + 1) / n, j / m, (j + 1) / m
            a, b, c, d = pt(u0, v0), pt(u1, v0), pt(u1, v1), pt(u0, v1)
            tris.append((a, b, c))
            tris.append((a, c, d))
    return tris


def normal(t):
    u, v = sub(t[1], t[0]), sub(t[2], t[0])
    n = [u[1] * v[2] - u[2] * v[1], u[2] * v[0] - u[0] * v[2], u[0] * v[1] - u[1] * v[0]]
    L = math.sqrt(sum(c * c for c in n)) or 1.0
    return [c / L for c in n]


def write_stl(path, name, tris):
    with open(path, "w") as f:
        f.write(f"solid {name}\n")
        for t in tris:
            n = normal(t)
            f.write(f"  facet normal {n[0]:.6e} {n[1]:.6e} {n[2]:.6e}\n    outer loop\n")
            for p in t:
                f.write(f"      vertex {p[0]:.6e} {p[1]:.6e} {p[2]:.6e}\n")
            f.write("    endloop\n  endfacet\n")
        f.write(f"endsolid {name}\n")


def box_walls(x0, x1, y0, y1, z0, z1):
    """Four vertical walls of a rectangular box (no floor, no lid)."""
    t = []
    t += quad([x0, y0, z0], [x1, y0, z0], [x1, y0, z1], [x0, y0, z1])
    t += quad([x0, y1, z0], [x1, y1, z0], [x1, y1, z1], [x0, y1, z1])
    t += quad([x0, y0, z0], [x0, y1, z0], [x0, y1, z1], [x0, y0, z1])
    t += quad([x1, y0, z0], [x1, y1, z0], [x1, y1, z1], [x1, y0, z1])
    return t


def flat(x0, x1, y0, y1, z):
    return quad([x0, y0, z], [x1, y0, z], [x1, y1, z], [x0, y1, z])


def flange(x0, x1, y0, y1, z, w):
    """Horizontal frame of width w around the rectangle x0..x1, y0..y1."""
    t = []
    t += flat(x0 - w, x1 + w, y0 - w, y0, z)
    t += flat(x0 - w, x1 + w, y1, y1 + w, z)
    t += flat(x0 - w, x0, y0, y1, z)
    t += flat(x1, x1 + w, y0, y1, z)
    return t


def blade(rake_deg, width=0.10, height=0.16):
    a = math.radians(rake_deg)
    back = height / math.tan(a) if rake_deg < 89.999 else 0.0
    y0, y1 = -width / 2, width / 2
    return quad([0, y0, 0], [0, y1, 0], [-back, y1, height], [-back, y0, height])


def disc(R, z=0.0, nseg=96, nring=15):
    tris = []
    for k in range(nring):
        r0, r1 = R * k / nring, R * (k + 1) / nring
        for s in range(nseg):
            a0, a1 = 2 * math.pi * s / nseg, 2 * math.pi * (s + 1) / nseg
            p00 = [r0 * math.cos(a0), r0 * math.sin(a0), z]
            p01 = [r0 * math.cos(a1), r0 * math.sin(a1), z]
            p10 = [r1 * math.cos(a0), r1 * math.sin(a0), z]
            p11 = [r1 * math.cos(a1), r1 * math.sin(a1), z]
            if k == 0:
                tris.append(([0, 0, z], p10, p11))
            else:
                tris.append((p00, p10, p11))
                tris.append((p00, p11, p01))
    return tris


def bucket(width=0.12, floor=0.08, back=0.08):
    """Bucket in its own frame: hinge on the y axis at (0, 0, 0) = top of the
    back plate; back plate from z = 0 down to z = -back at x = 0; floor from
    the back plate's foot forward to the cutting edge at x = floor, z = -back;
    sides fill the right-angled triangle-free rectangle between them
    (an open-topped, open-fronted box)."""
    y0, y1 = -width / 2, width / 2
    t = []
    t += quad([0, y0, -back], [floor, y0, -back], [floor, y1, -back], [0, y1, -back])  # floor
    t += quad([0, y0, -back], [0, y1, -back], [0, y1, 0], [0, y0, 0])  # back
    t += quad([0, y0, -back], [floor, y0, -back], [floor, y0, 0], [0, y0, 0])  # side -y
    t += quad([0, y1, -back], [floor, y1, -back], [floor, y1, 0], [0, y1, 0])  # side +y
    return t


def wheel_rim(r=0.15, width=0.10, nseg=120):
    """Cylinder of radius r about the y axis, y = -width/2..width/2; angle a
    from the downward vertical, x = r sin a, z = -r cos a."""
    def p(a, y):
        return [r * math.sin(a), y, -r * math.cos(a)]
    y0, y1 = -width / 2, width / 2
    t = []
    for s in range(nseg):
        a0, a1 = 2 * math.pi * s / nseg, 2 * math.pi * (s + 1) / nseg
        t += quad(p(a0, y0), p(a1, y0), p(a1, y1), p(a0, y1))
    return t


def wheel_sides(r=0.15, width=0.10):
    """The two side discs of the wheel: disc() turned into the x-z plane at y = +-width/2."""
    t = []
    for y in (-width / 2, width / 2):
        for tri in disc(r, nseg=60, nring=8):
            t.append(tuple([q[0], y, q[1]] for q in tri))
    return t


def main():
    out = sys.argv[1] if len(sys.argv) > 1 else "."
    os.makedirs(out, exist_ok=True)
    for rake in (90, 60):
        write_stl(os.path.join(out, f"blade_a{rake}.stl"), f"blade_a{rake}", blade(rake))
    write_stl(os.path.join(out, "pedestal.stl"), "pedestal", disc(0.15))
    # direct shear box: 0.15 x 0.15, lower box z 0..0.04, upper ring z 0.04..0.24
    L = 0.15
    write_stl(os.path.join(out, "shear_lower_box.stl"), "shear_lower_box",
              box_walls(0, L, 0, L, 0, 0.04) + flange(0, L, 0, L, 0.04, 0.04))
    write_stl(os.path.join(out, "shear_lower_floor.stl"), "shear_lower_floor", flat(0, L, 0, L, 0.0))
    write_stl(os.path.join(out, "shear_upper_ring.stl"), "shear_upper_ring",
              box_walls(0, L, 0, L, 0.04, 0.24) + flange(0, L, 0, L, 0.04, 0.04))
    g = 0.0015
    write_stl(os.path.join(out, "shear_lid.stl"), "shear_lid", flat(g, L - g, g, L - g, 0.0))
    # sliding plate (interface shear): fixed ring 0.15 x 0.15 standing 2 mm above a steel plate
    # that slides underneath it; the lid is shear_lid.stl
    write_stl(os.path.join(out, "slide_ring.stl"), "slide_ring", box_walls(0, L, 0, L, 0.002, 0.24))
    write_stl(os.path.join(out, "slide_plate.stl"), "slide_plate", flat(-0.06, 0.26, -0.05, 0.20, 0.0))
    write_stl(os.path.join(out, "bucket.stl"), "bucket", bucket())
    write_stl(os.path.join(out, "wheel_rim.stl"), "wheel_rim", wheel_rim())
    write_stl(os.path.join(out, "wheel_sides.stl"), "wheel_sides", wheel_sides())
    for radius_mm in (30, 50):
        write_stl(os.path.join(out, f"plate_r{radius_mm}.stl"), f"plate_r{radius_mm}", disc(radius_mm / 1000.0, nseg=48, nring=5))


if __name__ == "__main__":
    main()
