#!/usr/bin/env python3
"""Writes the generated scenes under scenes/ (OBJ + MTL + scene TOML).

Run from the repository's root: python3 scripts/generate_scenes.py
Every polygon is counter-clockwise seen from its lit side (OBJ convention).
"""
import math
import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes")


class Obj:
    def __init__(self):
        self.vertices = []
        self.lines = []

    def face(self, name, material, points):
        self.lines.append(f"o {name}\nusemtl {material}")
        for p in points:
            self.vertices.append(p)
            self.lines.append("v {:.6f} {:.6f} {:.6f}".format(*p))
        n = len(points)
        self.lines.append("f " + " ".join(str(-n + k) for k in range(n)))

    def box(self, name, material, lo, hi, bottom=False):
        """An axis-aligned box with outward faces (no bottom unless asked)."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        self.face(name, material, [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)])  # top, +y
        self.face(name, material, [(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)])  # -z
        self.face(name, material, [(x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (x0, y0, z1)])  # +z
        self.face(name, material, [(x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (x0, y0, z0)])  # -x
        self.face(name, material, [(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)])  # +x
        if bottom:
            self.face(name, material, [(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)])

    def write(self, path, header, mtllib):
        with open(path, "w") as f:
            f.write(header + f"\nmtllib {mtllib}\n\n" + "\n".join(self.lines) + "\n")


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def disc(centre, radius, sides, tilt_deg):
    """A disc facing down (-y), tilted by tilt_deg about the z axis."""
    t = math.radians(tilt_deg)
    # Its plane's axes: u (tilted x) and z; normal = (sin t, -cos t, 0).
    u = (math.cos(t), math.sin(t), 0.0)
    w = (0.0, 0.0, 1.0)
    points = []
    for k in range(sides):
        a = 2 * math.pi * k / sides
        points.append(tuple(centre[i] + radius * (math.cos(a) * u[i] + math.sin(a) * w[i]) for i in range(3)))
    # u × w = (sin t, -cos t, 0) is the normal; counter-clockwise about it: keep order.
    return points


def seed(tilt):
    name = f"seed_disc_{'tilted' if tilt else 'flat'}"
    folder = os.path.join(ROOT, "seed")
    os.makedirs(folder, exist_ok=True)
    obj = Obj()
    obj.face("floor", "floor", [(-5, 0, -5), (-5, 0, 5), (5, 0, 5), (5, 0, -5)])
    obj.face("lamp", "lamp", disc((0.0, 1.0, 0.0), 0.1, 64, tilt))
    obj.write(os.path.join(folder, name + ".obj"),
              f"# The seed paper's case (Arques, Biri, Derpierre 2005): a small disc of\n"
              f"# radius 0.1 m at 1 m over a 10 x 10 m plane, tilted {tilt} degrees. Metres.",
              "seed.mtl")
    write(os.path.join(folder, name + ".toml"),
          f'# Small disc over a plane, tilted {tilt} degrees (isorad scene file).\n'
          f'obj = "{name}.obj"\n\n[camera]\nposition = [0.0, 7.0, -9.0]\nlook_at = [0.0, 0.0, 0.0]\n'
          f'up = [0.0, 1.0, 0.0]\nvfov_deg = 50.0\nwidth = 512\nheight = 512\n\n[mesh]\nkind = "contour"\n')


def seed_material():
    write(os.path.join(ROOT, "seed", "seed.mtl"),
          "# Floor: grey diffuse. Lamp: emits 100 W/(m2 sr), reflects nothing.\n"
          "newmtl floor\nKd 0.5 0.5 0.5\n\nnewmtl lamp\nKd 0 0 0\nKe 100 100 100\n")


def room():
    folder = os.path.join(ROOT, "room")
    os.makedirs(folder, exist_ok=True)
    obj = Obj()
    X, Y, Z = 6.0, 3.0, 4.0
    obj.face("floor", "floor", [(0, 0, 0), (0, 0, Z), (X, 0, Z), (X, 0, 0)])
    obj.face("ceiling", "white", [(0, Y, 0), (X, Y, 0), (X, Y, Z), (0, Y, Z)])
    obj.face("back_wall", "white", [(0, 0, Z), (0, Y, Z), (X, Y, Z), (X, 0, Z)])
    obj.face("front_wall", "white", [(0, 0, 0), (X, 0, 0), (X, Y, 0), (0, Y, 0)])
    obj.face("left_wall", "blue", [(0, 0, 0), (0, Y, 0), (0, Y, Z), (0, 0, Z)])
    obj.face("right_wall", "white", [(X, 0, 0), (X, 0, Z), (X, Y, Z), (X, Y, 0)])
    # A table: a 1.4 x 0.8 m top at 0.75 m on four legs.
    tx, tz = 2.6, 1.6
    obj.box("table_top", "wood", (tx, 0.72, tz), (tx + 1.4, 0.75, tz + 0.8), bottom=True)
    for dx in (0.05, 1.3):
        for dz in (0.05, 0.7):
            obj.box("table_leg", "wood", (tx + dx, 0.0, tz + dz), (tx + dx + 0.05, 0.72, tz + dz + 0.05))
    # A small square luminaire, 0.25 m, tilted 30 degrees, 2.4 m up, off to one side.
    t = math.radians(30)
    c = (4.2, 2.4, 2.0)
    u = (math.cos(t), math.sin(t), 0.0)
    w = (0.0, 0.0, 1.0)
    h = 0.125
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]  # counter-clockwise about u x w: facing down
    obj.face("luminaire", "lamp",
             [tuple(c[i] + h * (a * u[i] + b * w[i]) for i in range(3)) for a, b in corners])
    obj.write(os.path.join(folder, "room.obj"),
              "# A 6 x 3 x 4 m room with a table and one small luminaire tilted 30 degrees\n"
              "# towards the wall at x = 6 m; the table casts a shadow on the floor. Metres.",
              "room.mtl")
    write(os.path.join(folder, "room.mtl"),
          "newmtl floor\nKd 0.45 0.42 0.38\n\nnewmtl white\nKd 0.75 0.75 0.72\n\n"
          "newmtl blue\nKd 0.25 0.35 0.6\n\nnewmtl wood\nKd 0.5 0.33 0.2\n\n"
          "newmtl lamp\nKd 0 0 0\nKe 400 380 340\n")
    write(os.path.join(folder, "room.toml"),
          '# A room with a table under a small tilted luminaire (isorad scene file).\n'
          'obj = "room.obj"\n\n[camera]\nposition = [0.6, 1.7, 0.3]\nlook_at = [3.6, 0.6, 2.6]\n'
          'up = [0.0, 1.0, 0.0]\nvfov_deg = 65.0\nwidth = 640\nheight = 480\n\n[mesh]\nkind = "contour"\n')


if __name__ == "__main__":
    seed(0)
    seed(30)
    seed_material()
    room()
