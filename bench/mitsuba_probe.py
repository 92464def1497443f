#!/usr/bin/env python3
"""Irradiance at points of an isorad scene, by Mitsuba 3: the path tracer's
answer to ``isorad probe``.

    mitsuba_probe.py SCENE.toml --points points.csv --out ref.csv
                     [--direct-samples N] [--indirect-samples N] [--seed S]

The scene is converted exactly as ``mitsuba_render.py`` converts it (its MTL,
one-sided diffuse surfaces and area lights). Each line of the points file is
``x,y,z,nx,ny,nz`` (the normal of the surface the point lies on; lines
starting with ``#`` and blank lines are skipped). The irradiance
E(p) = ∫ L_i(p, ω) cos θ dω is estimated in two independent parts:

* direct: Mitsuba's emitter sampling from p (``sample_emitter_direction``
  with its shadow ray), weight × cos θ averaged over ``--direct-samples``;
* indirect: ``--indirect-samples`` cosine-weighted rays from p, each given to
  the ``path`` integrator (unbounded depth, Russian roulette); rays whose
  first hit is an emitter are left out, since the direct part counts them;
  E = π × the mean radiance.

The output CSV has one row per point: ``x,y,z,irradiance_r,g,b`` and the
standard error of each channel's estimate (``se_r,g,b``), the columns of
``isorad probe``'s irradiance, so the two can be compared line by line.
"""

from __future__ import annotations

import argparse
import os
import sys
import tempfile
import time

import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from mitsuba_render import (  # noqa: E402
    Camera,
    build_scene,
    fail,
    llvm_variant_works,
    parse_obj,
    read_scene_toml,
)


def read_points(path: str) -> np.ndarray:
    rows = []
    with open(path) as f:
        for number, line in enumerate(f, 1):
            line = line.strip()
            if not line or line.startswith("#"):
                continue
            try:
                values = [float(v) for v in line.split(",")]
            except ValueError:
                fail(f"{path}:{number}: not numbers: {line}")
            if len(values) != 6:
                fail(f"{path}:{number}: need x,y,z,nx,ny,nz")
            rows.append(values)
    if not rows:
        fail(f"{path}: no points")
    points = np.array(rows, dtype=np.float64)
    normals = points[:, 3:]
    lengths = np.linalg.norm(normals, axis=1)
    if np.any(lengths == 0):
        fail(f"{path}: a normal is zero")
    points[:, 3:] = normals / lengths[:, None]
    return points


def per_sample(colour) -> np.ndarray:
    """A wide Color3f as an (N, 3) array (drjit converts it channel-major)."""
    values = np.array(colour, dtype=np.float64)
    return values.T if values.ndim == 2 and values.shape[0] == 3 else values.reshape(-1, 3)


def estimate(mi, dr, scene, point, normal, direct_n, indirect_n, seed, offset):
    """(E, standard error) per channel at one point."""
    origin = [float(v) for v in point + normal * offset]
    normal = [float(v) for v in normal]
    # Direct light: emitter sampling with shadow rays.
    sampler = mi.load_dict({"type": "independent"})
    sampler.seed(seed, direct_n)
    it = dr.zeros(mi.Interaction3f)
    it.p = mi.Point3f(*origin)
    it.n = mi.Normal3f(*normal)
    it.t = 0.0
    ds, weight = scene.sample_emitter_direction(it, sampler.next_2d(), True)
    cos = dr.maximum(dr.dot(ds.d, mi.Vector3f(*normal)), 0.0)
    direct = per_sample(weight * cos)
    # Indirect light: cosine-weighted rays, first hits on emitters left out.
    sampler.seed(seed + 1, indirect_n)
    local = mi.warp.square_to_cosine_hemisphere(sampler.next_2d())
    frame = mi.Frame3f(mi.Vector3f(*normal))
    ray = mi.Ray3f(mi.Point3f(*origin), frame.to_world(local))
    si = scene.ray_intersect(ray)
    first_is_emitter = si.is_valid() & si.shape.is_emitter()
    radiance, _, _ = scene.integrator().sample(scene, sampler, ray)
    radiance = dr.select(first_is_emitter, mi.Color3f(0.0), radiance)
    indirect = np.pi * per_sample(radiance)
    mean = direct.mean(axis=0) + indirect.mean(axis=0)
    se = np.sqrt(direct.var(axis=0) / direct_n + indirect.var(axis=0) / indirect_n)
    return mean, se


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scene", help="isorad scene TOML")
    ap.add_argument("--points", required=True, help="CSV of x,y,z,nx,ny,nz")
    ap.add_argument("--out", required=True, help="output CSV")
    ap.add_argument("--direct-samples", type=int, default=1 << 16)
    ap.add_argument("--indirect-samples", type=int, default=1 << 18)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--variant", default="auto", choices=["auto", "llvm_ad_rgb", "scalar_rgb"])
    args = ap.parse_args()
    obj, cam = read_scene_toml(args.scene)
    points = read_points(args.points)

    import drjit as dr
    import mitsuba as mi

    variant = args.variant
    if variant == "auto":
        variant = "llvm_ad_rgb" if ("llvm_ad_rgb" in mi.variants()
                                    and llvm_variant_works(sys.executable)) else "scalar_rgb"
    if variant == "scalar_rgb":
        fail("mitsuba_probe.py needs the llvm_ad_rgb variant (vectorised rays); see setup_venv.sh")
    mi.set_variant(variant)
    meshes, mats = parse_obj(obj)
    if cam is None:
        cam = Camera(position=(0.0, 0.0, 1.0), look_at=(0.0, 0.0, 0.0), up=(0.0, 1.0, 0.0),
                     vfov_deg=45.0, width=8, height=8)
    with tempfile.TemporaryDirectory(prefix="isorad_mi_") as tmp:
        scene = build_scene(mi, meshes, mats, cam, tmp, False, -1)
    lo, hi = scene.bbox().min, scene.bbox().max
    diagonal = float(dr.norm(hi - lo))
    offset = 1e-5 * diagonal
    t0 = time.perf_counter()
    lines = ["x,y,z,irradiance_r,irradiance_g,irradiance_b,se_r,se_g,se_b"]
    for k, row in enumerate(points):
        mean, se = estimate(mi, dr, scene, row[:3], row[3:], args.direct_samples,
                            args.indirect_samples, args.seed + 2 * k, offset)
        lines.append(",".join(f"{v:.9g}" for v in [*row[:3], *mean, *se]))
        print(f"  point {k + 1}/{len(points)}: E = {mean[1]:.6g} ± {se[1]:.2g}, "
              f"{time.perf_counter() - t0:.1f} s", file=sys.stderr, flush=True)
    with open(args.out, "w") as f:
        f.write("\n".join(lines) + "\n")
    print(f"mitsuba {mi.__version__} variant={variant}: {len(points)} points, "
          f"{args.direct_samples} direct + {args.indirect_samples} indirect samples each, "
          f"{time.perf_counter() - t0:.1f} s; wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
