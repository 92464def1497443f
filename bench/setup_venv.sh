#!/usr/bin/env bash
# Create bench/.venv with Mitsuba 3 and numpy for isorad's reference renders.
# As root, also installs libLLVM 19 (Debian package libllvm19) so that the
# fast `llvm_ad_rgb` variant works; otherwise mitsuba_render.py falls back to
# `scalar_rgb` (same images, several times slower).
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
python="${PYTHON:-python3}"

if [ "$(id -u)" = 0 ] && command -v apt-get >/dev/null 2>&1; then
    if ! ldconfig -p 2>/dev/null | grep -q 'libLLVM.so.19\|libLLVM-19'; then
        echo "setup_venv: installing libllvm19 for Mitsuba's llvm variant" >&2
        if ! { apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq libllvm19; }; then
            echo "setup_venv: libllvm19 not installed; the scalar_rgb variant will be used" >&2
        fi
    fi
else
    echo "setup_venv: not root; skipping libllvm19 (scalar_rgb will be used unless LLVM >= 16 is present)" >&2
fi

if [ ! -x "$here/.venv/bin/python" ]; then
    "$python" -m venv "$here/.venv"
fi
"$here/.venv/bin/python" -m pip install -q --upgrade pip
"$here/.venv/bin/python" -m pip install -q -r "$here/requirements.txt"
"$here/.venv/bin/python" - <<'PY'
import mitsuba as mi
print("mitsuba", mi.__version__, "variants:", ", ".join(mi.variants()))
PY
