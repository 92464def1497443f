#!/usr/bin/env bash
# Regenerates BENCHMARKS.md and docs/bench/*.png from the repository root:
#   (a) ray throughput, (b) scaling, (d) meshing: examples/bench_report.rs;
#   (c) isorad against Mitsuba 3: bench/pathtracer_comparison.py (time to equal
#       error, 60-view walkthrough) on the scenes in $PATHTRACER_SCENES; a scene
#       whose file is missing is skipped with a note.
#
#   bash bench/run_benchmarks.sh [--sections abcd] [--max-vertices N]
#
# --sections measures only the given sections and keeps the others from the
# existing BENCHMARKS.md. All of it takes about an hour on two cores, most of
# it Mitsuba (c) and the million-vertex solve (b). The criterion benches
# (kernels, shadow rays, rasterizer, Cornell solve) are separate: `cargo bench`.
set -euo pipefail
cd "$(dirname "$0")/.."
scenes="${PATHTRACER_SCENES:-scenes/cornell/cornell.toml scenes/office/office.toml}"
sections=abcd
args=("$@")
for ((i = 0; i < ${#args[@]}; i++)); do
    if [ "${args[i]}" = --sections ]; then sections="${args[i + 1]:-abcd}"; fi
done

cargo build --release --example bench_report --example walkthrough
if [[ "$sections" == *c* ]]; then
    if [ ! -x bench/.venv/bin/python ]; then
        bash bench/setup_venv.sh
    fi
    # shellcheck disable=SC2086 # a list of scene files
    bench/.venv/bin/python bench/pathtracer_comparison.py $scenes \
        --json target/bench/pathtracer.json --walkthrough target/release/examples/walkthrough
fi
./target/release/examples/bench_report "$@" --pathtracer target/bench/pathtracer.json
