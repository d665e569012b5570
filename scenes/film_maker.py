#!/usr/bin/env python3
"""Writes the film maker's scenes, scenes/film_bounce.pov, film_shapes.pov
and film_map_on_table.pov: POV-Ray scenes of mesh2 objects in the form the
Spring Systems POV film maker reads (Juhasz & Bercovici: each mesh2 fixed,
`#local spring_system_fixed = true;`, or free with its spring constants,
mass and vicinity as locals), after its movies "Bounce", "Shapes" and "Map
on table", whose source files are not in the seed. POV-Ray's up is +y;
lengths in metres. Each also renders in POV-Ray as it is.

    python3 scenes/film_maker.py scenes
"""
import math
import os
import sys


def icosphere(radius, subdivisions):
    t = (1 + 5 ** 0.5) / 2
    points = [(-1, t, 0), (1, t, 0), (-1, -t, 0), (1, -t, 0), (0, -1, t), (0, 1, t),
              (0, -1, -t), (0, 1, -t), (t, 0, -1), (t, 0, 1), (-t, 0, -1), (-t, 0, 1)]
    faces = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
             (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8),
             (3, 8, 9), (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    points = [normalized(p) for p in points]
    for _ in range(subdivisions):
        middle = {}

        def between(a, b):
            key = (min(a, b), max(a, b))
            if key not in middle:
                points.append(normalized([(points[a][k] + points[b][k]) / 2 for k in range(3)]))
                middle[key] = len(points) - 1
            return middle[key]

        faces = [f for a, b, c in faces
                 for ab, bc, ca in [(between(a, b), between(b, c), between(c, a))]
                 for f in ((a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca))]
    return [tuple(radius * x for x in p) for p in points], faces


def normalized(p):
    length = math.sqrt(sum(x * x for x in p))
    return tuple(x / length for x in p)


def grid(n, corner, u, v):
    """An n x n grid of points corner + i/(n-1) u + j/(n-1) v, two
    triangles a cell, counter-clockwise seen from the side u x v points to."""
    points = [tuple(corner[k] + i / (n - 1) * u[k] + j / (n - 1) * v[k] for k in range(3))
              for j in range(n) for i in range(n)]
    faces = []
    for j in range(n - 1):
        for i in range(n - 1):
            a = j * n + i
            faces += [(a, a + 1, a + n + 1), (a, a + n + 1, a + n)]
    return points, faces


def box(center, half, n):
    """A closed box of six n x n grids, joined along its edges."""
    points, faces, index = [], [], {}
    cx, cy, cz = center
    hx, hy, hz = half
    sides = [((cx - hx, cy - hy, cz - hz), (0, 2 * hy, 0), (2 * hx, 0, 0)),  # -z
             ((cx - hx, cy - hy, cz + hz), (2 * hx, 0, 0), (0, 2 * hy, 0)),  # +z
             ((cx - hx, cy - hy, cz - hz), (2 * hx, 0, 0), (0, 0, 2 * hz)),  # -y
             ((cx - hx, cy + hy, cz - hz), (0, 0, 2 * hz), (2 * hx, 0, 0)),  # +y
             ((cx - hx, cy - hy, cz - hz), (0, 0, 2 * hz), (0, 2 * hy, 0)),  # -x
             ((cx + hx, cy - hy, cz - hz), (0, 2 * hy, 0), (0, 0, 2 * hz))]  # +x
    for corner, u, v in sides:
        side_points, side_faces = grid(n, corner, u, v)
        ids = []
        for p in side_points:
            key = tuple(round(x, 9) for x in p)
            if key not in index:
                index[key] = len(points)
                points.append(p)
            ids.append(index[key])
        faces += [tuple(ids[k] for k in f) for f in side_faces]
    return points, faces


def moved(shape, offset):
    points, faces = shape
    return [tuple(p[k] + offset[k] for k in range(3)) for p in points], faces


FIXED = "    #local spring_system_fixed = true;\n"


def free(ks, kb, ds, db, mass, vicinity):
    return ("    #local spring_system_ks = %g;\n    #local spring_system_kb = %g;\n"
            "    #local spring_system_ds = %g;\n    #local spring_system_db = %g;\n"
            "    #local spring_system_mass = %g;\n    #local spring_system_vicinity = %g;\n"
            "    #local spring_system_fixed = false;\n" % (ks, kb, ds, db, mass, vicinity))


def mesh2(name, shape, locals_, color):
    points, faces = shape
    # POV-Ray is left-handed: x right, y up, z into the picture
    text = "#declare %s = mesh2\n{\n%s" % (name, locals_)
    text += "    vertex_vectors {\n        %d,\n" % len(points)
    text += ",\n".join("        <%.9g, %.9g, %.9g>" % p for p in points)
    text += "\n    }\n    face_indices {\n        %d,\n" % len(faces)
    text += ",\n".join("        <%d, %d, %d>" % f for f in faces)
    text += "\n    }\n}\nobject { %s texture { pigment { color rgb <%s> } finish { ambient 0.3 diffuse 0.7 } } }\n\n" % (
        name, color)
    return text


def scene(title, camera, objects):
    text = "// %s: written by scenes/film_maker.py (see there)\n" % title
    text += "camera { location <%g, %g, %g> look_at <%g, %g, %g> }\n" % camera
    text += "light_source { <2, 5, -4> color rgb <1, 1, 1> }\nbackground { color rgb <1, 1, 1> }\n\n"
    return text + "".join(objects)


FLOOR = grid(9, (-1.2, 0, -1.2), (0, 0, 2.4), (2.4, 0, 0))  # normal +y


def bounce():
    return scene("Bounce: a soft ball dropped on a fixed floor", (0, 0.8, -3, 0, 0.4, 0), [
        mesh2("Floor", FLOOR, FIXED, "0.6, 0.6, 0.6"),
        mesh2("Ball", moved(icosphere(0.2, 2), (0, 0.7, 0)), free(600, 600, 2, 2, 3, 0.3), "0.9, 0.2, 0.1")])


def shapes():
    return scene("Shapes: a ball, a box and a block falling onto a fixed floor and onto each other",
                 (0.3, 1.4, -3, 0, 0.4, 0), [
        mesh2("Floor", FLOOR, FIXED, "0.6, 0.6, 0.6"),
        mesh2("Block", box((0, 0.15, 0), (0.35, 0.15, 0.25), 5), free(800, 800, 2, 2, 4, 0.25), "0.2, 0.5, 0.9"),
        mesh2("Ball", moved(icosphere(0.15, 2), (0.1, 0.75, 0)), free(600, 600, 2, 2, 2, 0.2), "0.9, 0.2, 0.1"),
        mesh2("Cube", box((-0.15, 1.2, 0.05), (0.12, 0.12, 0.12), 5), free(800, 800, 2, 2, 1, 0.2),
              "0.2, 0.8, 0.3")])


def map_on_table():
    return scene("Map on table: a map, tilted, falling flat onto a fixed table", (0.6, 1.6, -2.4, 0, 0.6, 0), [
        mesh2("Table", box((0, 0.35, 0), (0.4, 0.35, 0.3), 2), FIXED, "0.55, 0.35, 0.2"),
        mesh2("Map", grid(21, (-0.35, 0.8, -0.25), (0, 0.1, 0.5), (0.7, 0, 0)), free(300, 20, 0.5, 0.05, 0.3, 0),
              "0.95, 0.9, 0.7")])


def main():
    folder = sys.argv[1] if len(sys.argv) > 1 else "."
    for name, make in (("film_bounce.pov", bounce), ("film_shapes.pov", shapes),
                       ("film_map_on_table.pov", map_on_table)):
        with open(os.path.join(folder, name), "w") as f:
            f.write(make())


if __name__ == "__main__":
    main()
