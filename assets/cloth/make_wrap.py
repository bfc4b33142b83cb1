#!/usr/bin/env python3
"""Writes wrap_strip.obj: a cloth strip wound one and a half turns round a horizontal post.

The post is a cylinder along y through (0, 0, height). The strip's short leg hangs down the
post's -x side, climbs over the top, winds 3*pi round the post as a helix of pitch `pitch` (so
that the turns do not touch) and leaves down the +x side as the long leg. Its rest shape, given
by the `vt` of each vertex in metres, is the flat fabric: the strip unrolled off the post, a band
sheared sideways along the wound part, so the strip starts unstretched.

    python3 assets/cloth/make_wrap.py [short_leg long_leg] > assets/cloth/wrap_strip.obj
"""
import math
import sys

POST_RADIUS = 0.03   # [m]
THICKNESS = 0.005    # the scenes' repulsion thickness [m]
HEIGHT = 0.5         # post axis [m]
WIDTH = 0.03         # strip width, along y [m]
PITCH = 0.05         # y advance per turn of the wound part [m]
TURNED = 3.0 * math.pi
SPACING = 0.005      # along the strip [m]
ACROSS = 7           # vertices across


def main():
    short_leg, long_leg = 0.05, 0.30
    if len(sys.argv) == 3:
        short_leg, long_leg = float(sys.argv[1]), float(sys.argv[2])
    r = POST_RADIUS + THICKNESS + 1e-4  # the strip's mid-surface, one thickness off the post
    wound = r * TURNED                   # arc of the wound part, round the post [m]
    length = short_leg + wound + long_leg
    along = int(round(length / SPACING)) + 1
    slope = PITCH / (2.0 * math.pi * r)  # y per unit of arc round the post

    def shift(u):
        """y offset of the strip's centre line at unrolled length u."""
        return slope * min(max(u - short_leg, 0.0), wound) - 0.5 * PITCH * TURNED / (2 * math.pi)

    out = ["# dexcloth wrap strip: legs %g and %g m, %.3g turns round a %g m post, %d x %d "
           "vertices (make_wrap.py)" % (short_leg, long_leg, TURNED / (2 * math.pi),
                                        POST_RADIUS, along, ACROSS)]
    uv = []
    for i in range(along):
        u = length * i / (along - 1)
        if u <= short_leg:
            x, z = -r, HEIGHT - (short_leg - u)
        elif u <= short_leg + wound:
            psi = math.pi - (u - short_leg) / r
            x, z = r * math.cos(psi), HEIGHT + r * math.sin(psi)
        else:
            x, z = r, HEIGHT - (u - short_leg - wound)
        for j in range(ACROSS):
            y = WIDTH * (j / (ACROSS - 1.0) - 0.5) + shift(u)
            out.append("v %.9f %.9f %.9f" % (x, y, z))
            uv.append((u, y))
    out += ["vt %.9f %.9f" % p for p in uv]
    for i in range(along - 1):
        for j in range(ACROSS - 1):
            a = i * ACROSS + j + 1
            b, d = a + ACROSS, a + 1
            c = b + 1
            out.append("f %d/%d %d/%d %d/%d" % (a, a, b, b, c, c))
            out.append("f %d/%d %d/%d %d/%d" % (a, a, c, c, d, d))
    print("\n".join(out))


if __name__ == "__main__":
    main()
