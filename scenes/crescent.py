#!/usr/bin/env python3
"""Writes scenes/crescent.obj, the moon of scenes/moon_hook.yaml: a closed
crescent of 3198 vertices, after Sekercioglu & Duysak's moon model (3198
atoms, 9504 bonds).

The crescent is a tube bent along an arc of radius 0.2 m over 260 degrees
in the x-y plane, its cross-section an ellipse whose half-width (in the
plane) is 0.06 m (0.3 + 0.7 sin(pi u)^0.5) at u from 0 to 1 along the arc
and whose half-height (along z) is 0.6 of that: thick in the middle,
blunt at each horn, closed there by a cone to a point on the arc. (Horns
that narrow to nothing have edges of a millimetre around their last ring,
whose angle and hinge terms need a much smaller time step.) 94 rings of 34 vertices and the two tips make 3198
vertices; quads between rings are split into two triangles, each tip is a
fan. A closed surface of V vertices has 3V - 6 edges, so this one has 9588
bonds, 0.9 % more than the seed's 9504 (which a closed surface of 3198
vertices cannot have: the seed's moon was presumably open somewhere).

    python3 scenes/crescent.py > scenes/crescent.obj
"""
import math

RINGS, AROUND = 94, 34
ARC_RADIUS, ARC_DEGREES = 0.2, 260.0
HALF_WIDTH, FLATNESS = 0.06, 0.6


def arc_point(u):
    """The arc's point and its outward direction in the plane at u."""
    angle = math.radians(-ARC_DEGREES / 2 + ARC_DEGREES * u)
    out = (math.cos(angle), math.sin(angle))
    return (ARC_RADIUS * out[0], ARC_RADIUS * out[1]), out


def vertices():
    yield arc_point(0.0)[0] + (0.0,)
    for i in range(1, RINGS + 1):
        u = i / (RINGS + 1)
        (cx, cy), (ox, oy) = arc_point(u)
        width = HALF_WIDTH * (0.3 + 0.7 * math.sin(math.pi * u) ** 0.5)
        for j in range(AROUND):
            t = 2 * math.pi * j / AROUND
            r, z = width * math.cos(t), FLATNESS * width * math.sin(t)
            yield (cx + r * ox, cy + r * oy, z)
    yield arc_point(1.0)[0] + (0.0,)


def triangles():
    """1-based OBJ indices, counter-clockwise seen from outside."""
    def ring(i, j):
        return 2 + (i - 1) * AROUND + j % AROUND

    last = 2 + RINGS * AROUND
    for j in range(AROUND):
        yield (1, ring(1, j), ring(1, j + 1))
    for i in range(1, RINGS):
        for j in range(AROUND):
            a, b = ring(i, j), ring(i, j + 1)
            c, d = ring(i + 1, j), ring(i + 1, j + 1)
            yield (a, d, b)
            yield (a, c, d)
    for j in range(AROUND):
        yield (last, ring(RINGS, j + 1), ring(RINGS, j))


def main():
    print("# crescent.obj: written by scenes/crescent.py (see there)")
    for x, y, z in vertices():
        print("v %.9g %.9g %.9g" % (x, y, z))
    for a, b, c in triangles():
        print("f %d %d %d" % (a, b, c))


if __name__ == "__main__":
    main()
