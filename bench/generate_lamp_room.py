#!/usr/bin/env python3
"""Writes a room lit by a floor lamp whose lens is a tessellated curved
emitter, as a modelling program exports one (OBJ, MTL and scene TOML).

The room is 5 m x 2.7 m x 4 m, closed, with a table on four legs. The
floor lamp stands in a corner: a 16-sided pole, an open conical shade of
48 segments (white inside, lit by the lens) and, under it, the lens: a
hemispherical cap of radius 3.5 cm facing down, written as --lens-rings
rings of --lens-segments triangles and quads split into triangles, every
triangle its own plane (about 2,000 emitting triangles by default). With
``--globes N`` the ceiling also carries N pendant globes (tessellated
spheres of radius 8 cm, --globe-segments around), as a hall's lamps.

Every emitting triangle is written on its own, as exporters write them;
nothing is merged. This is the case of issue 57: before emitting bodies,
each plane of the lens was its own lamp.

Usage:
    python3 bench/generate_lamp_room.py -o /tmp/lamp_room
    python3 bench/generate_lamp_room.py --globes 12 -o /tmp/globe_hall

writes <out>/lamp_room.{obj,mtl,toml} and prints the face counts. Only the
Python standard library is needed.
"""

import argparse
import math
import os

ROOM_X, ROOM_Y, ROOM_Z = 5.0, 2.7, 4.0
LENS_RADIUS = 0.035
LENS_CENTRE = (0.6, 1.55, 0.6)
GLOBE_RADIUS = 0.08
SHADE = 0.002

MATERIALS = {
    "floor": ((0.35, 0.33, 0.30), None),
    "ceiling": ((0.80, 0.80, 0.80), None),
    "wall": ((0.65, 0.63, 0.60), None),
    "table": ((0.55, 0.45, 0.35), None),
    "metal": ((0.30, 0.30, 0.32), None),
    "shade": ((0.75, 0.72, 0.65), None),
    "lens": ((0.0, 0.0, 0.0), (3000.0, 2800.0, 2400.0)),
    "globe": ((0.0, 0.0, 0.0), (150.0, 150.0, 150.0)),
}


class Obj:
    """Collects vertices and faces, one OBJ object per group."""

    def __init__(self):
        self.vertices = []
        self.lines = []
        self.faces = {}

    def group(self, name, material):
        self.lines.append(f"o {name}\nusemtl {material}")

    def face(self, points, material):
        start = len(self.vertices) + 1
        self.vertices.extend(points)
        indices = " ".join(str(start + k) for k in range(len(points)))
        self.lines.append(f"f {indices}")
        self.faces[material] = self.faces.get(material, 0) + 1

    def box(self, low, high, material, skip_bottom=True):
        (x0, y0, z0), (x1, y1, z1) = low, high
        quads = [
            [(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)],  # top
            [(x0, y0, z1), (x1, y0, z1), (x1, y1, z1), (x0, y1, z1)],  # +z
            [(x1, y0, z0), (x0, y0, z0), (x0, y1, z0), (x1, y1, z0)],  # -z
            [(x1, y0, z1), (x1, y0, z0), (x1, y1, z0), (x1, y1, z1)],  # +x
            [(x0, y0, z0), (x0, y0, z1), (x0, y1, z1), (x0, y1, z0)],  # -x
        ]
        if not skip_bottom:
            quads.append([(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)])
        for q in quads:
            self.face(q, material)


def sphere_point(centre, radius, polar, azimuth):
    """The point at polar angle `polar` from +y and `azimuth` about it."""
    s = math.sin(polar)
    return (
        centre[0] + radius * s * math.cos(azimuth),
        centre[1] + radius * math.cos(polar),
        centre[2] + radius * s * math.sin(azimuth),
    )


def cap(obj, centre, radius, polar_from, polar_to, rings, segments, material):
    """Triangles of the sphere between two polar angles, facing out,
    counter-clockwise seen from outside."""
    for i in range(rings):
        a0 = polar_from + (polar_to - polar_from) * i / rings
        a1 = polar_from + (polar_to - polar_from) * (i + 1) / rings
        for j in range(segments):
            b0 = 2 * math.pi * j / segments
            b1 = 2 * math.pi * (j + 1) / segments
            p00 = sphere_point(centre, radius, a0, b0)
            p01 = sphere_point(centre, radius, a0, b1)
            p10 = sphere_point(centre, radius, a1, b0)
            p11 = sphere_point(centre, radius, a1, b1)
            if a0 > 1e-12:
                obj.face([p00, p01, p11], material)
            if math.pi - a1 > 1e-12:
                obj.face([p00, p11, p10], material)


def room(obj):
    """The closed room, every face facing in."""
    x, y, z = ROOM_X, ROOM_Y, ROOM_Z
    obj.group("floor", "floor")
    obj.face([(0, 0, 0), (0, 0, z), (x, 0, z), (x, 0, 0)], "floor")
    obj.group("ceiling", "ceiling")
    obj.face([(0, y, 0), (x, y, 0), (x, y, z), (0, y, z)], "ceiling")
    obj.group("walls", "wall")
    obj.face([(0, 0, 0), (x, 0, 0), (x, y, 0), (0, y, 0)], "wall")
    obj.face([(x, 0, z), (0, 0, z), (0, y, z), (x, y, z)], "wall")
    obj.face([(0, 0, z), (0, 0, 0), (0, y, 0), (0, y, z)], "wall")
    obj.face([(x, 0, 0), (x, 0, z), (x, y, z), (x, y, 0)], "wall")


def table(obj):
    obj.group("table", "table")
    obj.box((2.0, 0.72, 1.5), (3.4, 0.76, 2.4), "table", skip_bottom=False)
    for lx, lz in [(2.05, 1.55), (3.3, 1.55), (2.05, 2.3), (3.3, 2.3)]:
        obj.box((lx, 0.0, lz), (lx + 0.05, 0.72, lz + 0.05), "metal")


def floor_lamp(obj, rings, segments):
    cx, cy, cz = LENS_CENTRE
    obj.group("lamp_pole", "metal")
    sides, r = 16, 0.015
    for k in range(sides):
        a0, a1 = 2 * math.pi * k / sides, 2 * math.pi * (k + 1) / sides
        p = lambda a, h: (cx + r * math.cos(a), h, cz + r * math.sin(a))
        obj.face([p(a0, 0.0), p(a0, cy - 0.06), p(a1, cy - 0.06), p(a1, 0.0)], "metal")
    obj.group("lamp_shade", "shade")
    shade = 48
    top_r, bottom_r, top_y, bottom_y = 0.06, 0.2, cy + 0.06, cy - 0.12
    for k in range(shade):
        a0, a1 = 2 * math.pi * k / shade, 2 * math.pi * (k + 1) / shade

        def t(a, out=0.0):
            r = top_r + out
            return (cx + r * math.cos(a), top_y, cz + r * math.sin(a))

        def b(a, out=0.0):
            r = bottom_r + out
            return (cx + r * math.cos(a), bottom_y, cz + r * math.sin(a))

        # Inside (facing the lens) and, 2 mm out, outside: a shade of some
        # thickness (faces exactly back to back are ambiguous to a path
        # tracer, which may hit either).
        obj.face([t(a1), t(a0), b(a0), b(a1)], "shade")
        obj.face([t(a0, SHADE), t(a1, SHADE), b(a1, SHADE), b(a0, SHADE)], "shade")
    obj.group("lamp_lens", "lens")
    cap(obj, LENS_CENTRE, LENS_RADIUS, math.pi / 2, math.pi, rings, segments, "lens")


def globes(obj, count, segments):
    columns = max(1, math.ceil(math.sqrt(count)))
    rows = math.ceil(count / columns)
    for k in range(count):
        i, j = k % columns, k // columns
        centre = (
            ROOM_X * (i + 0.5) / columns,
            ROOM_Y - 0.5,
            ROOM_Z * (j + 0.5) / rows,
        )
        obj.group(f"globe_{k}", "globe")
        cap(obj, centre, GLOBE_RADIUS, 0.0, math.pi, segments // 2, segments, "globe")


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", "--out", required=True)
    parser.add_argument("--name", default="lamp_room")
    parser.add_argument("--lens-rings", type=int, default=17)
    parser.add_argument("--lens-segments", type=int, default=64)
    parser.add_argument("--globes", type=int, default=0)
    parser.add_argument("--globe-segments", type=int, default=32)
    args = parser.parse_args()
    os.makedirs(args.out, exist_ok=True)
    obj = Obj()
    room(obj)
    table(obj)
    floor_lamp(obj, args.lens_rings, args.lens_segments)
    globes(obj, args.globes, args.globe_segments)
    with open(os.path.join(args.out, f"{args.name}.mtl"), "w") as f:
        for name, (kd, ke) in MATERIALS.items():
            f.write(f"newmtl {name}\nKd {kd[0]} {kd[1]} {kd[2]}\n")
            if ke:
                f.write(f"Ke {ke[0]} {ke[1]} {ke[2]}\n")
    with open(os.path.join(args.out, f"{args.name}.obj"), "w") as f:
        f.write(f"mtllib {args.name}.mtl\n")
        for v in obj.vertices:
            f.write(f"v {v[0]:.6f} {v[1]:.6f} {v[2]:.6f}\n")
        f.write("\n".join(obj.lines) + "\n")
    with open(os.path.join(args.out, f"{args.name}.toml"), "w") as f:
        f.write(
            f'obj = "{args.name}.obj"\n\n[camera]\n'
            "position = [4.6, 1.6, 3.7]\nlook_at = [1.2, 0.8, 0.8]\n"
            "up = [0, 1, 0]\nvfov_deg = 60\nwidth = 640\nheight = 480\n"
        )
    total = sum(obj.faces.values())
    print(f"{total} faces: " + ", ".join(f"{m} {n}" for m, n in sorted(obj.faces.items())))


if __name__ == "__main__":
    main()
