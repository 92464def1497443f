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


def room_with_table(obj, size, left_wall, table):
    """A room facing inwards (floor, ceiling, four walls; the x = 0 wall in
    material `left_wall`) and a 1.4 x 0.8 m table top at 0.75 m on four legs,
    its corner at `table` (x, z)."""
    X, Y, Z = size
    obj.face("floor", "floor", [(0, 0, 0), (0, 0, Z), (X, 0, Z), (X, 0, 0)])
    obj.face("ceiling", "white", [(0, Y, 0), (X, Y, 0), (X, Y, Z), (0, Y, Z)])
    obj.face("back_wall", "white", [(0, 0, Z), (0, Y, Z), (X, Y, Z), (X, 0, Z)])
    obj.face("front_wall", "white", [(0, 0, 0), (X, 0, 0), (X, Y, 0), (0, Y, 0)])
    obj.face("left_wall", left_wall, [(0, 0, 0), (0, Y, 0), (0, Y, Z), (0, 0, Z)])
    obj.face("right_wall", "white", [(X, 0, 0), (X, 0, Z), (X, Y, Z), (X, Y, 0)])
    tx, tz = table
    obj.box("table_top", "wood", (tx, 0.72, tz), (tx + 1.4, 0.75, tz + 0.8), bottom=True)
    for dx in (0.05, 1.3):
        for dz in (0.05, 0.7):
            obj.box("table_leg", "wood", (tx + dx, 0.0, tz + dz), (tx + dx + 0.05, 0.72, tz + dz + 0.05))


def room():
    folder = os.path.join(ROOT, "room")
    os.makedirs(folder, exist_ok=True)
    obj = Obj()
    room_with_table(obj, (6.0, 3.0, 4.0), "blue", (2.6, 1.6))
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


def table():
    """The table-shadow case: an open floor, a table, and a small tilted lamp."""
    folder = os.path.join(ROOT, "table")
    os.makedirs(folder, exist_ok=True)
    obj = Obj()
    obj.face("floor", "floor", [(-3, 0, -3), (-3, 0, 3), (3, 0, 3), (3, 0, -3)])
    # A 0.8 x 0.8 m top, 4 cm thick, at 0.76 m on four 3 cm legs.
    obj.box("table_top", "wood", (-0.4, 0.72, -0.4), (0.4, 0.76, 0.4), bottom=True)
    for x in (-0.37, 0.34):
        for z in (-0.37, 0.34):
            obj.box("table_leg", "wood", (x, 0.0, z), (x + 0.03, 0.72, z + 0.03))
    # A 0.15 m square lamp 1.5 m up, 0.9 m to the side, tilted 30 degrees towards the table.
    t = math.radians(-30)
    c = (0.9, 1.5, 0.0)
    u = (math.cos(t), math.sin(t), 0.0)
    w = (0.0, 0.0, 1.0)
    h = 0.075
    corners = [(-1, -1), (1, -1), (1, 1), (-1, 1)]  # counter-clockwise about u x w: facing down
    obj.face("lamp", "lamp", [tuple(c[i] + h * (a * u[i] + b * w[i]) for i in range(3)) for a, b in corners])
    obj.write(os.path.join(folder, "table.obj"),
              "# A 0.8 x 0.8 m table on a 6 x 6 m floor, open to the sky, under a small square\n"
              "# lamp tilted 30 degrees towards it: a shadow with an umbra lit only by the\n"
              "# light the floor and the table pass on. Metres.",
              "table.mtl")
    write(os.path.join(folder, "table.mtl"),
          "newmtl floor\nKd 0.5 0.5 0.5\n\nnewmtl wood\nKd 0.6 0.45 0.3\n\n"
          "newmtl lamp\nKd 0 0 0\nKe 200 200 200\n")
    write(os.path.join(folder, "table.toml"),
          '# A table casting a shadow under a small tilted lamp, open to the sky (isorad scene file).\n'
          'obj = "table.obj"\n\n[camera]\nposition = [-1.6, 2.6, -2.6]\nlook_at = [-0.3, 0.1, 0.1]\n'
          'up = [0.0, 1.0, 0.0]\nvfov_deg = 55.0\nwidth = 512\nheight = 384\n')


def downlights():
    """A room lit by two photometric downlights (an IES file, no emitting faces)."""
    folder = os.path.join(ROOT, "downlights")
    os.makedirs(folder, exist_ok=True)
    obj = Obj()
    room_with_table(obj, (5.0, 2.8, 4.0), "white", (1.8, 1.6))
    obj.write(os.path.join(folder, "downlights.obj"),
              "# A 5 x 2.8 x 4 m room with a table, lit only by two photometric downlights\n"
              "# (downlights.toml's [[luminaire]] tables, downlight.ies). Metres.",
              "downlights.mtl")
    write(os.path.join(folder, "downlights.mtl"),
          "newmtl floor\nKd 0.3 0.3 0.3\n\nnewmtl white\nKd 0.75 0.75 0.75\n\n"
          "newmtl wood\nKd 0.5 0.33 0.2\n")
    # An LM-63-2002 downlight: quadrant symmetric, I = 1200 cos^1.5 g (1 + 0.2 cos 2C) cd.
    vertical = [10 * k for k in range(10)]
    horizontal = [0, 30, 60, 90]
    lines = ["IESNA:LM-63-2002", "[TEST] isorad example", "[MANUFAC] isorad",
             "[LUMINAIRE] Downlight, slightly elongated beam", "TILT=NONE",
             f"1 -1 1.0 {len(vertical)} {len(horizontal)} 1 2 0.15 0.15 0.0", "1.0 1.0 18",
             " ".join(str(a) for a in vertical), " ".join(str(a) for a in horizontal)]
    for c in horizontal:
        values = [1200 * math.cos(math.radians(g)) ** 1.5 * (1 + 0.2 * math.cos(math.radians(2 * c)))
                  for g in vertical]
        lines.append(" ".join(f"{max(v, 0.0):.2f}" for v in values))
    write(os.path.join(folder, "downlight.ies"), "\n".join(lines) + "\n")
    write(os.path.join(folder, "washer.ldt"), wall_washer_ldt())
    luminaire = ('[[luminaire]]\nies = "downlight.ies"\nposition = [{x}, 2.75, 2.0]\n'
                 'aim = [0.0, -1.0, 0.0]\nc0 = [1.0, 0.0, 0.0]\ncolor = [1.0, 0.92, 0.82]\n')
    washer = ('[[luminaire]]\n# A wall washer lighting the back wall (EULUMDAT, asymmetric).\n'
              'ies = "washer.ldt"\nposition = [2.5, 2.7, 3.4]\naim = [0.0, -0.86, 0.51]\n'
              'c0 = [1.0, 0.0, 0.0]\nmultiplier = 0.9\ncolor = [0.85, 0.92, 1.0]\n')
    write(os.path.join(folder, "downlights.toml"),
          '# A room lit by two IES downlights and an EULUMDAT wall washer (isorad scene file).\n'
          'obj = "downlights.obj"\n\n[camera]\nposition = [0.4, 1.6, 0.3]\nlook_at = [3.0, 0.5, 2.6]\n'
          'up = [0.0, 1.0, 0.0]\nvfov_deg = 65.0\nwidth = 640\nheight = 480\n\n'
          + luminaire.format(x=1.5) + "\n" + luminaire.format(x=3.5) + "\n" + washer)


def wall_washer_ldt():
    """An asymmetric EULUMDAT wall washer (Isym 0, C every 30 degrees, gamma every 10):
    I = 240 max(cos(g - 35), 0)^2 (1 + 0.6 cos(C - 270)) + 6 cd for g <= 120 (about the
    lamps' 1500 lm times the 85 % light output ratio), its beam
    thrown towards C270 (with aim [0, -0.86, 0.51] and c0 +x, towards the wall it faces);
    a 300 x 80 mm luminous area; a 1500 lm lamp set, so cd/klm = I / 1.5."""
    cs = [30 * k for k in range(12)]
    gammas = [10 * k for k in range(19)]

    def intensity(c, g):
        if g > 120:
            return 0.0
        lobe = max(math.cos(math.radians(g - 35)), 0.0) ** 2
        return 240 * lobe * (1 + 0.6 * math.cos(math.radians(c - 270))) + 6

    lines = ["isorad", "1", "0", "12", "30", "19", "10", "isorad example", "Wall washer",
             "WW-300", "washer.ldt", "isorad scripts/generate_scenes.py",
             "320", "100", "60", "300", "80", "0", "0", "0", "0",
             "60", "85", "1.0", "0", "1", "1", "LED module", "1500", "3000", "90", "16"]
    lines += ["0.5"] * 10
    lines += [str(c) for c in cs] + [str(g) for g in gammas]
    for c in cs:
        lines += [f"{intensity(c, g) / 1.5:.2f}" for g in gammas]
    return "\r\n".join(lines) + "\r\n"


def newell(points):
    """Newell's normal of a polygon (not normalised)."""
    n = [0.0, 0.0, 0.0]
    for k, p in enumerate(points):
        q = points[(k + 1) % len(points)]
        n[0] += (p[1] - q[1]) * (p[2] + q[2])
        n[1] += (p[2] - q[2]) * (p[0] + q[0])
        n[2] += (p[0] - q[0]) * (p[1] + q[1])
    return n


def facing(points, direction):
    """The polygon, reversed if needed so that its front faces `direction`."""
    n = newell(points)
    return points if sum(a * b for a, b in zip(n, direction)) > 0 else points[::-1]


class CadObj(Obj):
    """An OBJ written the way CAD exporters write one: shared vertices,
    large flat faces as grids of small triangles, round legs as prisms."""

    def vertex(self, p):
        self.vertices.append(p)
        self.lines.append("v {:.6f} {:.6f} {:.6f}".format(*p))
        return len(self.vertices)

    def quad(self, name, material, points, direction):
        self.face(name, material, facing(points, direction))

    def triangle_grid(self, name, material, origin, du, dv, nu, nv, direction):
        """A parallelogram origin + s du + t dv (s in [0, nu], t in [0, nv])
        as 2 nu nv triangles with shared vertices, diagonals alternating."""
        self.lines.append(f"o {name}\nusemtl {material}")
        ids = [[self.vertex(tuple(origin[k] + i * du[k] + j * dv[k] for k in range(3)))
                for j in range(nv + 1)] for i in range(nu + 1)]
        for i in range(nu):
            for j in range(nv):
                a, b, c, d = ids[i][j], ids[i + 1][j], ids[i + 1][j + 1], ids[i][j + 1]
                tris = [(a, b, c), (a, c, d)] if (i + j) % 2 == 0 else [(a, b, d), (b, c, d)]
                for t in tris:
                    pts = [self.vertices[v - 1] for v in t]
                    if sum(x * y for x, y in zip(newell(pts), direction)) < 0:
                        t = t[::-1]
                    self.lines.append("f {} {} {}".format(*t))

    def open_box(self, name, material, lo, hi, skip=()):
        """An axis-aligned box with outward faces, leaving out the faces named
        in `skip` ("-x", "+x", "-y", "+y", "-z", "+z"): those that rest on or
        against something."""
        (x0, y0, z0), (x1, y1, z1) = lo, hi
        faces = {
            "+y": ([(x0, y1, z0), (x0, y1, z1), (x1, y1, z1), (x1, y1, z0)], (0, 1, 0)),
            "-y": ([(x0, y0, z0), (x1, y0, z0), (x1, y0, z1), (x0, y0, z1)], (0, -1, 0)),
            "-z": ([(x0, y0, z0), (x0, y1, z0), (x1, y1, z0), (x1, y0, z0)], (0, 0, -1)),
            "+z": ([(x1, y0, z1), (x1, y1, z1), (x0, y1, z1), (x0, y0, z1)], (0, 0, 1)),
            "-x": ([(x0, y0, z1), (x0, y1, z1), (x0, y1, z0), (x0, y0, z0)], (-1, 0, 0)),
            "+x": ([(x1, y0, z0), (x1, y1, z0), (x1, y1, z1), (x1, y0, z1)], (1, 0, 0)),
        }
        for key, (points, direction) in faces.items():
            if key not in skip:
                self.quad(name, material, points, direction)

    def prism(self, name, material, centre, radius, y0, y1, sides, top=False):
        """A vertical prism of `sides` sides standing on y0 (no bottom face)."""
        cx, cz = centre
        ring = [(cx + radius * math.cos(2 * math.pi * k / sides), cz + radius * math.sin(2 * math.pi * k / sides))
                for k in range(sides)]
        for k in range(sides):
            (ax, az), (bx, bz) = ring[k], ring[(k + 1) % sides]
            out = ((ax + bx) / 2 - cx, 0.0, (az + bz) / 2 - cz)
            self.quad(name, material, [(ax, y0, az), (bx, y0, bz), (bx, y1, bz), (ax, y1, az)], out)
        if top:
            self.quad(name, material, [(x, y1, z) for x, z in ring], (0, 1, 0))


def office():
    """An open-plan office, 12 x 8 x 3 m, in metres: carpet, walls and ceiling
    written as CAD exporters write them (grids of coplanar triangles), four
    bench-desk clusters with screens, chairs and pedestals, five bookcases of
    books, three windows (dark glass) and eight small ceiling luminaires."""
    import random
    rng = random.Random(5)
    folder = os.path.join(ROOT, "office")
    os.makedirs(folder, exist_ok=True)
    obj = CadObj()
    X, Y, Z = 12.0, 3.0, 8.0
    # Shell: carpet tiles of 0.25 m, ceiling tiles of 0.5 m, walls of 1 m, all triangulated.
    obj.triangle_grid("floor", "carpet", (0, 0, 0), (0.25, 0, 0), (0, 0, 0.25), 48, 32, (0, 1, 0))
    obj.triangle_grid("ceiling", "ceiling", (0, Y, 0), (0.5, 0, 0), (0, 0, 0.5), 24, 16, (0, -1, 0))
    obj.triangle_grid("wall_south", "wall", (0, 0, 0), (1, 0, 0), (0, 1, 0), 12, 3, (0, 0, 1))
    obj.triangle_grid("wall_north", "wall", (0, 0, Z), (1, 0, 0), (0, 1, 0), 12, 3, (0, 0, -1))
    obj.triangle_grid("wall_west", "accent", (0, 0, 0), (0, 0, 1), (0, 1, 0), 8, 3, (1, 0, 0))
    obj.triangle_grid("wall_east", "wall", (X, 0, 0), (0, 0, 1), (0, 1, 0), 8, 3, (-1, 0, 0))
    # Windows on the east wall: dark glass panes in 4 cm frames against the wall.
    for zc in (1.6, 4.0, 6.4):
        obj.open_box("window", "glass", (X - 0.04, 0.9, zc - 0.9), (X, 2.4, zc + 0.9), skip=("+x",))
    # Luminaires: 0.4 m square panels, 5 cm deep, on the ceiling; the bottom emits.
    for xc in (2.2, 3.8, 7.4, 9.0):
        for zc in (1.9, 5.4):
            lo, hi = (xc - 0.2, Y - 0.05, zc - 0.2), (xc + 0.2, Y, zc + 0.2)
            obj.open_box("luminaire_frame", "frame", lo, hi, skip=("+y", "-y"))
            obj.quad("luminaire", "lamp", [(lo[0], lo[1], lo[2]), (hi[0], lo[1], lo[2]),
                                           (hi[0], lo[1], hi[2]), (lo[0], lo[1], hi[2])], (0, -1, 0))
    # Bench-desk clusters: two 3.2 x 0.8 m benches face to face across a screen.
    for x0 in (1.4, 6.6):
        for z0 in (1.1, 4.6):
            cluster(obj, x0, z0)
    # Bookcases along the north wall, with books.
    for k in range(5):
        bookcase(obj, rng, 1.2 + 1.04 * k, Z)
    obj.write(os.path.join(folder, "office.obj"),
              "# An open-plan office, 12 x 8 x 3 m, written as a CAD exporter would (floor,\n"
              "# ceiling and walls as grids of coplanar triangles, round legs as prisms):\n"
              "# four bench-desk clusters, five bookcases, eight ceiling luminaires. Metres.\n"
              "# Generated by scripts/generate_scenes.py.",
              "office.mtl")
    books = "".join(f"newmtl book{k}\nKd {r} {g} {b}\n\n" for k, (r, g, b) in enumerate(BOOK_COLOURS))
    write(os.path.join(folder, "office.mtl"),
          "# Reflectances of a typical office: ceiling 0.8, walls 0.7, carpet 0.3.\n"
          "newmtl carpet\nKd 0.3 0.3 0.32\n\nnewmtl ceiling\nKd 0.8 0.8 0.8\n\n"
          "newmtl wall\nKd 0.7 0.69 0.66\n\nnewmtl accent\nKd 0.35 0.45 0.6\n\n"
          "newmtl glass\nKd 0.04 0.05 0.06\n\nnewmtl frame\nKd 0.75 0.75 0.75\n\n"
          "newmtl desk\nKd 0.6 0.5 0.38\n\nnewmtl metal\nKd 0.4 0.4 0.42\n\n"
          "newmtl screen\nKd 0.3 0.5 0.35\n\nnewmtl chair\nKd 0.12 0.12 0.14\n\n"
          "newmtl cabinet\nKd 0.55 0.55 0.55\n\nnewmtl shelf\nKd 0.65 0.6 0.5\n\n"
          + books +
          "# Luminaires: emitted radiance L_e in W/(m2 sr) (each panel emits pi L_e A, 38 W).\n"
          "newmtl lamp\nKd 0 0 0\nKe 75 72 66\n")
    write(os.path.join(folder, "office.toml"),
          "# An open-plan office (isorad scene file); see scripts/generate_scenes.py.\n"
          'obj = "office.obj"\nmerge_coplanar = true\n\n[camera]\nposition = [0.4, 1.65, 0.4]\n'
          "look_at = [7.5, 0.6, 6.0]\nup = [0.0, 1.0, 0.0]\nvfov_deg = 62.0\nwidth = 800\nheight = 500\n")


BOOK_COLOURS = [(0.55, 0.12, 0.1), (0.12, 0.22, 0.5), (0.15, 0.4, 0.2), (0.7, 0.62, 0.45),
                (0.2, 0.2, 0.22), (0.65, 0.45, 0.1)]


def cluster(obj, x0, z0):
    """Two benches (3.2 x 0.8 m, top at 0.745 m) face to face, 2 cm apart,
    with a 4 cm screen resting on both, two chairs and two pedestals each."""
    top, thick = 0.745, 0.025
    for side, (za, zb) in enumerate(((z0, z0 + 0.8), (z0 + 0.82, z0 + 1.62))):
        obj.open_box("desk", "desk", (x0, top - thick, za), (x0 + 3.2, top, zb))
        for lx in (x0 + 0.06, x0 + 1.6, x0 + 3.14):
            for lz in (za + 0.06, zb - 0.06):
                obj.prism("desk_leg", "metal", (lx, lz), 0.03, 0.0, top - thick, 8)
        outer = za if side == 0 else zb  # the seated side
        for k in range(2):
            xc = x0 + 0.8 + 1.6 * k
            # Pedestal under the desk, on the floor.
            pz = (za + 0.1, za + 0.7) if side == 0 else (zb - 0.7, zb - 0.1)
            obj.open_box("pedestal", "cabinet", (xc + 0.25, 0.0, pz[0]), (xc + 0.65, 0.6, pz[1]), skip=("-y",))
            chair(obj, xc - 0.1, outer - 0.4 if side == 0 else outer + 0.4, -1 if side == 0 else 1)
    zs = z0 + 0.81
    obj.open_box("desk_screen", "screen", (x0, top, zs - 0.02), (x0 + 3.2, top + 0.4, zs + 0.02), skip=("-y",))


def chair(obj, xc, zc, back_side):
    """An office chair: a square base plate, a column, a seat and a backrest.
    (A 16-sided base plate under the octagonal column makes the contact
    mesher's constrained triangulation panic inside spade 2.15.)"""
    obj.open_box("chair_base", "chair", (xc - 0.25, 0.0, zc - 0.25), (xc + 0.25, 0.05, zc + 0.25), skip=("-y",))
    obj.prism("chair_column", "metal", (xc, zc), 0.03, 0.05, 0.42, 8)
    obj.open_box("chair_seat", "chair", (xc - 0.23, 0.42, zc - 0.23), (xc + 0.23, 0.48, zc + 0.23))
    zb = zc + back_side * 0.23
    obj.open_box("chair_back", "chair", (xc - 0.23, 0.48, min(zb, zb - back_side * 0.05)),
                 (xc + 0.23, 0.98, max(zb, zb - back_side * 0.05)), skip=("-y",))


def bookcase(obj, rng, x0, wall_z):
    """A 1 x 2 x 0.35 m bookcase against the wall at z = wall_z, with four
    shelves of books (boxes standing on the boards, 3 mm apart)."""
    w, h, d = 1.0, 2.0, 0.35
    z0 = wall_z - d
    for sx in (x0, x0 + w - 0.02):
        obj.open_box("bookcase", "shelf", (sx, 0.0, z0), (sx + 0.02, h, wall_z), skip=("-y", "+z"))
    levels = [0.08, 0.5, 0.92, 1.34, 1.76, h - 0.02]
    for y in levels:
        obj.open_box("bookcase", "shelf", (x0 + 0.02, y, z0), (x0 + w - 0.02, y + 0.02, wall_z),
                     skip=("-x", "+x", "+z"))
    obj.open_box("bookcase", "shelf", (x0 + 0.02, 0.0, z0), (x0 + w - 0.02, 0.08, z0 + 0.02), skip=("-y", "+y"))
    for y in levels[:4]:
        x = x0 + 0.025
        while True:
            t = rng.uniform(0.018, 0.045)
            if x + t > x0 + w - 0.025:
                break
            bh, bd = rng.uniform(0.2, 0.3), rng.uniform(0.17, 0.26)
            colour = rng.randrange(len(BOOK_COLOURS))
            obj.open_box("book", f"book{colour}", (x, y + 0.02, z0 + 0.03), (x + t, y + 0.02 + bh, z0 + 0.03 + bd),
                         skip=("-y",))
            x += t + 0.003


if __name__ == "__main__":
    seed(0)
    seed(30)
    seed_material()
    room()
    table()
    downlights()
    office()
