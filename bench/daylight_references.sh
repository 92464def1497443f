#!/bin/sh
# Recomputes the Radiance daylight references in bench/references/daylight/
# (see its README) with bench/daylight_radiance.py. Needs Radiance's oconv,
# rtrace and gensky: RADIANCE_PREFIX=/path/to/radiance (bin/, lib/) or on
# PATH. Run from anywhere; SCENES=... limits the scenes (default: all).
set -eu
cd "$(dirname "$0")/.."
out=bench/references/daylight
mkdir -p "$out"
roof="1.5,3,1.5;2.5,3,1.5;1.5,3,2.5"
facade="1,0.9,4;3,0.9,4;1,2.1,4"
scenes=${SCENES:-"roof_opening facade_opening glazed_facade daylit_office"}

run() {  # run NAME SKY-SUFFIX [options...]
    name=$1 sky=$2
    shift 2
    toml=scenes/daylight/$name.toml
    [ "$sky" = clear ] && toml=scenes/daylight/${name}_clear.toml
    python3 bench/daylight_radiance.py "$toml" \
        --points "scenes/daylight/${name}_points.csv" \
        --out "$out/${name}_$sky.csv" --json "$out/${name}_$sky.json" "$@" > /dev/null
    echo "$out/${name}_$sky.json"
}

for scene in $scenes; do
    case $scene in
    roof_opening)
        for sky in overcast clear; do run roof_opening $sky --ad 262144 --opening "$roof"; done ;;
    facade_opening)
        for sky in overcast clear; do run facade_opening $sky --ad 262144 --opening "$facade"; done ;;
    glazed_facade)
        for sky in overcast clear; do
            run glazed_facade $sky --ad 262144 --opening "$facade" --opening-glass 0.8
        done ;;
    daylit_office)
        run daylit_office overcast --ad 131072 ;;
    esac
done
