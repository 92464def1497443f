#!/usr/bin/env python3
"""Compare two linear-radiance EXR images: A (e.g. isorad) against B (the reference).

    compare_images.py A.exr B.exr [--mask-edges] [--diff out.png]
                      [--png-a a.png --png-b b.png] [--json stats.json]

Reports
* mean radiance per channel of A and B, and the ratio A/B; then the same
  without emitter pixels (a light seen directly is ~100x brighter than any
  wall and would otherwise dominate every mean and max: pixels brighter than
  10 x B's 90th-percentile luminance count as emitters);
* relative RMS error  sqrt(mean((a-b)^2)) / sqrt(mean(b^2))  over all
  channels (error energy over signal energy): over all pixels, without
  emitter pixels, and without emitter and edge pixels;
* the per-pixel relative error of luminance |a-b| / max(b, eps): its mean
  (what a viewer of the tone-mapped image sees on average: RMS hides dark
  regions and shadows), median, 90th percentile and signed median (bias), over non-emitter pixels whose
  reference luminance is above eps = 1 % of B's maximum over non-emitter
  pixels (--threshold-of max: of B's plain maximum);
* the same statistics excluding pixels near strong edges of the reference:
  a pixel is an edge pixel when the max/min luminance ratio over its 3x3
  neighbourhood in B exceeds --edge-ratio (1.3). Shadow boundaries and
  geometric edges differ by discretisation (mesh vs pixel), so these are
  reported apart.

The --diff PNG shows the signed relative difference (a-b)/max(b, eps) of
luminance: red = A brighter, blue = A darker, white = equal, saturating at
+-(--diff-scale) (default 10 %); grey: below the threshold; dark grey:
emitter; with --mask-edges, edge pixels are light grey. --diff-blur K
box-averages both images over K x K pixels first, to see biases through
the reference's Monte Carlo noise. --png-a/--png-b write
both images tone-mapped with the same exposure (B's 99th-percentile surface
luminance to white, sRGB) for viewing side by side.

EXRs are read with Mitsuba's Bitmap (from bench/.venv), or with the OpenEXR
module if Mitsuba is not installed.
"""

from __future__ import annotations

import argparse
import json
import struct
import sys
import zlib

import numpy as np

LUM = np.array([0.2126, 0.7152, 0.0722])


def read_exr(path: str) -> np.ndarray:
    """Return an H x W x 3 float64 array of linear RGB."""
    try:
        import mitsuba as mi
        if mi.variant() is None:
            mi.set_variant("scalar_rgb")
        bmp = mi.Bitmap(path)
        bmp = bmp.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, srgb_gamma=False)
        return np.array(bmp, dtype=np.float64)
    except ImportError:
        import OpenEXR  # type: ignore
        import Imath  # type: ignore
        f = OpenEXR.InputFile(path)
        dw = f.header()["dataWindow"]
        w, h = dw.max.x - dw.min.x + 1, dw.max.y - dw.min.y + 1
        pt = Imath.PixelType(Imath.PixelType.FLOAT)
        chans = [np.frombuffer(f.channel(c, pt), dtype=np.float32).reshape(h, w) for c in "RGB"]
        return np.stack(chans, axis=-1).astype(np.float64)


def write_png(path: str, rgb8: np.ndarray) -> None:
    """Minimal RGB8 PNG writer (no dependencies)."""
    h, w, _ = rgb8.shape
    raw = b"".join(b"\x00" + rgb8[y].astype(np.uint8).tobytes() for y in range(h))

    def chunk(tag: bytes, data: bytes) -> bytes:
        return (struct.pack(">I", len(data)) + tag + data
                + struct.pack(">I", zlib.crc32(tag + data) & 0xFFFFFFFF))

    png = (b"\x89PNG\r\n\x1a\n"
           + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 2, 0, 0, 0))
           + chunk(b"IDAT", zlib.compress(raw, 9))
           + chunk(b"IEND", b""))
    with open(path, "wb") as f:
        f.write(png)


def tonemap(img: np.ndarray, white: float) -> np.ndarray:
    x = np.clip(img / white, 0.0, 1.0)
    srgb = np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)
    return np.round(srgb * 255.0)


def edge_mask(lum: np.ndarray, ratio: float, floor: float) -> np.ndarray:
    """True where the 3x3 neighbourhood's max/min luminance exceeds `ratio`."""
    p = np.pad(lum, 1, mode="edge")
    h, w = lum.shape
    stack = np.stack([p[dy:dy + h, dx:dx + w] for dy in range(3) for dx in range(3)])
    mx, mn = stack.max(axis=0), stack.min(axis=0)
    return mx > ratio * np.maximum(mn, floor)


def box_blur(x: np.ndarray, k: int) -> np.ndarray:
    """Mean over a k x k window (edge-replicated)."""
    r = k // 2
    p = np.pad(x, ((r, k - 1 - r), (r, k - 1 - r)), mode="edge")
    c = np.cumsum(np.cumsum(np.pad(p, ((1, 0), (1, 0))), axis=0), axis=1)
    h, w = x.shape
    return (c[k:k + h, k:k + w] - c[:h, k:k + w] - c[k:k + h, :w] + c[:h, :w]) / (k * k)


def rel_stats(la: np.ndarray, lb: np.ndarray, sel: np.ndarray, eps: float) -> dict:
    if not sel.any():
        return {"pixels": 0}
    signed = (la[sel] - lb[sel]) / np.maximum(lb[sel], eps)
    rel = np.abs(signed)
    return {
        "pixels": int(sel.sum()),
        "mean": float(rel.mean()),
        "median": float(np.median(rel)),
        "p90": float(np.percentile(rel, 90)),
        "signed_median": float(np.median(signed)),
        "mean_signed": float(signed.mean()),
    }


def rel_rms(a: np.ndarray, b: np.ndarray, sel: np.ndarray | None = None) -> float:
    if sel is not None:
        a, b = a[sel], b[sel]
    return float(np.sqrt(np.mean((a - b) ** 2)) / np.sqrt(np.mean(b ** 2)))


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("a", help="image under test (EXR, linear radiance)")
    ap.add_argument("b", help="reference image (EXR, linear radiance)")
    ap.add_argument("--mask-edges", action="store_true",
                    help="grey out edge pixels in the --diff image")
    ap.add_argument("--edge-ratio", type=float, default=1.3)
    ap.add_argument("--threshold", type=float, default=0.01,
                    help="relative errors over pixels with B above this fraction of max luminance")
    ap.add_argument("--threshold-of", choices=["surfaces", "max"], default="surfaces",
                    help="threshold relative to B's max over non-emitter pixels (default) or its max")
    ap.add_argument("--emitter-factor", type=float, default=10.0,
                    help="pixels brighter than this times B's 90th percentile are emitters")
    ap.add_argument("--diff", help="write a signed relative-difference PNG")
    ap.add_argument("--diff-scale", type=float, default=0.10,
                    help="relative difference shown at full colour")
    ap.add_argument("--diff-blur", type=int, default=1, metavar="K",
                    help="box-average both images over K x K pixels before the --diff map")
    ap.add_argument("--diff-zoom", type=int, default=1, metavar="Z",
                    help="enlarge the --diff map Z times (nearest neighbour)")
    ap.add_argument("--png-a", help="write A tone-mapped with B's exposure")
    ap.add_argument("--png-b", help="write B tone-mapped")
    ap.add_argument("--json", help="write the statistics as JSON")
    args = ap.parse_args()

    a, b = read_exr(args.a), read_exr(args.b)
    if a.shape != b.shape:
        print(f"compare_images: sizes differ: {args.a} is {a.shape[1]}x{a.shape[0]}, "
              f"{args.b} is {b.shape[1]}x{b.shape[0]}", file=sys.stderr)
        sys.exit(2)
    for name, img in ((args.a, a), (args.b, b)):
        bad = ~np.isfinite(img)
        if bad.any():
            print(f"compare_images: {name}: {int(bad.sum())} non-finite values (set to 0)",
                  file=sys.stderr)
            img[bad] = 0.0

    la, lb = a @ LUM, b @ LUM
    # Directly visible emitters are orders of magnitude brighter than any lit
    # surface: they would dominate "max" and every mean. Pixels brighter than
    # --emitter-factor x the 90th percentile of B count as emitter pixels.
    emitter = lb > args.emitter_factor * float(np.percentile(lb, 90))
    lmax = float(lb.max())
    level = lmax if args.threshold_of == "max" or emitter.all() else float(lb[~emitter].max())
    eps = args.threshold * level
    lit = (lb > eps) & ~emitter
    edges = edge_mask(lb, args.edge_ratio, 1e-3 * level)
    smooth = lit & ~edges

    mean_a, mean_b = a.reshape(-1, 3).mean(0), b.reshape(-1, 3).mean(0)
    surf_a, surf_b = a[~emitter].mean(0), b[~emitter].mean(0)
    stats = {
        "a": args.a, "b": args.b,
        "size": [a.shape[1], a.shape[0]],
        "mean_a": mean_a.tolist(), "mean_b": mean_b.tolist(),
        "mean_ratio": (mean_a / mean_b).tolist(),
        "mean_lum_ratio": float(la.mean() / lb.mean()),
        "emitter_fraction": float(emitter.mean()),
        "surf_mean_a": surf_a.tolist(), "surf_mean_b": surf_b.tolist(),
        "surf_mean_ratio": (surf_a / surf_b).tolist(),
        "rel_rms": rel_rms(a, b),
        "rel_rms_no_emitters": rel_rms(a, b, ~emitter),
        "rel_rms_no_emitters_no_edges": rel_rms(a, b, ~emitter & ~edges),
        "edge_fraction": float(edges.mean()),
        "threshold": eps,
        "rel_all": rel_stats(la, lb, lit, eps),
        "rel_no_edges": rel_stats(la, lb, smooth, eps),
    }

    def row(name, v):
        return f"{name:10s} " + "  ".join(f"{x:10.5f}" for x in v)

    print(f"A = {args.a}\nB = {args.b}\nsize {a.shape[1]}x{a.shape[0]}")
    print(f"{'':10s} {'R':>10s}  {'G':>10s}  {'B':>10s}")
    print(row("mean A", mean_a))
    print(row("mean B", mean_b))
    print(row("A/B", mean_a / mean_b))
    print(f"mean luminance ratio A/B: {stats['mean_lum_ratio']:.5f}")
    print(f"emitter pixels (B > {args.emitter_factor:g} x p90): "
          f"{100 * stats['emitter_fraction']:.2f} %; without them:")
    print(row("  mean A", surf_a))
    print(row("  mean B", surf_b))
    print(row("  A/B", surf_a / surf_b))
    print(f"edge pixels (3x3 max/min > {args.edge_ratio}): {100 * stats['edge_fraction']:.1f} %")
    print(f"relative RMS, all pixels: {stats['rel_rms']:.5f}; emitters excluded: "
          f"{stats['rel_rms_no_emitters']:.5f}; emitters and edges excluded: "
          f"{stats['rel_rms_no_emitters_no_edges']:.5f}")
    print(f"per-pixel |A-B|/B of luminance over lit surface pixels "
          f"(B > {args.threshold:g} x {'max' if args.threshold_of == 'max' else 'max without emitters'}"
          f" = {eps:.4g}):")
    for key, label in (("rel_all", "all"), ("rel_no_edges", "edges excluded")):
        s = stats[key]
        if s["pixels"] == 0:
            print(f"  {label}: no pixels")
            continue
        print(f"  {label:15s} {s['pixels']:6d} px  mean {s['mean']:.5f}  median {s['median']:.5f}"
              f"  p90 {s['p90']:.5f}"
              f"  signed median {s['signed_median']:+.5f}")

    if args.diff:
        da, db = la, lb
        if args.diff_blur > 1:
            # Average both over K x K pixels first: shows biases under Monte Carlo noise.
            da, db = box_blur(la, args.diff_blur), box_blur(lb, args.diff_blur)
        rel = (da - db) / np.maximum(db, eps)
        t = np.clip(rel / args.diff_scale, -1.0, 1.0)
        rgb = np.ones(a.shape)
        pos, neg = t > 0, t < 0
        rgb[pos, 1] -= t[pos]
        rgb[pos, 2] -= t[pos]           # white -> red
        rgb[neg, 0] += t[neg]
        rgb[neg, 1] += t[neg]           # white -> blue
        rgb[~lit] = 0.5
        rgb[emitter] = 0.25
        if args.mask_edges:
            rgb[edges & lit] = 0.75
        if args.diff_zoom > 1:
            rgb = np.repeat(np.repeat(rgb, args.diff_zoom, axis=0), args.diff_zoom, axis=1)
        write_png(args.diff, np.round(rgb * 255))
        print(f"wrote {args.diff} (red: A brighter, blue: A darker, full colour at "
              f"±{100 * args.diff_scale:g} %, grey: below threshold"
              + (", light grey: edge" if args.mask_edges else "") + ")")
    white = float(np.percentile(lb[~emitter], 99.0)) if (~emitter).any() else 1.0
    if args.png_a:
        write_png(args.png_a, tonemap(a, white))
    if args.png_b:
        write_png(args.png_b, tonemap(b, white))
    if args.json:
        with open(args.json, "w") as f:
            json.dump(stats, f, indent=2)


if __name__ == "__main__":
    main()
