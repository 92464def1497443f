#!/usr/bin/env python3
"""isorad against the stored Radiance daylight references.

For each scene of scenes/daylight/ that bench/references/daylight/ holds a
reference for, runs `isorad probe --in-space` on the same points at default
settings, then prints the whole-process time and, against Radiance: the
mean illuminance (or DF) ratio, the median's, the worst point, and the mean
|error| over the points above 0.5 % DF. These are the figures in README.md
and docs/accuracy.md.

    cargo build --release && python3 bench/daylight_compare.py [--isorad PATH]
"""
import argparse
import csv
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
CASES = [
    ("roof_opening", "overcast", "roof_opening.toml"),
    ("roof_opening", "clear", "roof_opening_clear.toml"),
    ("facade_opening", "overcast", "facade_opening.toml"),
    ("facade_opening", "clear", "facade_opening_clear.toml"),
    ("glazed_facade", "overcast", "glazed_facade.toml"),
    ("glazed_facade", "clear", "glazed_facade_clear.toml"),
    ("daylit_office", "overcast", "daylit_office.toml"),
]


def lux(path, column="illuminance_lux"):
    with open(path, newline="") as f:
        return [float(row[column]) for row in csv.DictReader(f)]


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--isorad", default=str(ROOT / "target/release/isorad"))
    args = parser.parse_args()
    scenes = ROOT / "scenes/daylight"
    references = ROOT / "bench/references/daylight"
    print(f"{'scene':<16} {'sky':<9} {'mean':>8} {'median':>8} {'worst':>7} {'mean|e|':>8} {'time':>6}")
    with tempfile.TemporaryDirectory() as tmp:
        for name, sky, toml in CASES:
            reference = references / f"{name}_{sky}.csv"
            if not reference.exists():
                continue
            points = Path(tmp) / "points.csv"
            lines = (scenes / f"{name}_points.csv").read_text().splitlines()
            points.write_text("\n".join(line for line in lines if not line.startswith("x")) + "\n")
            out = Path(tmp) / "isorad.csv"
            started = time.monotonic()
            with open(out, "w") as f:
                subprocess.run([args.isorad, "probe", str(scenes / toml), "--points", str(points),
                                "--in-space", "-q"], stdout=f, check=True)
            seconds = time.monotonic() - started
            got, want = lux(out), lux(reference)
            if len(got) != len(want):
                sys.exit(f"{name}: {len(got)} points read against {len(want)} in the reference")
            # Points above 0.5 % DF of the 10,000 lx sky.
            errors = [g / w - 1.0 for g, w in zip(got, want) if w > 50.0]
            mean = sum(got) / sum(want) - 1.0
            median = statistics.median(got) / statistics.median(want) - 1.0
            worst = max(abs(e) for e in errors)
            typical = statistics.mean(abs(e) for e in errors)
            print(f"{name:<16} {sky:<9} {100 * mean:>+7.2f}% {100 * median:>+7.2f}% "
                  f"{100 * worst:>6.2f}% {100 * typical:>7.2f}% {seconds:>5.1f}s")


if __name__ == "__main__":
    main()
