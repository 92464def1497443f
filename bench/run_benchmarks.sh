#!/usr/bin/env bash
# Regenerates BENCHMARKS.md and docs/bench/*.png: builds isorad in release and
# runs examples/bench_report.rs from the repository root. A few minutes on two
# cores. The criterion benches (kernels, shadow rays, rasterizer, Cornell
# solve) are separate: `cargo bench`.
set -euo pipefail
cd "$(dirname "$0")/.."
cargo build --release --example bench_report
./target/release/examples/bench_report "$@"
