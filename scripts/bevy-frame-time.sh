#!/usr/bin/env bash
# Bevy's frame time with gnomon's cascades over Bevy's own: the example headless at 1280x720
# on the demo's street view, the two runs interleaved ROUNDS times (default 3), each timing
# FRAMES frames (default 60) after three to warm up. Prints each run and the ratio of the
# medians. Timing on a shared CPU is noisy: compare the ratio of one run, not absolute times.
# Further arguments go to both runs (e.g. --shadow-map 512); GNOMON_ARGS to gnomon's only
# (e.g. "--technique cascades --stable").
set -euo pipefail
cd "$(dirname "$0")/.."
rounds=${ROUNDS:-3}
frames=${FRAMES:-60}
view=${VIEW:-street}
cargo build -q --release -p bevy_gnomon --example scene
out=$(mktemp -d)
for _ in $(seq "$rounds"); do
    for shadows in bevy gnomon; do
        extra=("$@")
        if [ "$shadows" = gnomon ] && [ -n "${GNOMON_ARGS:-}" ]; then
            read -r -a more <<<"$GNOMON_ARGS"
            extra+=("${more[@]}")
        fi
        ms=$(target/release/examples/scene --view "$view" --size 1280x720 --shadows "$shadows" \
            --frames "$frames" --screenshot "$out/$shadows.png" "${extra[@]}" 2>&1 |
            sed -n 's/.*: \([0-9.]*\) ms a frame/\1/p')
        echo "$shadows $ms"
        echo "$ms" >>"$out/$shadows"
    done
done
median() { sort -n "$1" | awk '{a[NR]=$1} END {print a[int((NR+1)/2)]}'; }
b=$(median "$out/bevy")
g=$(median "$out/gnomon")
echo "median ms a frame: bevy $b, gnomon $g, ratio $(awk -v g="$g" -v b="$b" 'BEGIN {printf "%.3f", g / b}')"
rm -rf "$out"
