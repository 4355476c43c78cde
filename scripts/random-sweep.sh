#!/usr/bin/env bash
# A sweep of random scenes against the exact shadows: scenes FROM to TO of
# scripts/random-scenes.py, each compared (every technique, four views, 320x180, 1024 maps) by
# the release `gnomon compare`, then a table of each technique's wrong pixels per kind of light
# (mean and worst over the views) and the views where a technique is wrong on more than
# THRESHOLD percent of the judged pixels (default 1).
#
#   scripts/random-sweep.sh FROM TO OUT [THRESHOLD]
#
# GENERATOR names another script that writes DIR/scene.toml from a seed (SEED DIR), e.g.
# GENERATOR=scripts/random-suite-views.py for random views of the scene suite's models.
#
# About 12 s a scene on this 2-core machine with lavapipe.
set -euo pipefail
cd "$(dirname "$0")/.."
if [ $# -lt 3 ] || ! [[ "$1" =~ ^[0-9]+$ && "$2" =~ ^[0-9]+$ ]]; then
    echo "usage: random-sweep.sh FROM TO OUT [THRESHOLD] (FROM and TO whole numbers)" >&2
    exit 2
fi
from=$1 to=$2 out=$3 threshold=${4:-1}
cargo build -q --release -p gnomon-cli
mkdir -p "$out"
for seed in $(seq "$from" "$to"); do
    python3 "${GENERATOR:-scripts/random-scenes.py}" "$seed" "$out/s$seed"
    if ! target/release/gnomon compare --scene-file "$out/s$seed/scene.toml" --techniques all \
        --size 320x180 --shadow-map 1024 --out "$out/s$seed/out" >"$out/s$seed/log" 2>&1; then
        echo "random-sweep.sh: scene $seed failed (see $out/s$seed/log)" >&2
        exit 1
    fi
    echo "scene $seed compared" >&2
done
python3 - "$out" "$threshold" <<'PY'
import collections, glob, json, sys
out, threshold = sys.argv[1], float(sys.argv[2])
wrong = collections.defaultdict(list)
flagged = []
for path in sorted(glob.glob(f"{out}/s*/out/report.json")):
    scene = path.split("/")[-3]
    for view in json.load(open(path))["views"]:
        light = next(iter(view["light"]))
        for row in view["techniques"]:
            if "skipped" in row:
                continue
            wrong[(row["technique"], light)].append(row["wrong_percent"])
            if row["wrong_percent"] > threshold:
                flagged.append((scene, view["view"], light, row["technique"],
                                row["wrong_percent"], row["compared_pixels"]))
print("| technique | light | views | mean wrong | worst |\n| --- | --- | ---: | ---: | ---: |")
for (technique, light), xs in sorted(wrong.items()):
    print(f"| {technique} | {light} | {len(xs)} | {sum(xs) / len(xs):.3f}% | {max(xs):.3f}% |")
print(f"\nviews wrong on more than {threshold}% of the judged pixels:")
for scene, view, light, technique, w, pixels in flagged:
    print(f"  {scene} {view} ({light}): {technique} {w:.3f}% of {pixels}")
PY
