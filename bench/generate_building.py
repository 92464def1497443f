#!/usr/bin/env python3
"""Writes a building floor of furnished offices as an isorad scene (OBJ, MTL
and scene TOML), for the scale benchmarks in BENCHMARKS.md.

Each office is 6 m × 5 m × 2.8 m, closed (its own six walls, 0.2 m apart
from its neighbours', so that every office is a closed zone), lit by six
0.6 m ceiling panels (emitted radiance 10 W/(m²·sr) each), or with
``--lights downlights`` by six photometric downlights in their places
(``scenes/downlights/downlight.ies``, copied beside the scene, 5 cm under
the ceiling, aimed down). What stands in it depends on --furniture:

- ``empty``: nothing (6 room faces, 6 lamps);
- ``furnished``: four desks on legs with a monitor each, four chairs;
- ``cluttered``: that, a bookshelf of four boards along the back wall with
  60 books on each (240 books), and a cable tray under the ceiling: about
  1,650 quads per office (with a keyboard, mug, computer and drawer
  unit at each desk, two filing cabinets and a whiteboard), the cluttered office of the scale issue.

Every box is written as its visible faces (a face flush on the floor or on
a neighbour is left out, as a modeller would), all quads, counter-clockwise
seen from outside. The camera stands in the first office (x, z the
smallest) and looks across it.

Usage:
    python3 bench/generate_building.py --rooms 4x4 --furniture cluttered -o /tmp/building

writes /tmp/building/building.{obj,mtl,toml} and prints the quad count.
Nothing but the Python standard library is needed. The books' sizes and
colours come from a seeded generator, so the same arguments always give the
same file. The scene file meshes in metres (``max_edge = 0.2``,
``patch_max_edge = 1.0``, about one office's defaults), so that a floor of
many offices is meshed as finely as one.
"""

import argparse
import os
import random
import shutil

ROOM_X, ROOM_Z, ROOM_Y = 6.0, 5.0, 2.8
WALL = 0.2  # gap between neighbouring offices' walls

MATERIALS = {
    "floor": ((0.35, 0.33, 0.30), None),
    "ceiling": ((0.80, 0.80, 0.80), None),
    "wall": ((0.65, 0.63, 0.60), None),
    "lamp": ((0.0, 0.0, 0.0), (10.0, 10.0, 10.0)),
    "desk": ((0.55, 0.45, 0.35), None),
    "metal": ((0.30, 0.30, 0.32), None),
    "screen": ((0.05, 0.05, 0.06), None),
    "chair": ((0.20, 0.25, 0.45), None),
    "shelf": ((0.60, 0.55, 0.45), None),
    "book_red": ((0.55, 0.12, 0.10), None),
    "book_green": ((0.15, 0.40, 0.20), None),
    "book_blue": ((0.12, 0.20, 0.50), None),
    "book_cream": ((0.75, 0.70, 0.55), None),
    "tray": ((0.45, 0.45, 0.45), None),
}
BOOKS = ["book_red", "book_green", "book_blue", "book_cream"]


class Obj:
    """Vertices and quads, grouped by material."""

    def __init__(self):
        self.vertices = []
        self.faces = []  # (material, [four 1-based indices])

    def quad(self, material, a, b, c, d):
        i = len(self.vertices)
        self.vertices.extend([a, b, c, d])
        self.faces.append((material, [i + 1, i + 2, i + 3, i + 4]))

    def box(self, material, x0, x1, y0, y1, z0, z1, skip=()):
        """An axis-aligned box, its faces facing out; `skip` names faces
        left out: any of "-x", "+x", "-y", "+y", "-z", "+z"."""
        faces = {
            "+y": ((x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)),
            "-y": ((x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)),
            "-z": ((x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)),
            "+z": ((x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (x0, y0, z1)),
            "-x": ((x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (x0, y0, z0)),
            "+x": ((x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)),
        }
        for name, corners in faces.items():
            if name not in skip:
                self.quad(material, *corners)


LIGHTS = [(1.0, 1.5), (1.0, 3.5), (3.0, 1.5), (3.0, 3.5), (5.0, 1.5), (5.0, 3.5)]


def office(obj, ox, oz, furniture, rng, panels=True):
    """One closed office with its corner at (ox, 0, oz), with ceiling panels
    unless ``panels`` is false."""
    X, Y, Z = ox + ROOM_X, ROOM_Y, oz + ROOM_Z
    # The room's faces, facing in.
    obj.quad("floor", (ox, 0, oz), (ox, 0, Z), (X, 0, Z), (X, 0, oz))
    obj.quad("ceiling", (ox, Y, oz), (X, Y, oz), (X, Y, Z), (ox, Y, Z))
    obj.quad("wall", (ox, 0, oz), (X, 0, oz), (X, Y, oz), (ox, Y, oz))
    obj.quad("wall", (ox, 0, Z), (ox, Y, Z), (X, Y, Z), (X, 0, Z))
    obj.quad("wall", (ox, 0, oz), (ox, Y, oz), (ox, Y, Z), (ox, 0, Z))
    obj.quad("wall", (X, 0, oz), (X, 0, Z), (X, Y, Z), (X, Y, oz))
    # Six ceiling panels, facing down, 1 cm below the ceiling.
    half, y = 0.3, Y - 0.01
    for lx, lz in LIGHTS if panels else []:
        x, z = ox + lx, oz + lz
        obj.quad("lamp", (x - half, y, z - half), (x + half, y, z - half),
                 (x + half, y, z + half), (x - half, y, z + half))
    if furniture == "empty":
        return
    # Four desks on legs, a monitor on each, a chair before each.
    for cx, cz in ((1.8, 1.4), (4.2, 1.4), (1.8, 3.3), (4.2, 3.3)):
        x0, x1 = ox + cx - 0.7, ox + cx + 0.7
        z0, z1 = oz + cz - 0.4, oz + cz + 0.4
        obj.box("desk", x0, x1, 0.72, 0.75, z0, z1)
        for lx, lz in ((x0 + 0.03, z0 + 0.03), (x1 - 0.08, z0 + 0.03),
                       (x0 + 0.03, z1 - 0.08), (x1 - 0.08, z1 - 0.08)):
            obj.box("metal", lx, lx + 0.05, 0.0, 0.72, lz, lz + 0.05, skip=("-y", "+y"))
        mx = ox + cx
        obj.box("metal", mx - 0.1, mx + 0.1, 0.75, 0.77, z1 - 0.25, z1 - 0.1, skip=("-y",))
        obj.box("metal", mx - 0.02, mx + 0.02, 0.77, 0.95, z1 - 0.2, z1 - 0.16, skip=("-y",))
        obj.box("screen", mx - 0.3, mx + 0.3, 0.95, 1.3, z1 - 0.2, z1 - 0.16)
        # The chair, in front of the desk (toward -z).
        sz = z0 - 0.35
        obj.box("chair", mx - 0.23, mx + 0.23, 0.45, 0.5, sz - 0.23, sz + 0.23)
        obj.box("chair", mx - 0.23, mx + 0.23, 0.5, 0.95, sz - 0.26, sz - 0.23)
        for lx, lz in ((mx - 0.2, sz - 0.2), (mx + 0.17, sz - 0.2),
                       (mx - 0.2, sz + 0.17), (mx + 0.17, sz + 0.17)):
            obj.box("metal", lx, lx + 0.03, 0.0, 0.45, lz, lz + 0.03, skip=("-y", "+y"))
    if furniture != "cluttered":
        return
    # On and under each desk: a keyboard, a mug, a computer, a drawer unit.
    for cx, cz in ((1.8, 1.4), (4.2, 1.4), (1.8, 3.3), (4.2, 3.3)):
        mx, z0, z1 = ox + cx, oz + cz - 0.4, oz + cz + 0.4
        obj.box("metal", mx - 0.22, mx + 0.22, 0.75, 0.77, z0 + 0.08, z0 + 0.24, skip=("-y",))
        obj.box("book_cream", mx + 0.4, mx + 0.48, 0.75, 0.85, z0 + 0.2, z0 + 0.28, skip=("-y",))
        obj.box("screen", mx + 0.35, mx + 0.55, 0.0, 0.45, z1 - 0.5, z1 - 0.05, skip=("-y",))
        obj.box("desk", mx - 0.6, mx - 0.2, 0.0, 0.6, z1 - 0.6, z1 - 0.05, skip=("-y",))
    # Two filing cabinets and a whiteboard on the side walls.
    obj.box("metal", ox, ox + 0.45, 0.0, 1.3, oz + 0.3, oz + 0.8, skip=("-y", "-x"))
    obj.box("metal", ox, ox + 0.45, 0.0, 1.3, oz + 0.85, oz + 1.35, skip=("-y", "-x"))
    obj.box("ceiling", X - 0.02, X, 0.9, 2.1, oz + 1.0, oz + 3.5, skip=("+x",))
    # A bookshelf along the back wall (z = Z), four boards of 60 books.
    sx0, sx1 = ox + 0.6, ox + 5.4
    depth = 0.3
    sz0, sz1 = Z - depth, Z
    obj.box("shelf", sx0 - 0.02, sx0, 0.0, 2.0, sz0, sz1, skip=("-y", "+z"))
    obj.box("shelf", sx1, sx1 + 0.02, 0.0, 2.0, sz0, sz1, skip=("-y", "+z"))
    for board in range(4):
        by = 0.1 + 0.48 * board
        obj.box("shelf", sx0, sx1, by, by + 0.02, sz0, sz1, skip=("+z",))
        x = sx0 + 0.01
        for _ in range(60):
            width = rng.uniform(0.05, 0.075)
            height = rng.uniform(0.22, 0.34)
            book_depth = rng.uniform(0.16, 0.24)
            obj.box(rng.choice(BOOKS), x, x + width, by + 0.02, by + 0.02 + height,
                    sz1 - 0.02 - book_depth, sz1 - 0.02, skip=("-y",))
            x += width + 0.001
    # A cable tray under the ceiling, across the room, on hangers.
    ty = Y - 0.4
    for tx in (ox + 0.5, ox + 5.5):
        obj.box("tray", tx - 0.15, tx + 0.15, ty, ty + 0.01, oz + 0.3, Z - 0.3)
        for hz in (oz + 0.6, oz + 2.5, Z - 0.6):
            obj.box("metal", tx - 0.01, tx + 0.01, ty + 0.01, Y, hz - 0.01, hz + 0.01,
                    skip=("-y", "+y"))


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--rooms", default="1x1", help="offices along x and z, e.g. 4x4")
    parser.add_argument("--furniture", choices=["empty", "furnished", "cluttered"],
                        default="cluttered")
    parser.add_argument("-o", "--output", required=True, help="directory to write into")
    parser.add_argument("--name", default="building", help="file name stem")
    parser.add_argument("--lights", choices=["panels", "downlights"], default="panels",
                        help="emitting ceiling panels, or photometric downlights in their places")
    args = parser.parse_args()
    try:
        nx, nz = (int(n) for n in args.rooms.lower().split("x"))
    except ValueError:
        parser.error(f"--rooms {args.rooms!r}: expected two counts such as 4x4")
    if nx < 1 or nz < 1:
        parser.error("--rooms needs at least 1x1")
    rng = random.Random(1651)
    obj = Obj()
    for i in range(nx):
        for k in range(nz):
            office(obj, i * (ROOM_X + WALL), k * (ROOM_Z + WALL), args.furniture, rng,
                   panels=args.lights == "panels")
    os.makedirs(args.output, exist_ok=True)
    stem = os.path.join(args.output, args.name)
    with open(stem + ".obj", "w") as f:
        f.write(f"mtllib {args.name}.mtl\n")
        for v in obj.vertices:
            f.write("v %.4f %.4f %.4f\n" % v)
        current = None
        for k, (material, indices) in enumerate(obj.faces):
            if material != current:
                f.write(f"o {material}_{k}\nusemtl {material}\n")
                current = material
            f.write("f " + " ".join(map(str, indices)) + "\n")
    with open(stem + ".mtl", "w") as f:
        for name, (kd, ke) in MATERIALS.items():
            f.write(f"newmtl {name}\nKd {kd[0]} {kd[1]} {kd[2]}\n")
            if ke:
                f.write(f"Ke {ke[0]} {ke[1]} {ke[2]}\n")
    with open(stem + ".toml", "w") as f:
        f.write(f'obj = "{args.name}.obj"\n\n[camera]\n'
                "position = [0.4, 1.7, 0.4]\n"
                "look_at = [4.5, 0.7, 4.2]\n"
                "up = [0.0, 1.0, 0.0]\n"
                "vfov_deg = 65.0\n"
                "width = 256\n"
                "height = 160\n\n"
                "# Elements and patches in metres, so that a floor of offices\n"
                "# is meshed as finely as one office (the defaults scale with the\n"
                "# scene's diagonal).\n"
                "[mesh]\n"
                "max_edge = 0.2\n"
                "patch_max_edge = 1.0\n")
        if args.lights == "downlights":
            for i in range(nx):
                for k in range(nz):
                    ox, oz = i * (ROOM_X + WALL), k * (ROOM_Z + WALL)
                    for lx, lz in LIGHTS:
                        f.write("\n[[luminaire]]\n"
                                'ies = "downlight.ies"\n'
                                f"position = [{ox + lx:.4f}, {ROOM_Y - 0.05:.4f}, {oz + lz:.4f}]\n"
                                "aim = [0.0, -1.0, 0.0]\n"
                                "c0 = [1.0, 0.0, 0.0]\n")
    if args.lights == "downlights":
        here = os.path.dirname(os.path.abspath(__file__))
        ies = os.path.join(here, "..", "scenes", "downlights", "downlight.ies")
        shutil.copyfile(ies, os.path.join(args.output, "downlight.ies"))
    print(f"{stem}.obj: {nx * nz} offices, {len(obj.faces)} quads")


if __name__ == "__main__":
    main()
