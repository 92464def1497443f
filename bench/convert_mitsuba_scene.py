#!/usr/bin/env python3
"""Convert a Mitsuba 0.6 or Mitsuba 3 scene (scene.xml) into an isorad scene:
one OBJ, its MTL and a scene TOML with the scene's camera.

    convert_mitsuba_scene.py SCENE.xml OUTDIR [--name NAME]
        [-D name=value ...] [--skip-missing] [--max-albedo 0.95]
        [--segments 48] [--drop-transmissive] [--report report.json]

Needs python3 with numpy; pillow for the mean colour of bitmap textures
(without it textured BSDFs fall back to 0.5 grey with a warning).

It is meant for the public interior scenes distributed in Mitsuba's format
(Benedikt Bitterli's rendering resources and the repositories that vendor
them), so that a trial on a real, modeller-exported interior can be
reproduced. The scene files themselves are not part of this repository.

What is read
------------

* ``<default name=.. value=..>`` and ``$name`` substitution (``-D`` overrides
  a default, as Mitsuba's command line does), ``<include filename=..>``,
  objects defined anywhere with an ``id`` and used by ``<ref id=..>``.
  Parameter names are compared case-blind without underscores, so Mitsuba
  0.6's ``toWorld`` / ``diffuseReflectance`` and Mitsuba 3's ``to_world`` /
  ``diffuse_reflectance`` are the same parameter.
* Transforms: ``matrix`` (4x4 or 3x3), ``translate``, ``scale``, ``rotate``,
  ``lookat``; the children of one ``<transform>`` compose left to right in
  the order given (each is applied after the previous one), as in Mitsuba.
* Shapes: ``obj`` (fan-triangulated polygons, negative indices, as Mitsuba's
  loader), ``ply`` (ascii and binary, fan-triangulated), ``serialized``
  (Mitsuba's zlib-compressed format, versions 3 and 4, any ``shapeIndex``;
  see Mitsuba's src/shapes/serialized.cpp), ``rectangle`` (2 triangles),
  ``cube`` (12), ``disk``, ``sphere`` and ``cylinder`` (tessellated with
  ``--segments``), ``shapegroup`` / ``instance``. Every shape's to-world
  transform is applied to its vertices.
* Geometry is not repaired: vertices are written as loaded (no welding),
  degenerate and duplicated faces are kept, windings are kept as the file
  has them. A mesh under a mirroring transform keeps its vertex order, so its
  world-space winding flips exactly as Mitsuba's geometric normal does. Two
  deliberate exceptions, both to keep Mitsuba's *emitting side*:
  ``flipNormals``/``flip_normals`` reverses the winding, and an analytic
  shape (rectangle, disk, ...) under a mirroring transform is reversed so
  that its front stays on the side of Mitsuba's transformed normal.

Materials (MTL ``Kd``)
----------------------

isorad is diffuse-only and its faces are one-sided, opaque and emit and
reflect on their front. Each Mitsuba BSDF becomes one diffuse reflectance
that keeps the energy the BSDF reflects (hemispherical albedo), not its
lobe shape:

* ``diffuse`` / ``roughdiffuse``: ``reflectance``.
* ``plastic`` / ``roughplastic``: a dielectric coat over a diffuse base,
  ``Kd = s*F + (1 - F)*R'`` with F the coat's hemispherical (cosine-weighted)
  Fresnel reflectance for ``intIOR/extIOR`` (default 1.49 / 1.000277), s the
  ``specularReflectance`` (default 1), R the ``diffuseReflectance``; with
  ``nonlinear`` the base's internal bounces give ``R' = R(1 - Fi)/(1 - R Fi)``
  (Fi: internal diffuse Fresnel reflectance), as in Mitsuba's plastic;
  otherwise R' = R.
* ``conductor`` / ``roughconductor``: ``specularReflectance`` times the
  hemispherical Fresnel reflectance of the complex index ``eta + i k``
  (RGB values given in the file, or the named ``material`` from a small
  table: Al, Ag, Au, Cu, Cr; ``none`` is a perfect mirror, albedo 1).
  A mirror thus becomes a bright diffuse surface.
* ``dielectric`` / ``roughdielectric``: the reflected part only,
  ``specularReflectance * F``; the transmitted part is absorbed (isorad's
  faces are opaque). ``thindielectric``: a slab's reflection
  ``R + T^2 R / (1 - R^2)``. With ``--drop-transmissive`` shapes whose BSDF
  transmits light (a dielectric whose ``specularTransmittance`` is not 0)
  are left out instead, so that light passes the glass.
* ``phong`` / ``ward``: diffuse + specular reflectance.
* ``coating`` / ``roughcoating``: F + (1 - F) * the inner BSDF's albedo.
* ``blendbsdf``: the weighted mean of the two BSDFs.
* ``twosided``, ``bumpmap``, ``normalmap``: the inner BSDF. isorad's faces
  stay one-sided: the back of a face Mitsuba rendered two-sided is black.
* ``mask``: the inner BSDF; the opacity is ignored (the face is opaque).
* ``null``: black. ``principled``: ``base_color``. Anything else: 0.5 grey,
  with a warning.
* Textures give their mean colour: bitmap textures are read with pillow and
  averaged in linear values (8-bit images decoded as sRGB unless ``gamma`` /
  ``raw`` say otherwise; EXR/HDR cannot be read and give 0.5 with a warning),
  ``scale`` multiplies, ``checkerboard`` averages its two colours.
* Spectra: ``rgb`` linear, ``srgb`` decoded from sRGB, ``spectrum`` with one
  value is grey, with ``wavelength:value`` pairs their mean as grey (a
  stated simplification), ``blackbody`` is not converted (white, warning).
* Every ``Kd`` channel is clamped to ``[0, --max-albedo]`` (default 0.95:
  isorad needs it below 1); the clamped materials are listed.

Emitters
--------

An ``area`` emitter on a shape gives its material ``Ke`` = the emitter's
``radiance`` (times ``scale`` if given); the material's ``Kd`` still comes
from the shape's BSDF. Mitsuba's area lights are one-sided like isorad's.
Emitters that are not on a shape (``envmap``, ``sunsky``, ``constant``,
``point``, ``spot``, ``directional`` ...) have no isorad equivalent here;
they are listed as a warning and in the TOML's header comment.

Camera
------

The first ``perspective`` / ``thinlens`` sensor: position = the to-world
transform's translation, look_at = position + its third column (Mitsuba's
camera looks along local +z), up = its second column; ``fov`` with
``fovAxis`` (default ``x``) or ``focalLength`` (36 mm film width) becomes the
vertical ``vfov_deg`` for the film's ``width`` x ``height``. Mitsuba's image
right is minus the first column, which is isorad's forward x up when the
transform does not mirror; a mirroring camera is reported.

Output
------

``OUTDIR/NAME.obj`` (one ``o`` object per Mitsuba shape, named after its id
or file), ``NAME.mtl``, ``NAME.toml`` and, with ``--report``, a JSON file
with the counts printed at the end: triangles, emitting triangles and the
planes each emitter spans, degenerate faces, duplicated faces (same three
positions, same or opposite winding) and edges whose two faces are wound
inconsistently (the same directed edge used twice, positions compared
exactly).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import re
import struct
import sys
import xml.etree.ElementTree as ET
import zlib
from collections import defaultdict

import numpy as np

try:
    from PIL import Image
except ImportError:  # pragma: no cover
    Image = None

WARNINGS: list[str] = []


def warn(msg: str) -> None:
    WARNINGS.append(msg)
    print(f"warning: {msg}", file=sys.stderr)


def norm_name(name: str | None) -> str:
    return (name or "").replace("_", "").lower()


# ---------------------------------------------------------------- XML


def floats(text: str) -> list[float]:
    return [float(t) for t in re.split(r"[,\s]+", text.strip()) if t]


def substitute(elem: ET.Element, params: dict[str, str]) -> None:
    """Replace $name in every attribute value (Mitsuba's <default> / -D)."""
    pat = re.compile(r"\$([A-Za-z_][A-Za-z0-9_]*)")
    for e in elem.iter():
        for k, v in list(e.attrib.items()):
            if "$" in v:
                e.attrib[k] = pat.sub(lambda m: params.get(m.group(1), m.group(0)), v)


def load_xml(path: str, overrides: dict[str, str]) -> ET.Element:
    root = ET.parse(path).getroot()
    base = os.path.dirname(os.path.abspath(path))
    # includes: splice the included scene's children in place
    changed = True
    while changed:
        changed = False
        for parent in root.iter():
            for i, child in enumerate(list(parent)):
                if child.tag == "include":
                    inc = os.path.join(base, child.get("filename", ""))
                    sub = ET.parse(inc).getroot()
                    parent.remove(child)
                    for j, c in enumerate(list(sub)):
                        parent.insert(i + j, c)
                    changed = True
                    break
            if changed:
                break
    params = {}
    for d in root.iter("default"):
        params[d.get("name")] = d.get("value")
    params.update(overrides)
    substitute(root, params)
    return root


class Scene:
    def __init__(self, root: ET.Element, base: str):
        self.root = root
        self.base = base
        self.ids: dict[str, ET.Element] = {}
        for e in root.iter():
            if e.tag != "ref" and e.get("id") is not None:
                self.ids[e.get("id")] = e

    def deref(self, e: ET.Element | None) -> ET.Element | None:
        while e is not None and e.tag == "ref":
            tgt = self.ids.get(e.get("id"))
            if tgt is None:
                warn(f"reference to unknown id `{e.get('id')}`")
            e = tgt
        return e

    def prop(self, obj: ET.Element, name: str) -> ET.Element | None:
        """The child of obj that sets parameter `name` (dereferenced)."""
        key = norm_name(name)
        for c in obj:
            if norm_name(c.get("name")) == key:
                return self.deref(c)
        return None

    def value(self, obj, name, default=None):
        e = self.prop(obj, name)
        if e is None:
            return default
        v = e.get("value")
        if e.tag in ("float", "integer"):
            return float(v)
        if e.tag == "boolean":
            return v.strip().lower() == "true"
        return v

    def child_bsdf(self, obj: ET.Element) -> ET.Element | None:
        for c in obj:
            if c.tag == "bsdf":
                return c
            if c.tag == "ref" and c.get("name") in (None, "bsdf"):
                t = self.deref(c)
                if t is not None and t.tag == "bsdf":
                    return t
        return None


# ---------------------------------------------------------------- transforms


def vec3_attr(e: ET.Element, default: float) -> np.ndarray:
    if e.get("value") is not None:
        v = floats(e.get("value"))
        if len(v) == 1:
            return np.array([v[0]] * 3)
        return np.array(v[:3])
    return np.array([float(e.get(k, default)) for k in "xyz"])


def rotation(axis: np.ndarray, angle_deg: float) -> np.ndarray:
    a = axis / np.linalg.norm(axis)
    t = math.radians(angle_deg)
    c, s = math.cos(t), math.sin(t)
    x, y, z = a
    r = np.array([
        [x * x + (1 - x * x) * c, x * y * (1 - c) - z * s, x * z * (1 - c) + y * s],
        [x * y * (1 - c) + z * s, y * y + (1 - y * y) * c, y * z * (1 - c) - x * s],
        [x * z * (1 - c) - y * s, y * z * (1 - c) + x * s, z * z + (1 - z * z) * c],
    ])
    m = np.eye(4)
    m[:3, :3] = r
    return m


def lookat(origin, target, up) -> np.ndarray:
    d = target - origin
    d /= np.linalg.norm(d)
    left = np.cross(up, d)
    left /= np.linalg.norm(left)
    new_up = np.cross(d, left)
    m = np.eye(4)
    m[:3, 0], m[:3, 1], m[:3, 2], m[:3, 3] = left, new_up, d, origin
    return m


def parse_transform(e: ET.Element | None) -> np.ndarray:
    m = np.eye(4)
    if e is None:
        return m
    for c in e:
        t = np.eye(4)
        tag = c.tag.lower()
        if tag == "matrix":
            v = floats(c.get("value"))
            if len(v) == 16:
                t = np.array(v).reshape(4, 4)
            elif len(v) == 9:
                t[:3, :3] = np.array(v).reshape(3, 3)
            else:
                raise ValueError(f"matrix with {len(v)} values")
        elif tag == "translate":
            t[:3, 3] = vec3_attr(c, 0.0)
        elif tag == "scale":
            t[:3, :3] = np.diag(vec3_attr(c, 1.0))
        elif tag == "rotate":
            if c.get("value") is not None:
                axis = np.array(floats(c.get("value")))
            else:
                axis = np.array([float(c.get(k, 0)) for k in "xyz"])
            t = rotation(axis, float(c.get("angle", 0)))
        elif tag == "lookat":
            o = np.array(floats(c.get("origin")))
            tg = np.array(floats(c.get("target")))
            up = np.array(floats(c.get("up", "0, 1, 0")))
            t = lookat(o, tg, up)
        else:
            warn(f"transform element <{c.tag}> ignored")
        m = t @ m
    return m


def apply(m: np.ndarray, p: np.ndarray) -> np.ndarray:
    return p @ m[:3, :3].T + m[:3, 3]


# ---------------------------------------------------------------- mesh files


def read_obj(path: str):
    """Positions and fan-triangulated faces (0-based), like Mitsuba's loader.
    Also the usemtl name of each triangle and the file's mtllib."""
    verts: list[tuple[float, float, float]] = []
    tris: list[tuple[int, int, int]] = []
    mats: list[str] = []
    cur = ""
    mtllib = None
    with open(path, "r", errors="replace") as f:
        for line in f:
            if line.startswith("v "):
                p = line.split()
                verts.append((float(p[1]), float(p[2]), float(p[3])))
            elif line.startswith("f "):
                idx = []
                n = len(verts)
                for tok in line.split()[1:]:
                    i = int(tok.split("/", 1)[0])
                    idx.append(i - 1 if i > 0 else n + i)
                for k in range(1, len(idx) - 1):
                    tris.append((idx[0], idx[k], idx[k + 1]))
                    mats.append(cur)
            elif line.startswith("usemtl"):
                cur = line[6:].strip()
            elif line.startswith("mtllib"):
                mtllib = line[6:].strip()
    return (np.array(verts, dtype=np.float64).reshape(-1, 3),
            np.array(tris, dtype=np.int64).reshape(-1, 3), mats, mtllib)


PLY_TYPES = {
    "char": "i1", "int8": "i1", "uchar": "u1", "uint8": "u1",
    "short": "i2", "int16": "i2", "ushort": "u2", "uint16": "u2",
    "int": "i4", "int32": "i4", "uint": "u4", "uint32": "u4",
    "float": "f4", "float32": "f4", "double": "f8", "float64": "f8",
}


def read_ply(path: str):
    with open(path, "rb") as f:
        data = f.read()
    end = data.index(b"end_header") + len(b"end_header")
    while data[end:end + 1] in (b"\r", b"\n"):
        end += 1
        if data[end - 1:end] == b"\n":
            break
    header = data[:end].decode("ascii", "replace").splitlines()
    fmt = "ascii"
    elements = []  # (name, count, [(prop, type, listcount_type or None)])
    for line in header:
        p = line.split()
        if not p:
            continue
        if p[0] == "format":
            fmt = p[1]
        elif p[0] == "element":
            elements.append((p[1], int(p[2]), []))
        elif p[0] == "property":
            if p[1] == "list":
                elements[-1][2].append((p[4], p[3], p[2]))
            else:
                elements[-1][2].append((p[2], p[1], None))
    body = data[end:]
    verts = None
    tris: list = []
    if fmt == "ascii":
        toks = body.split()
        pos = 0
        for name, count, props in elements:
            rows = []
            for _ in range(count):
                row = {}
                for pname, ptype, ltype in props:
                    if ltype is None:
                        row[pname] = float(toks[pos]); pos += 1
                    else:
                        n = int(toks[pos]); pos += 1
                        row[pname] = [int(t) for t in toks[pos:pos + n]]; pos += n
                rows.append(row)
            if name == "vertex":
                verts = np.array([[r["x"], r["y"], r["z"]] for r in rows], dtype=np.float64)
            elif name == "face":
                for r in rows:
                    idx = r.get("vertex_indices", r.get("vertex_index"))
                    for k in range(1, len(idx) - 1):
                        tris.append((idx[0], idx[k], idx[k + 1]))
    else:
        order = "<" if fmt == "binary_little_endian" else ">"
        off = 0
        for name, count, props in elements:
            if all(lt is None for _, _, lt in props):
                dt = np.dtype([(pn, order + PLY_TYPES[pt]) for pn, pt, _ in props])
                arr = np.frombuffer(body, dtype=dt, count=count, offset=off)
                off += dt.itemsize * count
                if name == "vertex":
                    verts = np.stack([arr["x"], arr["y"], arr["z"]], axis=1).astype(np.float64)
                continue
            # elements with lists: the common all-triangles face layout fast,
            # anything else element by element
            for _ in range(count):
                row = {}
                for pn, pt, lt in props:
                    if lt is None:
                        dt = np.dtype(order + PLY_TYPES[pt])
                        row[pn] = np.frombuffer(body, dt, 1, off)[0]
                        off += dt.itemsize
                    else:
                        ct = np.dtype(order + PLY_TYPES[lt])
                        n = int(np.frombuffer(body, ct, 1, off)[0]); off += ct.itemsize
                        it = np.dtype(order + PLY_TYPES[pt])
                        row[pn] = np.frombuffer(body, it, n, off); off += it.itemsize * n
                if name == "face":
                    idx = row.get("vertex_indices", row.get("vertex_index"))
                    for k in range(1, len(idx) - 1):
                        tris.append((int(idx[0]), int(idx[k]), int(idx[k + 1])))
    return verts.reshape(-1, 3), np.array(tris, dtype=np.int64).reshape(-1, 3)


def read_serialized(path: str, shape_index: int):
    """Mitsuba's .serialized format (little endian; versions 3 and 4)."""
    with open(path, "rb") as f:
        data = f.read()
    fmt_id, version = struct.unpack_from("<HH", data, 0)
    if fmt_id != 0x041C or version not in (3, 4):
        raise ValueError(f"{path}: not a Mitsuba serialized mesh (0x{fmt_id:x} v{version})")
    start = 0
    if shape_index != 0:
        (count,) = struct.unpack_from("<I", data, len(data) - 4)
        if shape_index >= count:
            raise ValueError(f"{path}: shapeIndex {shape_index} of {count}")
        if version == 4:
            (start,) = struct.unpack_from("<Q", data, len(data) - 4 - 8 * (count - shape_index))
        else:
            (start,) = struct.unpack_from("<I", data, len(data) - 4 * (count - shape_index + 1))
    d = zlib.decompressobj()
    raw = d.decompress(data[start + 4:])
    pos = 0
    (flags,) = struct.unpack_from("<I", raw, pos); pos += 4
    name = ""
    if version == 4:
        z = raw.index(b"\0", pos)
        name = raw[pos:z].decode("utf-8", "replace")
        pos = z + 1
    nv, nt = struct.unpack_from("<QQ", raw, pos); pos += 16
    ft = np.dtype("<f8") if flags & 0x2000 else np.dtype("<f4")
    verts = np.frombuffer(raw, ft, nv * 3, pos).reshape(-1, 3).astype(np.float64)
    pos += ft.itemsize * nv * 3
    if flags & 0x0001:
        pos += ft.itemsize * nv * 3
    if flags & 0x0002:
        pos += ft.itemsize * nv * 2
    if flags & 0x0008:
        pos += ft.itemsize * nv * 3
    it = np.dtype("<u8") if nv > 0xFFFFFFFF else np.dtype("<u4")
    tris = np.frombuffer(raw, it, nt * 3, pos).reshape(-1, 3).astype(np.int64)
    return verts, tris, name


# ---------------------------------------------------------------- analytic shapes


def rectangle():
    v = np.array([[-1, -1, 0], [1, -1, 0], [1, 1, 0], [-1, 1, 0]], float)
    return v, np.array([[0, 1, 2], [2, 3, 0]])


def cube():
    v, f = [], []
    for axis in range(3):
        for sign in (-1.0, 1.0):
            u, w = (axis + 1) % 3, (axis + 2) % 3
            base = len(v)
            for a, b in ((-1, -1), (1, -1), (1, 1), (-1, 1)):
                p = [0.0, 0.0, 0.0]
                p[axis], p[u], p[w] = sign, a, b
                v.append(p)
            quad = [base, base + 1, base + 2, base + 3]
            if sign < 0:
                quad = quad[::-1]
            f += [[quad[0], quad[1], quad[2]], [quad[2], quad[3], quad[0]]]
    return np.array(v, float), np.array(f)


def disk(n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    v = np.concatenate([[[0, 0, 0]], np.stack([np.cos(t), np.sin(t), 0 * t], 1)])
    f = [[0, 1 + i, 1 + (i + 1) % n] for i in range(n)]
    return v, np.array(f)


def sphere(n):
    rings = max(n // 2, 2)
    v = [[0, 0, -1.0]]
    for i in range(1, rings):
        th = np.pi * i / rings - np.pi / 2
        for j in range(n):
            ph = 2 * np.pi * j / n
            v.append([math.cos(th) * math.cos(ph), math.cos(th) * math.sin(ph), math.sin(th)])
    v.append([0, 0, 1.0])
    top = len(v) - 1
    f = []
    for j in range(n):
        f.append([0, 1 + (j + 1) % n, 1 + j])
    for i in range(rings - 2):
        a, b = 1 + i * n, 1 + (i + 1) * n
        for j in range(n):
            j2 = (j + 1) % n
            f += [[a + j, a + j2, b + j2], [b + j2, b + j, a + j]]
    a = 1 + (rings - 2) * n
    for j in range(n):
        f.append([a + j, a + (j + 1) % n, top])
    return np.array(v, float), np.array(f)


def cylinder(n):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    ring = np.stack([np.cos(t), np.sin(t), 0 * t], 1)
    v = np.concatenate([ring, ring + [0, 0, 1]])
    f = []
    for j in range(n):
        j2 = (j + 1) % n
        f += [[j, j2, n + j2], [n + j2, n + j, j]]
    return v, np.array(f)


# ---------------------------------------------------------------- spectra and BSDFs

IOR = {"vacuum": 1.0, "helium": 1.000036, "hydrogen": 1.000132, "air": 1.000277,
       "carbon dioxide": 1.00045, "water": 1.333, "acetone": 1.36, "ethanol": 1.361,
       "carbon tetrachloride": 1.461, "glycerol": 1.4729, "benzene": 1.501,
       "silicone oil": 1.52045, "bromine": 1.661, "water ice": 1.31,
       "fused quartz": 1.458, "pyrex": 1.47, "acrylic glass": 1.49,
       "polypropylene": 1.49, "bk7": 1.5046, "sodium chloride": 1.544,
       "amber": 1.55, "pet": 1.575, "diamond": 2.419}

# RGB complex indices of refraction (the values Bitterli's exports write)
CONDUCTORS = {
    "al": ((1.65746, 0.880369, 0.521229), (9.22387, 6.26952, 4.837)),
    "ag": ((0.155265, 0.116723, 0.138342), (4.82835, 3.12225, 2.14696)),
    "au": ((0.143119, 0.374957, 1.44248), (3.98316, 2.38572, 1.60322)),
    "cu": ((0.200438, 0.924033, 1.10221), (3.91295, 2.45285, 2.14219)),
    "cr": ((4.36968, 2.9167, 1.6547), (5.20643, 4.23136, 3.75495)),
}

MU = (np.arange(4096) + 0.5) / 4096  # cos(theta) samples for hemispherical means


def fresnel_dielectric(mu, eta):
    """Unpolarised Fresnel reflectance for incidence cosine mu, relative IOR eta."""
    sin2t = (1 - mu * mu) / (eta * eta)
    tir = sin2t >= 1
    cost = np.sqrt(np.clip(1 - sin2t, 0, 1))
    rs = (mu - eta * cost) / (mu + eta * cost)
    rp = (eta * mu - cost) / (eta * mu + cost)
    return np.where(tir, 1.0, 0.5 * (rs * rs + rp * rp))


def hemi_dielectric(eta: float) -> float:
    """Cosine-weighted hemispherical Fresnel reflectance, 2 int F(mu) mu dmu."""
    return float(2 * np.mean(fresnel_dielectric(MU, eta) * MU))


def hemi_conductor(eta: float, k: float) -> float:
    """The same for a conductor of complex index eta + i k (pbrt's FrConductor)."""
    mu = MU
    cos2 = mu * mu
    sin2 = 1 - cos2
    t0 = eta * eta - k * k - sin2
    a2b2 = np.sqrt(t0 * t0 + 4 * eta * eta * k * k)
    a = np.sqrt(0.5 * (a2b2 + t0))
    t1, t2 = a2b2 + cos2, 2 * mu * a
    rs = (t1 - t2) / (t1 + t2)
    t3, t4 = cos2 * a2b2 + sin2 * sin2, t2 * sin2
    rp = rs * (t3 - t4) / (t3 + t4)
    return float(2 * np.mean(0.5 * (rs + rp) * mu))


def srgb_to_linear(c):
    c = np.asarray(c, float)
    return np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)


def parse_colour_text(text: str, srgb: bool) -> np.ndarray:
    text = text.strip()
    if text.startswith("#"):
        h = text[1:]
        c = np.array([int(h[i:i + 2], 16) / 255.0 for i in (0, 2, 4)])
        return srgb_to_linear(c) if srgb else c
    v = floats(text)
    c = np.array(v * 3 if len(v) == 1 else v[:3], float)
    return srgb_to_linear(c) if srgb else c


class Materials:
    def __init__(self, scene: Scene, max_albedo: float):
        self.s = scene
        self.max_albedo = max_albedo
        self.tex_cache: dict[int, np.ndarray] = {}
        self.notes: dict[str, str] = {}

    # spectra and textures ------------------------------------------------
    def spectrum(self, obj, name, default):
        e = self.s.prop(obj, name)
        if e is None:
            return np.array(default, float) * np.ones(3)
        return self.spectrum_of(e)

    def spectrum_of(self, e: ET.Element) -> np.ndarray:
        tag = e.tag
        if tag in ("rgb", "color"):
            return parse_colour_text(e.get("value"), srgb=False)
        if tag == "srgb":
            return parse_colour_text(e.get("value"), srgb=True)
        if tag == "float":
            return np.full(3, float(e.get("value")))
        if tag == "spectrum":
            v = e.get("value")
            if v is None and e.get("filename"):
                warn(f"spectrum file {e.get('filename')} not read: 1.0 used")
                return np.ones(3)
            if ":" in v:
                pairs = [p.split(":") for p in re.split(r"[,\s]+", v.strip()) if p]
                vals = [float(b) for _, b in pairs]
                return np.full(3, float(np.mean(vals)))
            vv = floats(v)
            return np.array(vv * 3 if len(vv) == 1 else vv[:3], float)
        if tag == "blackbody":
            warn("blackbody spectrum not converted: white used")
            return np.ones(3) * float(e.get("scale", 1))
        if tag == "texture":
            return self.texture_mean(e)
        warn(f"<{tag}> used as a spectrum: 0.5 used")
        return np.full(3, 0.5)

    def texture_mean(self, e: ET.Element) -> np.ndarray:
        key = id(e)
        if key in self.tex_cache:
            return self.tex_cache[key]
        t = e.get("type")
        if t == "bitmap":
            c = self.bitmap_mean(e)
        elif t == "scale":
            inner = None
            for ch in e:
                if ch.tag in ("texture", "ref") or norm_name(ch.get("name")) == "texture":
                    inner = self.s.deref(ch)
            c = self.texture_mean(inner) if inner is not None else np.full(3, 0.5)
            c = c * float(self.s.value(e, "scale", 1.0))
        elif t == "checkerboard":
            c = 0.5 * (self.spectrum(e, "color0", 0.4) + self.spectrum(e, "color1", 0.2))
        else:
            warn(f"texture type `{t}` not converted: 0.5 used")
            c = np.full(3, 0.5)
        self.tex_cache[key] = c
        return c

    def bitmap_mean(self, e: ET.Element) -> np.ndarray:
        fn = self.s.value(e, "filename")
        path = resolve_path(self.s.base, fn)
        if Image is None:
            warn(f"pillow missing: texture {fn} taken as 0.5")
            return np.full(3, 0.5)
        if not os.path.exists(path) or fn.lower().endswith((".exr", ".hdr", ".pfm")):
            warn(f"texture {fn} {'missing' if not os.path.exists(path) else 'is HDR, not read'}: 0.5 used")
            return np.full(3, 0.5)
        im = Image.open(path)
        arr = np.asarray(im)
        if im.mode in ("I;16", "I;16B", "I"):
            arr = arr.astype(float) / 65535.0
            arr = np.repeat(arr[..., None], 3, axis=2)
        else:
            im = im.convert("RGB")
            arr = np.asarray(im).astype(float) / 255.0
        raw = self.s.value(e, "raw", False)
        gamma = float(self.s.value(e, "gamma", 0.0) or 0.0)
        if raw:
            lin = arr
        elif gamma > 0:
            lin = arr ** gamma
        else:  # Mitsuba: 8-bit images are sRGB unless told otherwise
            lin = srgb_to_linear(arr)
        return lin.reshape(-1, 3).mean(axis=0)

    def ior(self, obj, name, default):
        e = self.s.prop(obj, name)
        if e is None:
            return default
        v = e.get("value").strip()
        try:
            return float(v)
        except ValueError:
            if v.lower() in IOR:
                return IOR[v.lower()]
            warn(f"unknown IOR `{v}`: {default} used")
            return default

    def eta(self, obj):
        return self.ior(obj, "intIOR", 1.5046) / self.ior(obj, "extIOR", 1.000277)

    def inner(self, e):
        for c in e:
            if c.tag == "bsdf":
                return c
            if c.tag == "ref":
                t = self.s.deref(c)
                if t is not None and t.tag == "bsdf":
                    return t
        return None

    def inners(self, e):
        out = []
        for c in e:
            if c.tag == "bsdf":
                out.append(c)
            elif c.tag == "ref":
                t = self.s.deref(c)
                if t is not None and t.tag == "bsdf":
                    out.append(t)
        return out

    def transmits(self, e: ET.Element | None) -> bool:
        if e is None:
            return False
        t = e.get("type")
        if t in ("dielectric", "roughdielectric", "thindielectric"):
            return bool(np.any(self.spectrum(e, "specularTransmittance", 1.0) > 0))
        if t in ("twosided", "mask", "bumpmap", "normalmap", "coating", "roughcoating"):
            return self.transmits(self.inner(e))
        return False

    # BSDF albedo -----------------------------------------------------------
    def albedo(self, e: ET.Element | None) -> tuple[np.ndarray, str]:
        if e is None:
            return np.full(3, 0.5), "no BSDF: Mitsuba's default diffuse 0.5"
        t = e.get("type")
        S = self.spectrum
        if t in ("twosided", "bumpmap", "normalmap"):
            a, n = self.albedo(self.inner(e))
            return a, f"{t} -> {n}"
        if t == "mask":
            a, n = self.albedo(self.inner(e))
            op = self.s.prop(e, "opacity")
            opn = "" if op is None else f" (opacity {np.round(self.spectrum_of(op), 3).tolist()} ignored)"
            return a, f"mask{opn} -> {n}"
        if t in ("diffuse", "roughdiffuse", "orennayar"):
            return S(e, "reflectance", 0.5), t
        if t in ("plastic", "roughplastic"):
            eta = self.ior(e, "intIOR", 1.49) / self.ior(e, "extIOR", 1.000277)
            fe, fi = hemi_dielectric(eta), hemi_dielectric(1 / eta)
            r = S(e, "diffuseReflectance", 0.5)
            sp = S(e, "specularReflectance", 1.0)
            if self.s.value(e, "nonlinear", False):
                r = r * (1 - fi) / (1 - r * fi)
            return sp * fe + (1 - fe) * r, f"{t} (coat F={fe:.3f})"
        if t in ("conductor", "roughconductor"):
            mat = self.s.value(e, "material", None)
            sp = S(e, "specularReflectance", 1.0)
            if self.s.prop(e, "eta") is not None:
                eta, k = S(e, "eta", 1.0), S(e, "k", 0.0)
            elif mat is not None and mat.lower() == "none":
                return sp, f"{t} material=none (perfect mirror)"
            else:
                name = (mat or "Cu").lower()
                if name not in CONDUCTORS:
                    warn(f"conductor material `{mat}` not in the table: Al used")
                    name = "al"
                eta, k = map(np.array, CONDUCTORS[name])
            f = np.array([hemi_conductor(abs(eta[i]), abs(k[i])) for i in range(3)])
            return sp * f, f"{t} (hemispherical Fresnel {np.round(f, 3).tolist()})"
        if t in ("dielectric", "roughdielectric"):
            f = hemi_dielectric(self.eta(e))
            return S(e, "specularReflectance", 1.0) * f, f"{t} reflection only (F={f:.3f})"
        if t == "thindielectric":
            r = hemi_dielectric(self.eta(e))
            a = r + (1 - r) ** 2 * r / (1 - r * r)
            return S(e, "specularReflectance", 1.0) * a, f"thindielectric reflection only ({a:.3f})"
        if t in ("phong", "ward"):
            return (S(e, "diffuseReflectance", 0.5) + S(e, "specularReflectance", 0.2)), t
        if t in ("coating", "roughcoating"):
            f = hemi_dielectric(self.ior(e, "intIOR", 1.5046) / self.ior(e, "extIOR", 1.000277))
            a, n = self.albedo(self.inner(e))
            return f + (1 - f) * a, f"{t} -> {n}"
        if t in ("blendbsdf", "blend"):
            w = self.s.prop(e, "weight")
            w = 0.5 if w is None else float(np.mean(self.spectrum_of(w)))
            bs = self.inners(e)
            if len(bs) == 2:
                (a0, _), (a1, _) = self.albedo(bs[0]), self.albedo(bs[1])
                return (1 - w) * a0 + w * a1, "blendbsdf"
        if t == "null":
            return np.zeros(3), "null BSDF (invisible in Mitsuba): black, opaque here"
        if t == "principled":
            return S(e, "base_color", 0.5), "principled base_color"
        warn(f"BSDF type `{t}` not converted: 0.5 grey")
        return np.full(3, 0.5), f"{t} (unknown)"


# ---------------------------------------------------------------- conversion


def sanitize(name: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.\-]+", "_", name).strip("_") or "unnamed"


class Converter:
    def __init__(self, scene: Scene, args):
        self.s = scene
        self.args = args
        self.mats = Materials(scene, args.max_albedo)
        self.objects = []  # (name, material, verts(N,3), tris(M,3))
        self.materials: dict[str, dict] = {}
        self.mat_key: dict[tuple, str] = {}
        self.names: set[str] = set()
        self.missing: list[str] = []
        self.other_emitters: list[str] = []
        self.dropped: list[str] = []

    def unique(self, base: str, used: set[str]) -> str:
        base = sanitize(base)
        name, i = base, 1
        while name in used:
            i += 1
            name = f"{base}_{i}"
        used.add(name)
        return name

    def material(self, bsdf: ET.Element | None, emitter: ET.Element | None) -> str:
        ke = None
        if emitter is not None:
            if emitter.get("type") != "area":
                warn(f"emitter type `{emitter.get('type')}` on a shape: treated as area")
            ke = self.mats.spectrum(emitter, "radiance", 1.0) * float(self.s.value(emitter, "scale", 1.0))
            ke = tuple(float(x) for x in ke)
        bid = bsdf.get("id") if bsdf is not None else None
        kd, note = self.mats.albedo(bsdf)
        kd_t = tuple(round(float(x), 6) for x in kd)
        key = (bid if bid is not None else ("inline", kd_t), ke)
        if key in self.mat_key:
            return self.mat_key[key]
        if bid is not None:
            base = bid if ke is None else f"{bid}_emit"
        else:
            base = "emitter" if ke is not None else "inline"
        name = self.unique(base, set(self.materials))
        clamped = np.clip(kd, 0, self.args.max_albedo)
        self.materials[name] = {
            "kd": [float(x) for x in clamped], "kd_raw": [float(x) for x in kd],
            "ke": list(ke) if ke is not None else None, "note": note,
            "clamped": bool(np.any(kd > self.args.max_albedo) or np.any(kd < 0)),
        }
        self.mat_key[key] = name
        return name

    def shape_geometry(self, e: ET.Element):
        """Object-space vertices and triangles of a shape (or None), and
        whether the shape is analytic (its front follows the transformed
        normal, not the winding)."""
        t = e.get("type")
        seg = self.args.segments
        if t in ("obj", "ply", "serialized"):
            fn = self.s.value(e, "filename")
            path = resolve_path(self.s.base, fn)
            if not os.path.exists(path):
                if self.args.skip_missing:
                    warn(f"mesh file {fn} is missing: shape left out")
                    self.missing.append(fn)
                    return None
                sys.exit(f"error: mesh file {path} not found (--skip-missing leaves it out)")
            if t == "obj":
                v, f, mats, mtllib = read_obj(path)
                return v, f, False, (mats, mtllib, os.path.dirname(path))
            if t == "ply":
                v, f = read_ply(path)
                return v, f, False, None
            idx = int(self.s.value(e, "shapeIndex", 0))
            v, f, _ = read_serialized(path, idx)
            return v, f, False, None
        if t == "rectangle":
            v, f = rectangle()
        elif t == "cube":
            v, f = cube()
        elif t == "disk":
            v, f = disk(seg)
        elif t == "sphere":
            v, f = sphere(seg)
            r = float(self.s.value(e, "radius", 1.0))
            c = self.s.prop(e, "center")
            c = np.zeros(3) if c is None else (
                np.array(floats(c.get("value"))) if c.get("value") else
                np.array([float(c.get(k, 0)) for k in "xyz"]))
            v = v * r + c
        elif t == "cylinder":
            v, f = cylinder(seg)
            p0, p1 = self.s.prop(e, "p0"), self.s.prop(e, "p1")
            r = float(self.s.value(e, "radius", 1.0))
            if p0 is not None or p1 is not None:
                def pt(x, d):
                    if x is None:
                        return np.array(d, float)
                    if x.get("value"):
                        return np.array(floats(x.get("value")))
                    return np.array([float(x.get(k, 0)) for k in "xyz"])
                a, b = pt(p0, [0, 0, 0]), pt(p1, [0, 0, 1])
                d = b - a
                h = np.linalg.norm(d)
                w = d / h
                u = np.cross(w, [1, 0, 0] if abs(w[0]) < 0.9 else [0, 1, 0])
                u /= np.linalg.norm(u)
                vv = np.cross(w, u)
                v = a + np.outer(v[:, 0] * r, u) + np.outer(v[:, 1] * r, vv) + np.outer(v[:, 2] * h, w)
            else:
                v = v * [r, r, 1]
        else:
            warn(f"shape type `{t}` not converted")
            return None
        return v, f, True, None

    def add_shape(self, e: ET.Element, parent: np.ndarray, label_hint: str = ""):
        t = e.get("type")
        if t == "shapegroup":
            return  # only through instances
        if t == "instance":
            grp = None
            for c in e:
                g = self.s.deref(c) if c.tag == "ref" else None
                if g is not None and g.tag == "shape" and g.get("type") == "shapegroup":
                    grp = g
            if grp is None:
                warn("instance without a shapegroup")
                return
            m = parent @ parse_transform(self.s.prop(e, "toWorld"))
            for c in grp:
                if c.tag == "shape":
                    self.add_shape(c, m, f"{grp.get('id')}")
            return
        bsdf = self.s.child_bsdf(e)
        emitter = next((c for c in e if c.tag == "emitter"), None)
        if self.args.drop_transmissive and emitter is None and self.mats.transmits(bsdf):
            label = e.get("id") or self.s.value(e, "filename", t)
            self.dropped.append(str(label))
            return
        g = self.shape_geometry(e)
        if g is None:
            return
        v, f, analytic, objinfo = g
        m = parent @ parse_transform(self.s.prop(e, "toWorld"))
        vw = apply(m, v)
        f = f.copy()
        flip = bool(self.s.value(e, "flipNormals", False))
        if analytic and np.linalg.det(m[:3, :3]) < 0:
            flip = not flip
        if flip:
            f = f[:, ::-1]
        fn = self.s.value(e, "filename")
        label = e.get("id") or (os.path.splitext(os.path.basename(fn))[0] if fn else t)
        if label_hint:
            label = f"{label_hint}.{label}"
        if t == "serialized":
            label = f"{label}@{int(self.s.value(e, 'shapeIndex', 0))}" if not e.get("id") else label
        if bsdf is None and objinfo is not None and any(objinfo[0]):
            # no BSDF in the XML: the OBJ's own usemtl/MTL, as Mitsuba does
            mats, mtllib, d = objinfo
            kds = read_mtl(os.path.join(d, mtllib)) if mtllib else {}
            groups = defaultdict(list)
            for i, mn in enumerate(mats):
                groups[mn].append(i)
            for mn, idx in groups.items():
                name = self.obj_mtl_material(mn, kds.get(mn), emitter)
                self.objects.append((self.unique(f"{label}_{mn}", self.names), name, vw,
                                     f[np.array(idx)], emitter is not None))
            return
        name = self.material(bsdf, emitter)
        self.objects.append((self.unique(label, self.names), name, vw, f, emitter is not None))

    def obj_mtl_material(self, mn, kd, emitter):
        key = ("objmtl", mn, emitter is not None)
        if key in self.mat_key:
            return self.mat_key[key]
        ke = None
        if emitter is not None:
            ke = [float(x) for x in self.mats.spectrum(emitter, "radiance", 1.0)]
        kd = np.full(3, 0.5) if kd is None else np.array(kd)
        name = self.unique(mn or "default", set(self.materials))
        self.materials[name] = {"kd": [float(x) for x in np.clip(kd, 0, self.args.max_albedo)],
                                "kd_raw": [float(x) for x in kd], "ke": ke,
                                "note": "OBJ's own MTL Kd", "clamped": bool(np.any(kd > self.args.max_albedo))}
        self.mat_key[key] = name
        return name

    def run(self):
        for c in self.s.root:
            if c.tag == "shape":
                self.add_shape(c, np.eye(4))
            elif c.tag == "emitter":
                self.other_emitters.append(c.get("type"))
        if self.other_emitters:
            warn("emitters not on a shape are not converted: " + ", ".join(self.other_emitters))

    # camera -------------------------------------------------------------
    def camera(self):
        sensor = next((c for c in self.s.root.iter("sensor")), None)
        if sensor is None:
            return None
        m = parse_transform(self.s.prop(sensor, "toWorld"))
        film = next((c for c in sensor if c.tag == "film"), None)
        w = int(float(self.s.value(film, "width", 768))) if film is not None else 768
        h = int(float(self.s.value(film, "height", 576))) if film is not None else 576
        axis = (self.s.value(sensor, "fovAxis", "x") or "x").lower()
        fov = self.s.value(sensor, "fov", None)
        if fov is None:
            fl = self.s.value(sensor, "focalLength", "50mm")
            flv = float(re.sub(r"mm$", "", str(fl)))
            fov = math.degrees(2 * math.atan(36.0 / (2 * flv)))
            axis = "x"
        t = math.tan(math.radians(float(fov)) / 2)
        aspect = w / h
        if axis == "smaller":
            axis = "x" if w < h else "y"
        elif axis == "larger":
            axis = "x" if w > h else "y"
        if axis == "x":
            ty = t / aspect
        elif axis == "y":
            ty = t
        else:  # diagonal
            ty = t / math.sqrt(aspect * aspect + 1)
        vfov = math.degrees(2 * math.atan(ty))
        col = m[:3, :3]
        scale = np.linalg.norm(col, axis=0)
        pos = m[:3, 3]
        fwd = col[:, 2] / scale[2]
        up = col[:, 1] / scale[1]
        det = np.linalg.det(col)
        if det < 0:
            warn("the camera transform mirrors: isorad's image is the mirror of Mitsuba's")
        return {"position": pos, "look_at": pos + fwd, "up": up, "vfov_deg": vfov,
                "width": w, "height": h}

    # output -------------------------------------------------------------
    def write(self, outdir: str, name: str, src: str):
        os.makedirs(outdir, exist_ok=True)
        objp = os.path.join(outdir, f"{name}.obj")
        mtlp = os.path.join(outdir, f"{name}.mtl")
        with open(mtlp, "w") as f:
            f.write(f"# converted from {src} by bench/convert_mitsuba_scene.py\n")
            for mn, m in self.materials.items():
                f.write(f"\n# {m['note']}" + ("; clamped from " + " ".join(f"{x:.4g}" for x in m["kd_raw"])
                                               if m["clamped"] else "") + "\n")
                f.write(f"newmtl {mn}\nKd {m['kd'][0]:.6g} {m['kd'][1]:.6g} {m['kd'][2]:.6g}\n")
                if m["ke"] is not None:
                    f.write(f"Ke {m['ke'][0]:.6g} {m['ke'][1]:.6g} {m['ke'][2]:.6g}\n")
        with open(objp, "w") as f:
            f.write(f"# converted from {src} by bench/convert_mitsuba_scene.py\n")
            f.write(f"mtllib {name}.mtl\n")
            base = 1
            for oname, mat, v, tris, _ in self.objects:
                f.write(f"o {oname}\nusemtl {mat}\n")
                np.savetxt(f, v, fmt="v %.9g %.9g %.9g")
                np.savetxt(f, tris + base, fmt="f %d %d %d")
                base += len(v)
        cam = self.camera()
        tomlp = os.path.join(outdir, f"{name}.toml")
        with open(tomlp, "w") as f:
            f.write(f"# {name}: converted from {src}\n# by bench/convert_mitsuba_scene.py"
                    " (geometry as exported, not repaired).\n")
            if self.other_emitters:
                f.write("# Not converted (no isorad equivalent here): emitters "
                        + ", ".join(self.other_emitters) + "\n")
            if self.missing:
                f.write("# Left out (files missing): " + ", ".join(self.missing) + "\n")
            if self.dropped:
                f.write("# Left out (transmissive BSDF, --drop-transmissive): "
                        + ", ".join(self.dropped) + "\n")
            f.write(f'obj = "{name}.obj"\nmerge_coplanar = true\n')
            if cam is not None:
                fmt = lambda a: "[" + ", ".join(f"{x:.6g}" for x in a) + "]"
                f.write("\n[camera]\n")
                f.write(f"position = {fmt(cam['position'])}\n")
                f.write(f"look_at = {fmt(cam['look_at'])}\n")
                f.write(f"up = {fmt(cam['up'])}\n")
                f.write(f"vfov_deg = {cam['vfov_deg']:.6g}\n")
                f.write(f"width = {cam['width']}\nheight = {cam['height']}\n")
        return objp, mtlp, tomlp


def resolve_path(base: str, fn: str) -> str:
    """base/fn, or a file whose name differs only in case (scenes written
    on Windows name files as they like; Mitsuba there finds them)."""
    path = os.path.join(base, fn.replace("\\", "/"))
    if os.path.exists(path):
        return path
    d, name = os.path.split(path)
    if os.path.isdir(d):
        for cand in os.listdir(d):
            if cand.lower() == name.lower():
                warn(f"{fn}: using {cand} (file name differs in case)")
                return os.path.join(d, cand)
    return path


def read_mtl(path: str) -> dict:
    out, cur = {}, None
    if not os.path.exists(path):
        return out
    for line in open(path, errors="replace"):
        p = line.split()
        if not p:
            continue
        if p[0] == "newmtl":
            cur = line.strip()[6:].strip()
        elif p[0] == "Kd" and cur is not None:
            out[cur] = [float(x) for x in p[1:4]]
    return out


# ---------------------------------------------------------------- statistics


def planes_spanned(v: np.ndarray, tris: np.ndarray, diag: float) -> int:
    p0, p1, p2 = v[tris[:, 0]], v[tris[:, 1]], v[tris[:, 2]]
    n = np.cross(p1 - p0, p2 - p0)
    ln = np.linalg.norm(n, axis=1)
    ok = ln > 0
    if not ok.any():
        return 0
    n = n[ok] / ln[ok, None]
    d = np.einsum("ij,ij->i", n, p0[ok])
    # planes equal within 0.57 degrees and 1e-5 of the diagonal (isorad's merge tolerances)
    key = np.concatenate([np.round(n / 0.01), np.round(d / (1e-5 * diag))[:, None]], axis=1)
    return len(np.unique(key, axis=0))


def statistics(objects, diag: float) -> dict:
    allv = np.concatenate([o[2] for o in objects])
    offs = np.cumsum([0] + [len(o[2]) for o in objects])
    allt = np.concatenate([o[3] + offs[i] for i, o in enumerate(objects)])
    owner = np.concatenate([np.full(len(o[3]), i) for i, o in enumerate(objects)])
    # weld exactly equal positions (float32, as the file holds them)
    p32 = allv.astype(np.float32)
    _, wid = np.unique(p32, axis=0, return_inverse=True)
    wid = wid.ravel()
    wt = wid[allt]
    p0, p1, p2 = allv[allt[:, 0]], allv[allt[:, 1]], allv[allt[:, 2]]
    area2 = np.linalg.norm(np.cross(p1 - p0, p2 - p0), axis=1)
    idx_degen = (wt[:, 0] == wt[:, 1]) | (wt[:, 1] == wt[:, 2]) | (wt[:, 0] == wt[:, 2])
    zero_area = (~idx_degen) & (area2 <= 1e-12 * diag * diag)
    # duplicates: the same three welded vertices
    good = ~idx_degen
    srt = np.sort(wt[good], axis=1)
    _, inv, cnt = np.unique(srt, axis=0, return_inverse=True, return_counts=True)
    inv = inv.ravel()
    dup_faces = int(np.sum(cnt[cnt > 1]))
    # same / opposite winding among duplicates: canonical rotation of the cycle
    g = wt[good]
    rot = np.argmin(g, axis=1)
    can = np.stack([g[np.arange(len(g)), rot], g[np.arange(len(g)), (rot + 1) % 3],
                    g[np.arange(len(g)), (rot + 2) % 3]], axis=1)
    _, cnt2 = np.unique(can, axis=0, return_counts=True)
    dup_same = int(np.sum(cnt2[cnt2 > 1]))
    # directed edges used more than once: neighbours wound inconsistently
    # (or more than two faces on an edge)
    e = np.concatenate([g[:, [0, 1]], g[:, [1, 2]], g[:, [2, 0]]])
    eo = np.concatenate([owner[good]] * 3)
    _, einv, ecnt = np.unique(e, axis=0, return_inverse=True, return_counts=True)
    einv = einv.ravel()
    bad_edges = int(np.sum(ecnt > 1))
    bad_objs = sorted({objects[i][0] for i in np.unique(eo[ecnt[einv] > 1])})
    und = np.sort(e, axis=1)
    _, ucnt = np.unique(und, axis=0, return_counts=True)
    return {
        "triangles": int(len(allt)),
        "vertices_written": int(len(allv)),
        "distinct_positions": int(wid.max() + 1),
        "degenerate_repeated_vertex": int(idx_degen.sum()),
        "degenerate_zero_area": int(zero_area.sum()),
        "duplicated_faces": dup_faces,
        "duplicated_faces_same_winding": dup_same,
        "edges_used_twice_in_same_direction": bad_edges,
        "objects_with_inconsistent_winding": len(bad_objs),
        "objects_with_inconsistent_winding_list": bad_objs[:50],
        "edges_with_more_than_two_faces": int(np.sum(ucnt > 2)),
        "boundary_edges": int(np.sum(ucnt == 1)),
    }


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0],
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("scene", help="Mitsuba scene.xml")
    ap.add_argument("outdir")
    ap.add_argument("--name", help="output file stem (default: the scene's folder name)")
    ap.add_argument("-D", action="append", default=[], metavar="NAME=VALUE",
                    help="override a <default> parameter")
    ap.add_argument("--skip-missing", action="store_true",
                    help="leave out shapes whose mesh file is missing (else: error)")
    ap.add_argument("--max-albedo", type=float, default=0.95,
                    help="clamp every Kd channel to this (isorad needs < 1)")
    ap.add_argument("--segments", type=int, default=48,
                    help="segments of tessellated disks, spheres and cylinders")
    ap.add_argument("--drop-transmissive", action="store_true",
                    help="leave out shapes whose BSDF transmits (glass) instead of making them opaque")
    ap.add_argument("--report", help="write the statistics as JSON here")
    args = ap.parse_args()

    overrides = dict(d.split("=", 1) for d in args.D)
    root = load_xml(args.scene, overrides)
    scene = Scene(root, os.path.dirname(os.path.abspath(args.scene)))
    name = args.name or os.path.basename(os.path.dirname(os.path.abspath(args.scene))) or "scene"
    conv = Converter(scene, args)
    conv.run()
    if not conv.objects:
        sys.exit("error: no shapes converted")
    src = os.path.abspath(args.scene)
    objp, mtlp, tomlp = conv.write(args.outdir, name, src)

    allv = np.concatenate([o[2] for o in conv.objects])
    lo, hi = allv.min(axis=0), allv.max(axis=0)
    diag = float(np.linalg.norm(hi - lo))
    stats = statistics(conv.objects, diag)
    emitters = []
    for oname, mat, v, tris, emits in conv.objects:
        if emits:
            emitters.append({"object": oname, "material": mat, "triangles": int(len(tris)),
                             "planes": planes_spanned(v, tris, diag),
                             "radiance": conv.materials[mat]["ke"]})
    stats["emitting_triangles"] = int(sum(e["triangles"] for e in emitters))
    stats["emitters"] = emitters
    stats["bounds"] = [lo.tolist(), hi.tolist()]
    stats["objects"] = len(conv.objects)
    stats["materials"] = len(conv.materials)
    stats["clamped_materials"] = [m for m, d in conv.materials.items() if d["clamped"]]
    stats["missing_files"] = conv.missing
    stats["unconverted_emitters"] = conv.other_emitters
    stats["dropped_transmissive"] = conv.dropped
    stats["warnings"] = WARNINGS

    print(f"wrote {objp}\n      {mtlp}\n      {tomlp}")
    print(f"{stats['objects']} objects, {stats['materials']} materials, "
          f"{stats['triangles']:,} triangles, bounds {np.round(lo, 3).tolist()} .. {np.round(hi, 3).tolist()}")
    print(f"emitting triangles: {stats['emitting_triangles']:,}")
    for e in emitters:
        print(f"  {e['object']}: {e['triangles']} triangles in {e['planes']} plane(s), "
              f"radiance {e['radiance']}")
    for k in ("degenerate_repeated_vertex", "degenerate_zero_area", "duplicated_faces",
              "duplicated_faces_same_winding", "edges_used_twice_in_same_direction",
              "objects_with_inconsistent_winding", "edges_with_more_than_two_faces",
              "boundary_edges"):
        print(f"{k}: {stats[k]:,}")
    if stats["clamped_materials"]:
        print("Kd clamped to", args.max_albedo, "in:", ", ".join(stats["clamped_materials"]), flush=True)
    if args.report:
        with open(args.report, "w") as f:
            json.dump(stats, f, indent=1)


if __name__ == "__main__":
    main()
