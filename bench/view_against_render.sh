#!/bin/bash
# The viewer's picture against the renderer's: `isorad view SCENE` solved,
# its page screenshotted by headless Chromium at the scene camera's size
# (the panel fades while idle), and `isorad render SCENE`'s PNG of the same
# camera; prints the mean per-pixel luminance difference relative to the
# mean luminance, and the ratio of mean luminances. The figures in the
# guide's §17 come from this script.
#
# usage: bash bench/view_against_render.sh SCENE [PORT]
# needs: target/release/isorad, chromium, python3 with pillow and numpy
set -euo pipefail
scene=$1
port=${2:-8899}
bin=$(dirname "$0")/../target/release/isorad
work=$(mktemp -d)
"$bin" view "$scene" --port "$port" -q >/dev/null 2>"$work/view.err" &
viewer=$!
trap 'kill -INT $viewer 2>/dev/null || true; rm -rf "$work"' EXIT
for _ in $(seq 1 600); do
    state=$(curl -s "localhost:$port/state" || true)
    case "$state" in *'"done"'*|*'"failed"'*) break ;; esac
    sleep 1
done
"$bin" render "$scene" -o "$work/render.exr" --png "$work/render.png" -q
size=$(python3 -c "from PIL import Image; print('%d,%d' % Image.open('$work/render.png').size)")
chromium --headless --no-sandbox --use-angle=swiftshader --enable-unsafe-swiftshader \
    --disable-gpu-sandbox --disable-background-networking --disable-component-update \
    --disable-sync --no-first-run --user-data-dir="$work/profile" --hide-scrollbars \
    --screenshot="$work/page.png" --window-size="$size" --virtual-time-budget=20000 \
    "http://127.0.0.1:$port/" 2>/dev/null
python3 - "$work/page.png" "$work/render.png" "$scene" "$size" <<'PY'
import sys
import numpy as np
from PIL import Image

def luminance(path):
    c = np.asarray(Image.open(path).convert('RGB')).astype(float) / 255.0
    c = np.where(c <= 0.04045, c / 12.92, ((c + 0.055) / 1.055) ** 2.4)
    return 0.2126 * c[..., 0] + 0.7152 * c[..., 1] + 0.0722 * c[..., 2]

page, render = luminance(sys.argv[1]), luminance(sys.argv[2])
if page.sum() == 0:
    # Chromium's virtual time ran out before the page had its mesh.
    sys.exit('the screenshot is black: the page was not drawn in time; run again')
print('%s %s: mean |dY| / mean Y = %.2f %%, mean ratio %.4f' % (
    sys.argv[3], sys.argv[4],
    100 * np.abs(page - render).sum() / render.sum(), page.sum() / render.sum()))
PY
