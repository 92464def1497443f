#!/usr/bin/env python3
"""Writes the daylight test scenes under scenes/daylight/ (OBJ + MTL + scene
TOML + work-plane points), the scenes bench/daylight_radiance.py computes a
Radiance reference for.

Run from anywhere: python3 scripts/generate_daylight_scenes.py

Conventions: +y up, metres, north = -z (so the south wall is at the largest
z). Every polygon is counter-clockwise seen from its front, and every room
surface faces into the room. Walls are single polygons except the office's
window wall (0.2 m thick, with reveals). An opening is missing geometry: the
surface around it is written as four rectangles.

Scenes:
  roof_opening      4 x 4 x 3 m black room, 1 x 1 m hole in the ceiling's centre
  facade_opening    the same room, a 2 m x 1.2 m hole (sill 0.9 m) in the south wall
  glazed_facade     facade_opening with a pane (Tf 0.8) filling the hole
  daylit_office     6 m deep x 4 m wide x 3 m high office (ceiling 0.7, walls 0.5,
                    floor 0.2), 3 m x 1.5 m window (Tf 0.7, sill 0.8 m) in a
                    0.2 m thick south wall, two desks and a cabinet
"""
import os

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "scenes", "daylight")

SKY_OVERCAST = """
[sky]
model = "cie_overcast"
horizontal_illuminance = 10000.0  # lux, sky alone
ground_reflectance = 0.2
north = [0.0, 0.0, -1.0]
"""

SKY_CLEAR = """
[sky]
model = "cie_clear"
horizontal_illuminance = 10000.0  # lux, sky alone
ground_reflectance = 0.2
north = [0.0, 0.0, -1.0]

[sun]
altitude_deg = 40.0
azimuth_deg = 180.0
normal_illuminance = 70000.0  # lux
"""


def sub(a, b):
    return tuple(x - y for x, y in zip(a, b))


def add(a, b):
    return tuple(x + y for x, y in zip(a, b))


def cross(a, b):
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dot(a, b):
    return sum(x * y for x, y in zip(a, b))


class Obj:
    def __init__(self):
        self.lines = []
        self.faces = []  # (name, points) for the checks

    def face(self, name, material, points):
        self.lines.append(f"o {name}\nusemtl {material}")
        for p in points:
            self.lines.append("v {:.6f} {:.6f} {:.6f}".format(*p))
        n = len(points)
        self.lines.append("f " + " ".join(str(-n + k) for k in range(n)))
        self.faces.append((name, points))

    def rect(self, name, material, origin, a, b, front):
        """The rectangle origin + [0,1]a + [0,1]b, counter-clockwise about
        the normal that points along `front`."""
        n = cross(a, b)
        if dot(n, front) < 0:
            a, b = b, a
        assert dot(cross(a, b), front) > 0, name
        self.face(name, material, [origin, add(origin, a), add(add(origin, a), b), add(origin, b)])

    def box(self, name, material, lo, hi):
        """A solid axis-aligned box standing on the floor: five outward faces."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        dx, dy, dz = (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, z1 - z0)
        self.rect(name, material, (x0, y1, z0), dx, dz, (0, 1, 0))
        self.rect(name, material, (x0, y0, z0), dx, dy, (0, 0, -1))
        self.rect(name, material, (x0, y0, z1), dx, dy, (0, 0, 1))
        self.rect(name, material, (x0, y0, z0), dy, dz, (-1, 0, 0))
        self.rect(name, material, (x1, y0, z0), dy, dz, (1, 0, 0))

    def write(self, path, header, mtllib):
        with open(path, "w") as f:
            f.write(header + f"\nmtllib {mtllib}\n\n" + "\n".join(self.lines) + "\n")


def write(path, text):
    with open(path, "w") as f:
        f.write(text)


def room(obj, w, d, h, materials, roof_hole=None, south_hole=None, skip_south=False):
    """A closed w (x) by d (z) by h (y) room from the origin, every surface
    facing in. `roof_hole` = (x0, x1, z0, z1), `south_hole` = (x0, x1, y0, y1)
    leave openings in the ceiling or in the south wall (z = d)."""
    floor, ceiling, wall = materials
    obj.rect("floor", floor, (0, 0, 0), (w, 0, 0), (0, 0, d), (0, 1, 0))
    if roof_hole is None:
        obj.rect("ceiling", ceiling, (0, h, 0), (w, 0, 0), (0, 0, d), (0, -1, 0))
    else:
        x0, x1, z0, z1 = roof_hole
        down = (0, -1, 0)
        obj.rect("ceiling", ceiling, (0, h, 0), (w, 0, 0), (0, 0, z0), down)
        obj.rect("ceiling", ceiling, (0, h, z1), (w, 0, 0), (0, 0, d - z1), down)
        obj.rect("ceiling", ceiling, (0, h, z0), (x0, 0, 0), (0, 0, z1 - z0), down)
        obj.rect("ceiling", ceiling, (x1, h, z0), (w - x1, 0, 0), (0, 0, z1 - z0), down)
    obj.rect("wall_west", wall, (0, 0, 0), (0, h, 0), (0, 0, d), (1, 0, 0))
    obj.rect("wall_east", wall, (w, 0, 0), (0, h, 0), (0, 0, d), (-1, 0, 0))
    obj.rect("wall_north", wall, (0, 0, 0), (w, 0, 0), (0, h, 0), (0, 0, 1))
    if skip_south:
        return
    if south_hole is None:
        obj.rect("wall_south", wall, (0, 0, d), (w, 0, 0), (0, h, 0), (0, 0, -1))
    else:
        wall_with_hole(obj, "wall_south", wall, w, h, d, south_hole, (0, 0, -1))


def wall_with_hole(obj, name, material, w, h, z, hole, front):
    """The wall plane z from x 0..w, y 0..h, less the hole (x0, x1, y0, y1):
    below, above, left and right of it."""
    x0, x1, y0, y1 = hole
    obj.rect(name, material, (0, 0, z), (w, 0, 0), (0, y0, 0), front)
    obj.rect(name, material, (0, y1, z), (w, 0, 0), (0, h - y1, 0), front)
    obj.rect(name, material, (0, y0, z), (x0, 0, 0), (0, y1 - y0, 0), front)
    obj.rect(name, material, (x1, y0, z), (w - x1, 0, 0), (0, y1 - y0, 0), front)


def check_faces_in(obj, inside):
    """Every room surface must face the point `inside` (the furniture,
    which faces out, is left out by name)."""
    for name, pts in obj.faces:
        if name.startswith(("desk", "cabinet", "exterior")):
            continue
        n = cross(sub(pts[1], pts[0]), sub(pts[2], pts[0]))
        centre = tuple(sum(p[k] for p in pts) / len(pts) for k in range(3))
        assert dot(n, sub(inside, centre)) > 0, f"{name} faces out"


def points_csv(path, xs, zs, y):
    lines = ["x,y,z,nx,ny,nz"]
    for z in zs:
        for x in xs:
            lines.append(f"{x:.3f},{y:.3f},{z:.3f},0,1,0")
    write(path, "\n".join(lines) + "\n")


def frange(start, stop, step):
    n = int(round((stop - start) / step)) + 1
    return [start + k * step for k in range(n)]


def camera(position, look_at, vfov=70.0, width=640, height=480):
    return (f"\n[camera]\nposition = {list(position)}\nlook_at = {list(look_at)}\n"
            f"up = [0.0, 1.0, 0.0]\nvfov_deg = {vfov}\nwidth = {width}\nheight = {height}\n")


BLACK_MTL = "# A black room (isorad daylight scene).\nnewmtl black\nKd 0 0 0\n"
GLASS = "\nnewmtl glass\nKd 0 0 0\nTf {t} {t} {t}\n"


def black_room(name, header, roof_hole=None, south_hole=None, glazed=False, cam=None):
    obj = Obj()
    room(obj, 4.0, 4.0, 3.0, ("black", "black", "black"), roof_hole=roof_hole,
         south_hole=south_hole)
    mtl = BLACK_MTL
    if glazed:
        x0, x1, y0, y1 = south_hole
        obj.rect("pane", "glass", (x0, y0, 4.0), (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, -1))
        mtl += GLASS.format(t=0.8)
    check_faces_in(obj, (2.0, 1.5, 2.0))
    obj.write(os.path.join(ROOT, name + ".obj"), header, name + ".mtl")
    write(os.path.join(ROOT, name + ".mtl"), mtl)
    toml = f'# {header.splitlines()[0][2:]}\nobj = "{name}.obj"\n' + cam
    write(os.path.join(ROOT, name + ".toml"), toml + SKY_OVERCAST)
    write(os.path.join(ROOT, name + "_clear.toml"), toml + SKY_CLEAR)
    centres = frange(0.25, 3.75, 0.5)
    points_csv(os.path.join(ROOT, name + "_points.csv"), centres, centres, 0.001)


def office():
    w, d, h, t = 4.0, 6.0, 3.0, 0.2
    x0, x1, y0, y1 = 0.5, 3.5, 0.8, 2.3
    obj = Obj()
    room(obj, w, d, h, ("floor", "ceiling", "wall"), skip_south=True)
    # The window wall: its room face (z = d), its outer face (z = d + t) and
    # the four reveals of the hole between them.
    wall_with_hole(obj, "wall_south", "wall", w, h, d, (x0, x1, y0, y1), (0, 0, -1))
    wall_with_hole(obj, "exterior_south", "wall", w, h, d + t, (x0, x1, y0, y1), (0, 0, 1))
    obj.rect("reveal_sill", "wall", (x0, y0, d), (x1 - x0, 0, 0), (0, 0, t), (0, 1, 0))
    obj.rect("reveal_head", "wall", (x0, y1, d), (x1 - x0, 0, 0), (0, 0, t), (0, -1, 0))
    obj.rect("reveal_west", "wall", (x0, y0, d), (0, y1 - y0, 0), (0, 0, t), (1, 0, 0))
    obj.rect("reveal_east", "wall", (x1, y0, d), (0, y1 - y0, 0), (0, 0, t), (-1, 0, 0))
    # The pane in the middle of the reveal, facing the room.
    obj.rect("pane", "glass", (x0, y0, d + t / 2), (x1 - x0, 0, 0), (0, y1 - y0, 0), (0, 0, -1))
    obj.box("desk_1", "furniture", (0.6, 0.0, 3.8), (2.2, 0.75, 4.6))
    obj.box("desk_2", "furniture", (1.8, 0.0, 1.6), (3.4, 0.75, 2.4))
    obj.box("cabinet", "furniture", (3.6, 0.0, 0.4), (4.0, 1.8, 1.2))
    check_faces_in(obj, (2.0, 1.5, 3.0))
    header = ("# A daylit office, 6 m deep (z) x 4 m wide (x) x 3 m high, window in the\n"
              "# 0.2 m thick south wall (z = 6..6.2): 3 m x 1.5 m, sill 0.8 m, pane Tf 0.7;\n"
              "# two desks and a cabinet. Metres, +y up, north = -z.\n"
              "# Generated by scripts/generate_daylight_scenes.py.")
    obj.write(os.path.join(ROOT, "daylit_office.obj"), header, "daylit_office.mtl")
    write(os.path.join(ROOT, "daylit_office.mtl"),
          "# Reflectances: ceiling 0.7, walls 0.5, floor 0.2, furniture 0.5; pane Tf 0.7.\n"
          "newmtl ceiling\nKd 0.7 0.7 0.7\n\nnewmtl wall\nKd 0.5 0.5 0.5\n\n"
          "newmtl floor\nKd 0.2 0.2 0.2\n\nnewmtl furniture\nKd 0.5 0.5 0.5\n"
          + GLASS.format(t=0.7))
    write(os.path.join(ROOT, "daylit_office.toml"),
          '# A daylit office under the CIE overcast sky (isorad scene file).\n'
          'obj = "daylit_office.obj"\n'
          + camera((2.0, 1.6, 0.3), (2.0, 1.3, 6.0), vfov=65.0, width=800, height=500)
          + SKY_OVERCAST)
    # The same office under the clear sky and a winter afternoon's sun.
    write(os.path.join(ROOT, "daylit_office_sun.toml"),
          '# The daylit office under the CIE clear sky and the sun (isorad scene file).\n'
          'obj = "daylit_office.obj"\n'
          + camera((2.0, 1.6, 0.3), (2.0, 1.3, 6.0), vfov=65.0, width=800, height=500)
          + '\n[sky]\nmodel = "cie_clear"\nhorizontal_illuminance = 10000.0\n'
          'ground_reflectance = 0.2\nnorth = [0.0, 0.0, -1.0]\n'
          '\n[sun]\naltitude_deg = 35.0\nazimuth_deg = 165.0\nnormal_illuminance = 70000.0\n')
    # The work plane: 0.85 m high, a 0.5 m grid inset 0.5 m from the walls.
    points_csv(os.path.join(ROOT, "daylit_office_points.csv"),
               frange(0.5, 3.5, 0.5), frange(0.5, 5.5, 0.5), 0.85)


def main():
    os.makedirs(ROOT, exist_ok=True)
    black_room("roof_opening",
               "# A black 4 x 4 x 3 m room with a 1 x 1 m hole in the centre of its ceiling.\n"
               "# Metres, +y up, north = -z. Generated by scripts/generate_daylight_scenes.py.",
               roof_hole=(1.5, 2.5, 1.5, 2.5),
               cam=camera((0.4, 1.2, 3.6), (2.0, 3.0, 2.0)))
    facade_cam = camera((2.0, 1.5, 0.2), (2.0, 1.4, 4.0))
    black_room("facade_opening",
               "# A black 4 x 4 x 3 m room with a 2 m x 1.2 m hole (sill 0.9 m) in its south\n"
               "# wall (z = 4). Metres, +y up, north = -z. Generated by scripts/generate_daylight_scenes.py.",
               south_hole=(1.0, 3.0, 0.9, 2.1), cam=facade_cam)
    black_room("glazed_facade",
               "# A black 4 x 4 x 3 m room with a 2 m x 1.2 m window (sill 0.9 m, pane Tf 0.8)\n"
               "# in its south wall (z = 4). Metres, +y up, north = -z. Generated by\n"
               "# scripts/generate_daylight_scenes.py.",
               south_hole=(1.0, 3.0, 0.9, 2.1), glazed=True, cam=facade_cam)
    office()


if __name__ == "__main__":
    main()
