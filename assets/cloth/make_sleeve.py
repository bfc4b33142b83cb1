#!/usr/bin/env python3
"""Writes sleeve.obj: an open tube of cloth (a sleeve) along x, centred on the origin.

The tube has `around` vertices per ring and `rings` rings; faces are wound so their normals
point outward. Each face corner carries a `vt` in metres, the tube cut along its seam and
unrolled (u around the circumference, v along the axis), so the rest shape is the flat fabric
the sleeve is sewn from: the seam's faces use u = circumference at their far corners.

    python3 assets/cloth/make_sleeve.py [radius length around rings] > assets/cloth/sleeve.obj
"""
import math
import sys


def main():
    radius, length, around, rings = 0.04, 0.12, 32, 16
    if len(sys.argv) == 5:
        radius, length = float(sys.argv[1]), float(sys.argv[2])
        around, rings = int(sys.argv[3]), int(sys.argv[4])
    out = ["# dexcloth sleeve: radius %g m, length %g m, %d x %d vertices (make_sleeve.py)"
           % (radius, length, around, rings)]
    for j in range(rings):
        x = -0.5 * length + length * j / (rings - 1)
        for i in range(around):
            phi = 2.0 * math.pi * i / around
            out.append("v %.9f %.9f %.9f" % (x, radius * math.cos(phi), radius * math.sin(phi)))
    # Texture coordinates: (around + 1) per ring, the last one the seam's far side.
    for j in range(rings):
        y = -0.5 * length + length * j / (rings - 1)
        for i in range(around + 1):
            out.append("vt %.9f %.9f" % (2.0 * math.pi * radius * i / around, y))

    def v(i, j):
        return j * around + (i % around) + 1

    def t(i, j):
        return j * (around + 1) + i + 1

    for j in range(rings - 1):
        for i in range(around):
            a, b = (i, j), (i + 1, j)
            c, d = (i + 1, j + 1), (i, j + 1)
            # Counter-clockwise in (u, v) and, as u turns about +x, outward in 3D.
            tri = [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
            for f in tri:
                out.append("f " + " ".join("%d/%d" % (v(*p), t(*p)) for p in f))
    print("\n".join(out))


if __name__ == "__main__":
    main()
