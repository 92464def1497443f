#!/usr/bin/env python3
"""Render an isorad scene file with Mitsuba 3, as an independent reference.

    mitsuba_render.py SCENE.toml --spp N --out ref.exr
                      [--width W --height H] [--variant auto|llvm_ad_rgb|scalar_rgb]

The scene is read the way isorad reads it (shared/DESIGN.md, "Conventions"):

* ``obj`` in the TOML is a path relative to the TOML file. The TOML must have
  a ``[camera]`` table: isorad's default framing (and bare OBJ paths) are not
  reproduced here.
* MTL ``Kd`` is the diffuse reflectance -> Mitsuba ``diffuse`` BSDF.
  MTL ``Ke`` is the emitted radiance -> Mitsuba ``area`` emitter, one-sided
  (emits on the front face, counter-clockwise side, as isorad's lights).
  The MTL is parsed here: Mitsuba's OBJ loader ignores materials.
* Every surface is one-sided: Mitsuba's diffuse BSDF is black from the back,
  exactly like isorad's polygons.
* The OBJ is split into one triangle mesh per material (Mitsuba binds one
  BSDF per shape). Polygons are fan-triangulated here from their first vertex,
  so quads and n-gons (convex, as isorad requires planar convex-or-simple
  polygons) are handled without relying on Mitsuba's OBJ loader. Face
  normals are used (flat shading), as for isorad's planar polygons.
* Camera: pinhole look-at, ``vfov_deg`` is the full vertical field of view
  (``fov_axis='y'``), row 0 at the top, right = forward x up.
  Mitsuba's ``look_at`` builds camera axes (left = up x forward, up, forward)
  and its film's +x runs along -left = forward x up, which is isorad's
  "right". So no mirroring is needed: checked by rendering the Cornell box,
  whose red wall (x ~ 550) appears on the LEFT in both renderers
  (see ``--check-handedness``).
* The image is linear radiance (hdrfilm, pixel_format rgb, box filter of one
  pixel), written as a float32 OpenEXR.

The path integrator runs with max_depth = -1 (unbounded, Russian roulette
from depth 5) and the ``independent`` sampler (``ldsampler`` was seen biased).
Samples are taken in passes of at most ``--pass-spp`` with distinct seeds and
averaged, which bounds memory for the llvm variant.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import tempfile
import time
import tomllib
from dataclasses import dataclass, field

import numpy as np


# --------------------------------------------------------------------------- scene files


@dataclass
class Camera:
    position: tuple[float, float, float]
    look_at: tuple[float, float, float]
    up: tuple[float, float, float]
    vfov_deg: float
    width: int
    height: int


@dataclass
class Material:
    name: str
    kd: tuple[float, float, float] = (0.0, 0.0, 0.0)
    ke: tuple[float, float, float] = (0.0, 0.0, 0.0)

    @property
    def emits(self) -> bool:
        return any(c > 0.0 for c in self.ke)


@dataclass
class ObjMesh:
    """Triangles of one material, with their own vertex list."""

    material: str
    vertices: list[tuple[float, float, float]] = field(default_factory=list)
    triangles: list[tuple[int, int, int]] = field(default_factory=list)
    polygons: int = 0


def fail(msg: str) -> "None":
    print(f"mitsuba_render: {msg}", file=sys.stderr)
    sys.exit(2)


def read_scene_toml(path: str) -> tuple[str, Camera | None]:
    try:
        with open(path, "rb") as f:
            doc = tomllib.load(f)
    except (OSError, tomllib.TOMLDecodeError) as e:
        fail(f"{path}: {e}")
    if "obj" not in doc:
        fail(f"{path}: missing key `obj`")
    obj = os.path.join(os.path.dirname(os.path.abspath(path)), doc["obj"])
    cam = None
    if "camera" in doc:
        c = doc["camera"]
        try:
            cam = Camera(
                position=tuple(float(x) for x in c["position"]),
                look_at=tuple(float(x) for x in c["look_at"]),
                up=tuple(float(x) for x in c.get("up", [0.0, 1.0, 0.0])),
                vfov_deg=float(c["vfov_deg"]),
                width=int(c.get("width", 512)),
                height=int(c.get("height", 512)),
            )
        except KeyError as e:
            fail(f"{path}: [camera] is missing {e}")
    return obj, cam


def parse_mtl(path: str) -> dict[str, Material]:
    mats: dict[str, Material] = {}
    cur: Material | None = None
    if not os.path.exists(path):
        fail(f"{path}: MTL file not found")
    with open(path, encoding="utf-8") as f:
        for lineno, raw in enumerate(f, 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            key, *rest = line.split()
            if key == "newmtl":
                cur = Material(" ".join(rest))
                mats[cur.name] = cur
            elif key in ("Kd", "Ke"):
                if cur is None:
                    fail(f"{path}:{lineno}: {key} before any newmtl")
                vals = [float(x) for x in rest]
                if len(vals) == 1:
                    vals = vals * 3
                if len(vals) != 3:
                    fail(f"{path}:{lineno}: {key} needs 1 or 3 numbers")
                setattr(cur, key.lower(), tuple(vals))
    return mats


def parse_obj(path: str) -> tuple[list[ObjMesh], dict[str, Material]]:
    """Read vertices and faces; group faces by material; fan-triangulate."""
    verts: list[tuple[float, float, float]] = []
    meshes: dict[str, ObjMesh] = {}
    remap: dict[str, dict[int, int]] = {}
    mats: dict[str, Material] = {}
    cur = "(none)"
    base = os.path.dirname(os.path.abspath(path))
    if not os.path.exists(path):
        fail(f"{path}: OBJ file not found")
    with open(path, encoding="utf-8") as f:
        for lineno, raw in enumerate(f, 1):
            line = raw.split("#", 1)[0].strip()
            if not line:
                continue
            key, *rest = line.split()
            if key == "v":
                verts.append(tuple(float(x) for x in rest[:3]))
            elif key == "mtllib":
                for name in rest:
                    mats.update(parse_mtl(os.path.join(base, name)))
            elif key == "usemtl":
                cur = " ".join(rest)
            elif key == "f":
                idx = []
                for tok in rest:
                    i = int(tok.split("/")[0])
                    i = i - 1 if i > 0 else len(verts) + i
                    if not 0 <= i < len(verts):
                        fail(f"{path}:{lineno}: vertex index {tok} out of range")
                    idx.append(i)
                if len(idx) < 3:
                    fail(f"{path}:{lineno}: face with fewer than 3 vertices")
                m = meshes.setdefault(cur, ObjMesh(cur))
                rm = remap.setdefault(cur, {})
                local = []
                for i in idx:
                    if i not in rm:
                        rm[i] = len(m.vertices)
                        m.vertices.append(verts[i])
                    local.append(rm[i])
                for k in range(1, len(local) - 1):
                    m.triangles.append((local[0], local[k], local[k + 1]))
                m.polygons += 1
    for name in meshes:
        if name not in mats:
            fail(f"{path}: material `{name}` is not defined in its MTL")
    return list(meshes.values()), mats


def write_obj(path: str, mesh: ObjMesh) -> None:
    with open(path, "w", encoding="utf-8") as f:
        for v in mesh.vertices:
            f.write(f"v {v[0]!r} {v[1]!r} {v[2]!r}\n")
        for t in mesh.triangles:
            f.write(f"f {t[0] + 1} {t[1] + 1} {t[2] + 1}\n")


# --------------------------------------------------------------------------- Mitsuba


def llvm_variant_works(python: str) -> bool:
    """Probe llvm_ad_rgb in a child process: with libLLVM < 16 it aborts."""
    code = (
        "import mitsuba as mi\n"
        "mi.set_variant('llvm_ad_rgb')\n"
        "s = mi.load_dict({'type':'scene','integrator':{'type':'path'},"
        "'sensor':{'type':'perspective','film':{'type':'hdrfilm','width':4,'height':4}},"
        "'e':{'type':'constant'},'r':{'type':'rectangle'}})\n"
        "mi.render(s, spp=2)\n"
    )
    try:
        r = subprocess.run([python, "-c", code], capture_output=True, timeout=300)
    except (OSError, subprocess.TimeoutExpired):
        return False
    return r.returncode == 0


def build_scene(mi, meshes: list[ObjMesh], mats: dict[str, Material], cam: Camera,
                tmpdir: str, mirror: bool, max_depth: int):
    T = mi.ScalarTransform4f
    to_world = T().look_at(origin=cam.position, target=cam.look_at, up=cam.up)
    if mirror:
        to_world = to_world @ T().scale([-1.0, 1.0, 1.0])
    scene = {
        "type": "scene",
        "integrator": {"type": "path", "max_depth": max_depth},
        "sensor": {
            "type": "perspective",
            "to_world": to_world,
            "fov": cam.vfov_deg,
            "fov_axis": "y",
            "near_clip": 1e-3,
            "far_clip": 1e7,
            "sampler": {"type": "independent", "sample_count": 1},
            "film": {
                "type": "hdrfilm",
                "width": cam.width,
                "height": cam.height,
                "pixel_format": "rgb",
                "component_format": "float32",
                "rfilter": {"type": "box"},
            },
        },
    }
    for k, m in enumerate(meshes):
        mat = mats[m.material]
        fn = os.path.join(tmpdir, f"mesh{k}.obj")
        write_obj(fn, m)
        shape = {
            "type": "obj",
            "filename": fn,
            "face_normals": True,
            "bsdf": {"type": "diffuse",
                     "reflectance": {"type": "rgb", "value": list(mat.kd)}},
        }
        if mat.emits:
            shape["emitter"] = {"type": "area",
                                "radiance": {"type": "rgb", "value": list(mat.ke)}}
        scene[f"shape_{k}_{m.material}"] = shape
    return mi.load_dict(scene)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="isorad scene TOML")
    ap.add_argument("--spp", type=int, required=True, help="samples per pixel")
    ap.add_argument("--out", required=True, help="output linear EXR")
    ap.add_argument("--width", type=int)
    ap.add_argument("--height", type=int)
    ap.add_argument("--variant", default="auto",
                    choices=["auto", "llvm_ad_rgb", "scalar_rgb"])
    ap.add_argument("--pass-spp", type=int, default=256,
                    help="samples per pass (passes are averaged; bounds memory)")
    ap.add_argument("--seed", type=int, default=0, help="seed of the first pass")
    ap.add_argument("--max-depth", type=int, default=-1,
                    help="path length limit (-1: unbounded, Russian roulette)")
    ap.add_argument("--mirror", action="store_true",
                    help="mirror the image left-right (diagnostic only)")
    args = ap.parse_args()

    if args.scene.lower().endswith(".obj"):
        fail("give an isorad scene TOML with a [camera] table, not a bare OBJ")
    obj, cam = read_scene_toml(args.scene)
    if cam is None:
        fail(f"{args.scene}: needs a [camera] table (isorad's default framing is not reproduced)")
    if args.width:
        cam.width = args.width
    if args.height:
        cam.height = args.height
    if args.spp < 1:
        fail("--spp must be at least 1")

    import mitsuba as mi

    variant = args.variant
    if variant == "auto":
        variant = "llvm_ad_rgb" if ("llvm_ad_rgb" in mi.variants()
                                    and llvm_variant_works(sys.executable)) else "scalar_rgb"
    mi.set_variant(variant)

    meshes, mats = parse_obj(obj)
    for m in meshes:
        mat = mats[m.material]
        print(f"  {m.material:12s} {m.polygons:3d} polygons -> {len(m.triangles):3d} triangles"
              f"  Kd={mat.kd}" + (f"  Ke={mat.ke}" if mat.emits else ""))

    with tempfile.TemporaryDirectory(prefix="isorad_mi_") as tmp:
        scene = build_scene(mi, meshes, mats, cam, tmp, args.mirror, args.max_depth)

    t0 = time.perf_counter()
    acc = None
    done = 0
    npass = 0
    while done < args.spp:
        n = min(args.pass_spp, args.spp - done)
        img = np.array(mi.render(scene, spp=n, seed=args.seed + npass), dtype=np.float64)
        acc = img * n if acc is None else acc + img * n
        done += n
        npass += 1
        print(f"  pass {npass}: {done}/{args.spp} spp, {time.perf_counter() - t0:.1f} s",
              flush=True)
    elapsed = time.perf_counter() - t0
    img = (acc / done).astype(np.float32)

    bmp = mi.Bitmap(img, pixel_format=mi.Bitmap.PixelFormat.RGB)
    out_dir = os.path.dirname(os.path.abspath(args.out))
    os.makedirs(out_dir, exist_ok=True)
    fd, tmp_out = tempfile.mkstemp(suffix=".exr", dir=out_dir)
    os.close(fd)
    bmp.write(tmp_out)
    os.chmod(tmp_out, 0o644)
    os.replace(tmp_out, args.out)

    mean = img.reshape(-1, 3).mean(axis=0)
    print(f"mitsuba {mi.__version__} variant={variant} spp={done} "
          f"size={cam.width}x{cam.height} time={elapsed:.1f}s")
    print(f"mean radiance RGB = {mean[0]:.6g} {mean[1]:.6g} {mean[2]:.6g}")
    print(f"wrote {args.out}")


if __name__ == "__main__":
    main()
