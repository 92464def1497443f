#!/usr/bin/env python3
"""isorad against a path tracer (Mitsuba 3): time to equal error, and a walkthrough.

    pathtracer_comparison.py SCENE.toml [SCENE.toml ...] --json out.json
        [--width 256] [--walkthrough target/release/examples/walkthrough]
        [--views 60] [--views-measured 4] [--max-spp 2048] [--reference-spp 8192]
        [--runs 3] [--work-dir DIR] [--variant auto|llvm_ad_rgb|scalar_rgb]

For every scene file that exists (a missing one is skipped with a note):

1. **Reference.** ``bench/references/<stem>_<width>.exr``, a converged Mitsuba
   render of the scene's camera at ``--width`` (height from the camera's
   aspect); rendered at ``--reference-spp`` in passes of 512 when missing, then
   cached (the file is committed, keep it small).
2. **isorad.** ``examples/walkthrough.rs`` meshes, solves and renders the
   scene's camera (median of ``--runs`` runs), then renders ``--views``
   cameras along a walkthrough path from the same solution. Load, mesh, solve
   and the first render make the time to the converged image. It also runs at
   looser tolerances (0.3, 0.1, 0.03) for isorad's own error-against-time curve.
3. **Error.** Relative RMS error against the reference,
   sqrt(mean((a - b)^2)) / sqrt(mean(b^2)) over RGB channels and all pixels
   except directly seen emitters and their 8 neighbours (the light's outline,
   where pixels mix the light with a wall: there, 1 % of coverage outweighs
   the whole lit surface). Emitter pixels are those of ``compare_images.py``
   (reference luminance > 10 x its 90th percentile); background pixels are 0
   in both and add nothing. The same without pixels at strong edges of the
   reference (3 x 3 max/min > 1.3) is recorded too.
   Both renderers are measured against the same reference, whose own noise
   (about 0.9 % for the Cornell box at 8192 spp) is in every figure.
4. **Path tracer.** Mitsuba renders the same camera at 1, 2, 4, ... spp (passes
   of at most 256 spp), each timed (``mi.render`` only: the scene is loaded and
   the kernels compiled by a 1-spp warm-up render first), until its error is
   below 0.8 x isorad's or ``--max-spp`` is reached. The time and spp at which
   it reaches isorad's error are interpolated log-log between the two
   bracketing renders.
5. **Walkthrough.** Mitsuba renders ``--views-measured`` of the 60 cameras,
   evenly spread along the path, at that spp (rounded up); 60 views cost 60 x
   their mean time. isorad's 60 views are all rendered and timed.

Mitsuba's variant (``llvm_ad_rgb`` when libLLVM >= 16 is present, else
``scalar_rgb``) and thread count (Dr.Jit's pool: all cores) go in the JSON.
The JSON feeds section (c) of BENCHMARKS.md (``examples/bench_report.rs``).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)

import compare_images  # noqa: E402
import mitsuba_render  # noqa: E402

LOOSE_TOLERANCES = [0.3, 0.1, 0.03]


def drjit_threads() -> int:
    """Threads of Dr.Jit's pool (the llvm variant's parallelism)."""
    try:
        import drjit
        return int(drjit.thread_count())
    except (ImportError, AttributeError):
        return 1


def git_commit() -> str:
    """The isorad commit measured (with a mark if the tree has changes)."""
    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], capture_output=True,
                              text=True, check=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, check=True).stdout.strip()
        return head + (" (modified)" if dirty else "")
    except (OSError, subprocess.CalledProcessError):
        return "unknown"


def log(msg: str) -> None:
    print(f"pathtracer_comparison: {msg}", file=sys.stderr, flush=True)


# --------------------------------------------------------------------------- error


def dilate(mask: np.ndarray) -> np.ndarray:
    """The mask grown by one pixel (8-neighbourhood)."""
    h, w = mask.shape
    p = np.pad(mask, 1)
    out = np.zeros_like(mask)
    for dy in range(3):
        for dx in range(3):
            out |= p[dy:dy + h, dx:dx + w]
    return out


def errors(img: np.ndarray, ref: np.ndarray) -> dict:
    """Relative RMS error of `img` against `ref` over RGB: without emitter
    pixels and their 8 neighbours (the light's outline, where a pixel mixes
    the light and a wall and a 1 % difference in coverage outweighs every lit
    surface), and without those and pixels at strong edges of the reference
    (emitter and edge masks as in compare_images.py)."""
    lb = ref @ compare_images.LUM
    emitter = lb > 10.0 * float(np.percentile(lb, 90))
    level = float(lb.max()) if emitter.all() else float(lb[~emitter].max())
    edges = compare_images.edge_mask(lb, 1.3, 1e-3 * level)
    outline = dilate(emitter)
    la = img @ compare_images.LUM
    lit = ~outline & (lb > 0.01 * float(lb.mean()))
    return {
        "rel_rms": compare_images.rel_rms(img, ref, ~outline),
        "rel_rms_no_edges": compare_images.rel_rms(img, ref, ~outline & ~edges),
        # Mean per-pixel relative error of luminance over pixels above 1 % of
        # the reference's mean: what the tone-mapped image shows.
        "per_pixel": float((np.abs(la[lit] - lb[lit]) / lb[lit]).mean()),
    }


def interpolate_loglog(points: list[tuple[float, float]], target: float) -> float | None:
    """x at which y (falling with x) reaches `target`, interpolated linearly in
    log x and log y between the first bracketing pair; None if never reached."""
    for (x0, y0), (x1, y1) in zip(points, points[1:]):
        if y0 >= target >= y1 and y0 > y1:
            f = (math.log(y0) - math.log(target)) / (math.log(y0) - math.log(y1))
            return math.exp(math.log(x0) + f * (math.log(x1) - math.log(x0)))
    if points and points[0][1] <= target:
        return points[0][0]
    return None


# --------------------------------------------------------------------------- Mitsuba


class Mitsuba:
    """One Mitsuba scene per scene file; renders any of isorad's cameras."""

    def __init__(self, mi, scene_path: str, camera: mitsuba_render.Camera, tmp: str):
        self.mi = mi
        obj, _ = mitsuba_render.read_scene_toml(scene_path)
        meshes, mats = mitsuba_render.parse_obj(obj)
        self.scene = mitsuba_render.build_scene(mi, meshes, mats, camera, tmp, False, -1)

    def sensor(self, cam: dict):
        mi = self.mi
        to_world = mi.ScalarTransform4f().look_at(
            origin=cam["position"], target=cam["look_at"], up=cam["up"])
        return mi.load_dict({
            "type": "perspective", "to_world": to_world, "fov": cam["vfov_deg"],
            "fov_axis": "y", "near_clip": 1e-3, "far_clip": 1e7,
            "sampler": {"type": "independent", "sample_count": 1},
            "film": {"type": "hdrfilm", "width": cam["width"], "height": cam["height"],
                     "pixel_format": "rgb", "component_format": "float32",
                     "rfilter": {"type": "box"}},
        })

    def render(self, sensor, spp: int, seed: int, pass_spp: int = 256) -> tuple[np.ndarray, float]:
        """Image at `spp` (passes of at most `pass_spp`) and its seconds."""
        t0 = time.perf_counter()
        acc, done, k = None, 0, 0
        while done < spp:
            n = min(pass_spp, spp - done)
            img = np.array(self.mi.render(self.scene, sensor=sensor, spp=n, seed=seed + k),
                           dtype=np.float64)
            acc = img * n if acc is None else acc + img * n
            done, k = done + n, k + 1
        return acc / done, time.perf_counter() - t0


def write_exr(mi, path: str, img: np.ndarray) -> None:
    fd, tmp = tempfile.mkstemp(suffix=".exr", dir=os.path.dirname(os.path.abspath(path)))
    os.close(fd)
    mi.Bitmap(img.astype(np.float32), pixel_format=mi.Bitmap.PixelFormat.RGB).write(tmp)
    os.chmod(tmp, 0o644)
    os.replace(tmp, path)


# --------------------------------------------------------------------------- isorad


def run_walkthrough(binary: str, scene: str, width: int, views: int, out_dir: str,
                    tolerance: float | None = None) -> dict:
    os.makedirs(out_dir, exist_ok=True)
    record = os.path.join(out_dir, "walkthrough.json")
    cmd = [binary, scene, "--width", str(width), "--views", str(views),
           "--out-dir", out_dir, "--json", record]
    if tolerance is not None:
        cmd += ["--tolerance", str(tolerance)]
    subprocess.run(cmd, check=True)
    with open(record) as f:
        return json.load(f)


def median_record(records: list[dict]) -> dict:
    """The run with the median time to the converged image, with every timing
    replaced by its median over the runs."""
    keys = ["load_seconds", "mesh_seconds", "solve_seconds", "render_seconds",
            "converged_seconds", "views_seconds"]
    out = dict(sorted(records, key=lambda r: r["converged_seconds"])[len(records) // 2])
    for k in keys:
        out[k] = statistics.median(r[k] for r in records)
    out["runs"] = len(records)
    return out


# --------------------------------------------------------------------------- one scene


def compare_scene(args, mi, variant: str, scene: str) -> dict:
    stem = os.path.splitext(os.path.basename(scene))[0]
    work = os.path.join(args.work_dir, stem)
    os.makedirs(work, exist_ok=True)
    _, cam = mitsuba_render.read_scene_toml(scene)
    if cam is None:
        return {"scene": scene, "skipped": "no [camera] table"}
    cam.height = max(1, round(args.width * cam.height / cam.width))
    cam.width = args.width
    result: dict = {"scene": scene, "width": cam.width, "height": cam.height,
                    "commit": git_commit()}

    with tempfile.TemporaryDirectory(prefix="isorad_mi_") as tmp:
        mitsuba = Mitsuba(mi, scene, cam, tmp)
    main_cam = {"position": cam.position, "look_at": cam.look_at, "up": cam.up,
                "vfov_deg": cam.vfov_deg, "width": cam.width, "height": cam.height}
    main_sensor = mitsuba.sensor(main_cam)

    # 1. The converged reference, cached.
    ref_path = os.path.join(HERE, "references", f"{stem}_{args.width}.exr")
    if not os.path.exists(ref_path):
        log(f"{stem}: rendering the reference, {args.reference_spp} spp (cached afterwards)")
        img, seconds = mitsuba.render(main_sensor, args.reference_spp, seed=1_000_000,
                                      pass_spp=512)
        write_exr(mi, ref_path, img)
        log(f"{stem}: reference in {seconds:.0f} s -> {ref_path}")
    ref = compare_images.read_exr(ref_path)
    result["reference"] = os.path.relpath(ref_path, os.path.dirname(HERE))

    # 2. isorad: converged image and walkthrough (median of runs), looser tolerances.
    runs = [run_walkthrough(args.walkthrough, scene, args.width, args.views,
                            os.path.join(work, "isorad")) for _ in range(args.runs)]
    isorad = median_record(runs)
    isorad.pop("cameras_unused", None)
    isorad_img = compare_images.read_exr(os.path.join(work, "isorad", "view_main.exr"))
    isorad.update(errors(isorad_img, ref))
    curve = []
    for tol in LOOSE_TOLERANCES:
        r = run_walkthrough(args.walkthrough, scene, args.width, 0,
                            os.path.join(work, f"isorad_tol{tol}"), tol)
        img = compare_images.read_exr(os.path.join(work, f"isorad_tol{tol}", "view_main.exr"))
        curve.append({"tolerance": tol, "seconds": r["converged_seconds"], **errors(img, ref)})
    curve.append({"tolerance": "default", "seconds": isorad["converged_seconds"],
                  "rel_rms": isorad["rel_rms"], "rel_rms_no_edges": isorad["rel_rms_no_edges"],
                  "per_pixel": isorad["per_pixel"]})
    isorad["curve"] = curve
    cameras = isorad.pop("cameras")
    result["isorad"] = isorad
    log(f"{stem}: isorad {isorad['converged_seconds']:.2f} s to its image, "
        f"error {isorad['rel_rms']:.4f} RMS, {isorad['per_pixel']:.4f} per pixel; {args.views} views in {isorad['views_seconds']:.2f} s")

    # 3. Mitsuba at 1, 2, 4, ... spp until below isorad's error.
    mitsuba.render(main_sensor, 1, seed=7)  # load and compile
    sweep = []
    spp = 1
    while spp <= args.max_spp:
        img, seconds = mitsuba.render(main_sensor, spp, seed=100 * spp)
        e = errors(img, ref)
        sweep.append({"spp": spp, "seconds": seconds, **e})
        log(f"{stem}: mitsuba {spp} spp {seconds:.2f} s, error {e['rel_rms']:.4f} RMS, "
            f"{e['per_pixel']:.4f} per pixel")
        if all(e[k] < 0.8 * isorad[k] for k in ("rel_rms", "rel_rms_no_edges", "per_pixel")):
            break
        spp *= 2
    result["mitsuba"] = {"variant": variant, "version": mi.__version__,
                         "threads": drjit_threads(), "sweep": sweep}
    for key in ("rel_rms", "rel_rms_no_edges", "per_pixel"):
        target = isorad[key]
        t = interpolate_loglog([(s["seconds"], s[key]) for s in sweep], target)
        n = interpolate_loglog([(s["spp"], s[key]) for s in sweep], target)
        result["mitsuba"][f"seconds_at_isorad_{key}"] = t
        result["mitsuba"][f"spp_at_isorad_{key}"] = n
    t_eq = result["mitsuba"]["seconds_at_isorad_rel_rms"]
    spp_eq = result["mitsuba"]["spp_at_isorad_rel_rms"]
    if t_eq is not None:
        result["time_ratio"] = t_eq / isorad["converged_seconds"]
        log(f"{stem}: mitsuba reaches {isorad['rel_rms']:.4f} at {spp_eq:.0f} spp, {t_eq:.2f} s "
            f"({result['time_ratio']:.1f} x isorad)")

    # 4. The walkthrough at the spp of equal error.
    if spp_eq is not None and cameras:
        spp_walk = max(1, math.ceil(spp_eq))
        count = min(args.views_measured, len(cameras))
        picks = sorted({round(i * (len(cameras) - 1) / max(count - 1, 1)) for i in range(count)})
        times = []
        for i in picks:
            _, seconds = mitsuba.render(mitsuba.sensor(cameras[i]), spp_walk, seed=10_000 + i)
            times.append(seconds)
        mean = statistics.fmean(times)
        result["walkthrough"] = {
            "views": len(cameras), "spp": spp_walk, "measured_views": picks,
            "mitsuba_view_seconds": times,
            "mitsuba_seconds": mean * len(cameras),
            "isorad_seconds": isorad["views_seconds"],
            "isorad_with_solve_seconds": isorad["views_seconds"] + isorad["load_seconds"]
            + isorad["mesh_seconds"] + isorad["solve_seconds"],
        }
        w = result["walkthrough"]
        w["ratio"] = w["mitsuba_seconds"] / w["isorad_seconds"]
        w["ratio_with_solve"] = w["mitsuba_seconds"] / w["isorad_with_solve_seconds"]
        log(f"{stem}: walkthrough mitsuba {w['mitsuba_seconds']:.1f} s (at {spp_walk} spp) vs isorad "
            f"{w['isorad_seconds']:.2f} s ({w['ratio']:.0f} x; with the solve {w['ratio_with_solve']:.0f} x)")
    return result


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("scenes", nargs="+", help="isorad scene files (.toml with a [camera])")
    ap.add_argument("--json", required=True, help="write the results here")
    ap.add_argument("--width", type=int, default=256)
    ap.add_argument("--walkthrough", default="target/release/examples/walkthrough")
    ap.add_argument("--views", type=int, default=60)
    ap.add_argument("--views-measured", type=int, default=4)
    ap.add_argument("--max-spp", type=int, default=2048)
    ap.add_argument("--reference-spp", type=int, default=8192)
    ap.add_argument("--runs", type=int, default=3)
    ap.add_argument("--work-dir", default="target/bench/pathtracer")
    ap.add_argument("--variant", default="auto", choices=["auto", "llvm_ad_rgb", "scalar_rgb"])
    args = ap.parse_args()

    import mitsuba as mi
    variant = args.variant
    if variant == "auto":
        variant = "llvm_ad_rgb" if ("llvm_ad_rgb" in mi.variants()
                                    and mitsuba_render.llvm_variant_works(sys.executable)) else "scalar_rgb"
    mi.set_variant(variant)
    log(f"mitsuba {mi.__version__}, variant {variant}")

    results = []
    for scene in args.scenes:
        if not os.path.exists(scene):
            log(f"{scene}: not found, skipped")
            results.append({"scene": scene, "skipped": "scene file not found"})
            continue
        results.append(compare_scene(args, mi, variant, scene))
    out = {"variant": variant, "mitsuba": mi.__version__, "threads": drjit_threads(),
           "metric": "relative RMS over RGB, emitter pixels and their 8 neighbours excluded", "scenes": results}
    os.makedirs(os.path.dirname(os.path.abspath(args.json)), exist_ok=True)
    with open(args.json, "w") as f:
        json.dump(out, f, indent=2)
    log(f"wrote {args.json}")


if __name__ == "__main__":
    main()
